"""Per-world contact parameters in MJX: every world of a random batch delivers its target e_N (issue 36).

N worlds with random masses, stiffnesses, approach speeds, loads and target e_N (MuJoCo's soft
contact, impedance 0.9).  The JAX front door (``contactalpha.xla.contact_parameters``) gives each
world's direct-mode ``solref``; one MJX rollout of all worlds (``contactalpha.xla.mjx_drop``:
per-world ``geom_solref``, ``geom_solimp``, ``body_mass``, ``body_invweight0``, ``opt.timestep``)
at ``--per-period`` steps per undamped period, touchdown at phase 0; each world's e_N is read
from its run.  Prints the largest miss and writes a JSON summary (``--out``).

Usage:  python benchmarks/study_mjx_batch.py [--n 1024] [--per-period 4000]
        [--out docs/engines/mjx-batch.json]
Timings depend on the machine's load (printed).
"""

import argparse
import json
import os
import time

import numpy as np


def scenes(n, seed=0):
    rng = np.random.default_rng(seed)
    return {
        "mass": rng.uniform(0.1, 2.0, n),
        "stiffness": 10.0 ** rng.uniform(3.0, 5.0, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 30.0, n),
        "target": rng.uniform(0.1, 0.9, n),
    }


def main():
    import jax

    jax.config.update("jax_enable_x64", True)
    from contactalpha.xla import mjx_drop
    from contactalpha.xla.front import contact_parameters

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1024)
    p.add_argument("--per-period", type=int, default=4000)
    p.add_argument("--out", default=None)
    args = p.parse_args()
    s = scenes(args.n)
    t0 = time.perf_counter()
    out = contact_parameters(**s, law="mujoco_soft")
    params_s = time.perf_counter() - t0
    ok = np.asarray(out["ok"])
    mj = out["engines"]["mjx"]
    h = 2.0 * np.pi / np.sqrt(s["stiffness"] / s["mass"]) / args.per_period
    t0 = time.perf_counter()
    z, v = mjx_drop.rollout(
        mjx_drop.base_model(0.9), s["mass"][ok], s["accel"][ok], s["approach_speed"][ok],
        np.asarray(mj["solref"])[ok], np.asarray(mj["solimp"])[ok], h[ok], int(1.5 * args.per_period),
    )  # fmt: skip
    rollout_s = time.perf_counter() - t0
    got = mjx_drop.delivered_e_n(z, v, s["accel"][ok], h[ok], s["approach_speed"][ok])
    miss = np.abs(got - s["target"][ok])
    summary = {
        "worlds": args.n,
        "with_an_answer": int(ok.sum()),
        "steps_per_period": args.per_period,
        "max_miss_e_n": float(miss.max()),
        "median_miss_e_n": float(np.median(miss)),
        "within_1e-3": int((miss <= 1e-3).sum()),
        "worst_worlds": [
            {
                "zeta": float(np.asarray(out["damping"])[ok][i]),
                "xi": float(np.asarray(out["xi"])[ok][i]),
                "target": float(s["target"][ok][i]),
                "delivered": float(got[i]),
            }
            for i in np.argsort(-miss)[:5]
        ],  # fmt: skip
        "front_door_s_incl_compile": round(params_s, 1),
        "rollout_s_incl_compile": round(rollout_s, 1),
        "load_1min": os.getloadavg()[0],
        "cores": os.cpu_count(),
        "jax": jax.__version__,
    }
    print(json.dumps(summary, indent=1))
    if args.out:
        from pathlib import Path

        from contactalpha.io import write_atomic

        write_atomic(Path(args.out), lambda tmp: Path(tmp).write_text(json.dumps(summary, indent=1) + "\n"))


if __name__ == "__main__":
    main()
