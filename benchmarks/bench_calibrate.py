"""Benchmark of issue 28: calibrating a 20-bounce drop test (target <= 5 s on 2 cores).

Run: ``PYTHONPATH=src python benchmarks/bench_calibrate.py`` (``--quick``: one repeat).
Prints, measured side by side in this run on data/drops/hc_eps_times.csv (21 impacts):
- the first call in this process (numba kernels loaded or compiled, the table read) apart;
- ``ca.calibrate`` with its default laws (the three n = 3/2 ones) and profile-likelihood
  intervals, best of repeats (``--family``: also every registered law);
- the same without intervals, and one law (hc_eps) alone;
- baselines: one exact bounce prediction of the sequence (``predict_bounces``), and the classic
  rigid fit (least squares of a geometric series of flights, scipy) that ignores contacts.
"""

import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "data" / "drops" / "hc_eps_times.csv"


def best(fn, repeat):
    """Best wall time of ``repeat`` calls, s."""
    out = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        out = min(out, time.perf_counter() - t)
    return out


def rigid_fit(t, g=9.81):
    """Classic fit: touchdowns t0 + sum of rigid flights 2 v e^i / g; returns (e, v1)."""
    from scipy.optimize import least_squares

    def res(x):
        t0, v1, e = x
        flights = 2.0 * v1 * e ** np.arange(t.size - 1) / g
        return t - np.concatenate([[t0], t0 + np.cumsum(flights)])

    dt = np.diff(t)
    sol = least_squares(res, [t[0], 0.5 * g * dt[0], dt[1] / dt[0]])
    return sol.x[2], sol.x[1]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="one repeat")
    p.add_argument(
        "--family", action="store_true", help="also time hypotheses='all' (the contact-law family)"
    )
    args = p.parse_args(argv)
    repeat = 1 if args.quick else 3
    start = time.perf_counter()
    import contactalpha as ca
    from contactalpha.calibration.data import read_drop
    from contactalpha.scene.ball import Scene
    from contactalpha.scene.bounces import predict_bounces

    data = read_drop(DATA)
    t = time.perf_counter()
    ca.calibrate(data, mass=0.05, hypotheses=["hc_eps"], intervals=False)
    first = time.perf_counter() - t
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, {platform.python_version()}")
    print(f"import: {t - start:.2f} s; first calibrate call (kernels loaded/compiled): {first:.2f} s")
    scene = Scene(mass=0.05, stiffness=1e8, approach_speed=2.0, force=0.0, eps=0.8)
    rows = [
        ("calibrate, default laws, intervals", lambda: ca.calibrate(data, mass=0.05, radius=0.02)),
        ("calibrate, default laws, no intervals", lambda: ca.calibrate(data, mass=0.05, intervals=False)),
        ("calibrate, hc_eps, intervals", lambda: ca.calibrate(data, mass=0.05, hypotheses=["hc_eps"])),
        ("baseline: one predict_bounces", lambda: predict_bounces(scene, "exact")),
        ("baseline: rigid geometric fit", lambda: rigid_fit(data.values)),
    ]
    if args.family:
        ca.calibrate(data, mass=0.05, hypotheses=["kelvin_voigt_damping"], intervals=False)  # compile apart
        rows.insert(
            3,
            (
                "calibrate, hypotheses='all', intervals",
                lambda: ca.calibrate(data, mass=0.05, hypotheses="all"),
            ),
        )
    times = {name: best(fn, repeat) for name, fn in rows}
    base = times["baseline: one predict_bounces"]
    rigid = times["baseline: rigid geometric fit"]
    print(f"{'':36s} {'seconds':>9s} {'/ predict':>10s} {'/ rigid':>9s}")
    for name, sec in times.items():
        print(f"{name:36s} {sec:9.4f} {sec / base:10.0f} {sec / rigid:9.1f}")
    full = times["calibrate, default laws, intervals"]
    print(f"target: <= 5 s for the full calibration: {'met' if full <= 5.0 else 'NOT met'} ({full:.2f} s)")
    e, _ = rigid_fit(data.values)
    print(f"rigid fit's e = {e:.5f} (biased by the contacts; calibrate's hc_eps eps is the material's)")


if __name__ == "__main__":
    main()
