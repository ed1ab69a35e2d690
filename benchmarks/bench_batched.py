"""The batched front door against the scalar call, in one run (issue 27).

``contact_parameters`` with arrays of N scenes (mass, Hertz stiffness, speed, load, target e_N;
random, inside the table's domain) against N' scalar calls of the same scenes; both give every
engine's parameters of the law (OpenSim and Exudyn for Hunt-Crossley, n = 3/2).  Prints scenes/s
of each and their ratio; the first (compiling) batched call is timed apart.  Prints the largest relative
difference between the two on the scalar subset.

``--law`` picks another contact law (``contactalpha.laws``; e.g. ``mujoco_soft`` for MuJoCo,
``kelvin_voigt`` for PyBullet): its engines' parameters, the scalar calls solving exactly.

Usage:  python benchmarks/bench_batched.py [--law hunt_crossley] [--n 1000000] [--scalar 2000] [--repeat 3]
Timings depend on the machine's load (printed).
"""

import argparse
import os
import time

import numpy as np

from contactalpha.parameters.front_door import contact_parameters


def scenes(n, seed=0):
    rng = np.random.default_rng(seed)
    return {
        "mass": rng.uniform(0.1, 2.0, n),
        "stiffness": 10.0 ** rng.uniform(6.0, 9.0, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 50.0, n),
        "e_N": rng.uniform(0.05, 0.95, n),
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--scalar", type=int, default=2000)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--law", default=None, help="contact law (default: Hunt-Crossley, n = 3/2)")
    args = p.parse_args()
    s = scenes(args.n)
    law = {} if args.law is None else {"law": args.law}
    t0 = time.perf_counter()
    contact_parameters(**{k: v[:8] for k, v in s.items()}, **law)
    compile_s = time.perf_counter() - t0
    batched = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        out = contact_parameters(**s, **law)
        batched.append(time.perf_counter() - t0)
    scalar = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        one = [
            contact_parameters(**{k: float(v[i]) for k, v in s.items()}, **law) for i in range(args.scalar)
        ]
        scalar.append(time.perf_counter() - t0)
    if law:  # another law: the scalar call solves exactly; compare the dimensionless damping
        worst = max(abs(one[i].damping / out.damping[i] - 1.0) for i in range(args.scalar) if one[i].damping)
    else:  # the scalar xi may differ from the array path's in the last bit (engine.scaling's two paths)
        worst = max(
            abs(one[i].engines[e][name] / np.broadcast_to(out.engines[e][name], (args.n,))[i] - 1.0)
            for i in range(args.scalar)
            for e in one[i].engines
            for name in one[i].engines[e]
            if isinstance(one[i].engines[e][name], float) and one[i].engines[e][name] != 0.0
        )
    b_rate, s_rate = args.n / min(batched), args.scalar / min(scalar)
    print(f"machine load (1 min): {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print(f"first batched call (compile, 8 scenes): {compile_s:.2f} s")
    print(f"batched: {args.n} scenes in {min(batched):.3f} s = {b_rate:.3g} scenes/s (best of {args.repeat})")
    print(
        f"scalar:  {args.scalar} calls in {min(scalar):.3f} s = {s_rate:.3g} scenes/s (best of {args.repeat})"
    )
    print(f"ratio batched/scalar: {b_rate / s_rate:.1f}; max relative difference, scalar subset: {worst:.1e}")


if __name__ == "__main__":
    main()
