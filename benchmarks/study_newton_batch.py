"""Per-shape ke/kd in Newton: every world of a random batch delivers its target e_N (issue 36).

N worlds with random masses, stiffnesses, approach speeds, loads and target e_N (MuJoCo's soft
contact, impedance 0.9), run in Newton's MuJoCo solver on Warp's CPU backend (float32) with
per-shape force-space ``ke``, ``kd`` from the JAX front door's ``newton`` block
(``contactalpha.xla.newton_drop``).  Newton steps every world with one dt, so the stiffness per
unit mass spans a factor of two (1e4-2e4 s^-2) and the step gives the stiffest world
``--per-period`` steps per undamped period; touchdown at phase 0.  Prints the largest miss and
writes a JSON summary (``--out``).

Usage:  python benchmarks/study_newton_batch.py [--n 1024] [--per-period 4000]
        [--out docs/engines/newton-batch.json]
Timings depend on the machine's load (printed).
"""

import argparse
import json
import os
import time

import numpy as np


def scenes(n, seed=0):
    rng = np.random.default_rng(seed)
    mass = rng.uniform(0.1, 2.0, n)
    return {
        "mass": mass,
        "stiffness": mass * rng.uniform(1e4, 2e4, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 30.0, n),
        "target": rng.uniform(0.1, 0.9, n),
    }


def main():
    import jax

    jax.config.update("jax_enable_x64", True)
    import newton

    from contactalpha.adapters.stepped import measure_steps
    from contactalpha.xla import newton_drop
    from contactalpha.xla.front import contact_parameters

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1024)
    p.add_argument("--per-period", type=int, default=4000)
    p.add_argument("--out", default=None)
    args = p.parse_args()
    s = scenes(args.n)
    out = contact_parameters(**s, law="mujoco_soft")
    ok = np.asarray(out["ok"])
    block = out["engines"]["newton"]
    worlds = {key: value[ok] for key, value in s.items()}
    omega = np.sqrt(worlds["stiffness"] / worlds["mass"])
    h = 2.0 * np.pi / omega.max() / args.per_period
    nstep = int(0.8 * 2.0 * np.pi / omega.min() / h)
    t0 = time.perf_counter()
    ke, kd = np.asarray(block["shape_material_ke"])[ok], np.asarray(block["shape_material_kd"])[ok]
    z, w = newton_drop.rollout(worlds, ke, kd, 0.9, h, nstep)
    rollout_s = time.perf_counter() - t0
    v, a = worlds["approach_speed"], worlds["accel"]
    got = np.array(
        [measure_steps(z[i], w[i], a[i], h, v[i], newton_drop.FREE_RTOL_F32).e_n for i in range(len(v))]
    )
    miss = np.abs(got - worlds["target"])
    summary = {
        "worlds": args.n,
        "with_an_answer": int(ok.sum()),
        "steps_per_period_stiffest": args.per_period,
        "timestep_s": h,
        "steps": nstep,
        "max_miss_e_n": float(miss.max()),
        "median_miss_e_n": float(np.median(miss)),
        "within_1e-3": int((miss <= 1e-3).sum()),
        "worst_worlds": [
            {
                "zeta": float(np.asarray(out["damping"])[ok][i]),
                "xi": float(np.asarray(out["xi"])[ok][i]),
                "target": float(worlds["target"][i]),
                "delivered": float(got[i]),
            }
            for i in np.argsort(-miss)[:5]
        ],  # fmt: skip
        "rollout_s_incl_compile": round(rollout_s, 1),
        "load_1min": os.getloadavg()[0],
        "cores": os.cpu_count(),
        "newton": newton.__version__,
    }
    print(json.dumps(summary, indent=1))
    if args.out:
        from pathlib import Path

        from contactalpha.io import write_atomic

        write_atomic(Path(args.out), lambda tmp: Path(tmp).write_text(json.dumps(summary, indent=1) + "\n"))


if __name__ == "__main__":
    main()
