"""Delivered e_N against approach speed under gravity, in LAMMPS: LAMMPS's own mapping and the package's.

Run: PYTHONPATH=src nice python benchmarks/study_lammps_speed.py [OUT.png] [OUT.json]
(defaults docs/assets/dem_lammps_speed.png and results/dem/lammps_speed.json).

The issue's bead (d = 5 mm, E = 1e7 Pa, nu = 0.3, rho = 2500) falls on a wall of its material at
16 speeds from 0.01 to 1 m/s under gravity, at the DEM step t_contact / 50, four touchdown phases
each.  For targets 0.5 and 0.9 and LAMMPS's default (no ``limit_damping``):

- LAMMPS's own mapping: ``damping coeff_restitution`` given the target itself;
- the package's: the unfloored Tsuji law's beta at the speed's load factor (continuous);
- the package's, refined on LAMMPS's own drops at that step (``calibrate``).

The JSON holds every number, the LAMMPS version and the wall-clock seconds of the LAMMPS runs.
"""

import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from contactalpha.adapters import lammps_granular as lg
from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.stepped import ContactStepsWarning
from contactalpha.io import write_json_atomic

R, E, NU, RHO = 2.5e-3, 1e7, 0.3, 2500.0
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
K = 4.0 / 3.0 * (E / (2.0 * (1.0 - NU * NU))) * math.sqrt(R)
SPEEDS = np.geomspace(0.01, 1.0, 16)
TARGETS = (0.5, 0.9)


def main(png="docs/assets/dem_lammps_speed.png", out="results/dem/lammps_speed.json"):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a = lg.UNFLOORED
    style = lg.damping_style("coeff_restitution")
    rows, start = [], time.perf_counter()
    for target in TARGETS:
        for v in SPEEDS:
            scene = DropScene(MASS, K, float(v), 9.81, 0.0, R)
            own = a.delivered(scene, float(style.damp_of(target))).e_n
            sol, xi = a.law_damping(scene, target)
            ours = a.delivered(scene, float(sol.damping)).e_n
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ContactStepsWarning)
                _, ref, got = a.calibrate(scene, target, start=float(sol.damping))
            rows.append({"target": target, "speed": float(v), "xi": float(xi), "lammps_mapping": own,
                         "package": ours, "package_refined": got.e_n, "beta": float(sol.damping),
                         "beta_refined": float(ref.damping)})  # fmt: skip
            print(f"e = {target}  v = {v:.4g} m/s  xi = {xi:.3f}  LAMMPS {own:.4f}  package {ours:.4f}  "
                  f"refined {got.e_n:.4f}", flush=True)  # fmt: skip
    seconds = time.perf_counter() - start
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for target, color in zip(TARGETS, ("C0", "C1"), strict=True):
        sel = [r for r in rows if r["target"] == target]
        v = [r["speed"] for r in sel]
        ax.plot(v, [r["lammps_mapping"] for r in sel], "o-", color=color, mfc="none",
                label=f"LAMMPS coeff_restitution {target}")  # fmt: skip
        ax.plot(v, [r["package"] for r in sel], "s--", color=color, ms=4, label=f"package β, target {target}")
        ax.plot(v, [r["package_refined"] for r in sel], "^-", color=color, ms=4,
                label=f"package β refined at the step, {target}")  # fmt: skip
        ax.axhline(target, color=color, lw=0.6, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel("approach speed (m/s)")
    ax.set_ylabel("delivered e_N in LAMMPS")
    ax.set_title("5 mm bead on a wall under gravity, LAMMPS (no limit_damping)", fontsize=10)
    ax.legend(fontsize=7, loc="lower right")
    Path(png).parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    write_json_atomic(out, {"lammps_version": a.version(), "steps_per_contact": a.settings.steps_per_contact,
                            "phases": a.settings.phases, "seconds": seconds, "rows": rows})  # fmt: skip
    print(f"{len(rows)} scenes in {seconds:.1f} s of LAMMPS runs; wrote {png} and {out}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
