"""Benchmark of the impact engine and the alpha solver (issue: impact engine).

Run: ``python benchmarks/bench_core.py`` (add ``--quick`` for a smoke run).
Prints, measured side by side in this run:
- numba compile time (cold, cache cleared in a temporary NUMBA_CACHE_DIR) and warm load;
- one impact against scipy ``solve_ivp(method="DOP853")`` with events, same tolerances;
- a full 99 x 100 (eps, xi) grid of ``solve_alpha`` on all cores and on one;
- impacts integrated per grid point.
"""

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def cold_compile_seconds():
    """Import and first call in a fresh process with an empty numba cache."""
    code = (
        "import time; t=time.perf_counter(); import contactalpha as ca; "
        "ca.impact(0.5, 0.2); ca.solve_alpha(0.5, 0.2); print(time.perf_counter()-t)"
    )
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=tmp)
        cold = float(
            subprocess.run(
                [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
            ).stdout
        )
        warm = float(
            subprocess.run(
                [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
            ).stdout
        )
    return cold, warm


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="smaller repeat counts")
    p.add_argument("--out", type=Path, default=None, help="write the numbers as JSON here")
    args = p.parse_args(argv)
    import numba

    import contactalpha as ca
    from contactalpha.baselines.reference import impact_scipy
    from contactalpha.engine.kernel import impact_kernel

    cold, warm = cold_compile_seconds()
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"numba threads {numba.get_num_threads()}, python {platform.python_version()}"
    )
    print(f"compile (cold cache): {cold:.2f} s   import+first call (warm cache): {warm:.2f} s")

    rec = np.empty((0, 3))
    results = {"compile_cold_s": cold, "warm_start_s": warm, "impact": []}
    for alpha, xi, label in [
        (0.5, 0.2, "separation"),
        (5.0, 0.2, "nonseparation"),
        (50.0, 0.2, "creep"),
        (10.0, 0.0, "unloaded"),
    ]:
        A = float(ca.scaled_load(xi))
        n = 200 if args.quick else 2000

        def ours_run(alpha=alpha, A=A, n=n):
            for _ in range(n):
                impact_kernel(alpha, A, 1e-12, 1e-14, 2_000_000, rec, np.inf)

        def scipy_run(alpha=alpha, xi=xi):
            impact_scipy(alpha, xi, method="DOP853", rtol=1e-12, atol=1e-14)

        ours = best_of(ours_run, 3) / n
        ref = best_of(scipy_run, 3)
        print(
            f"one impact [{label:13s}] ours {ours * 1e6:8.1f} us   scipy DOP853 {ref * 1e6:9.0f} us"
            f"   ratio {ref / ours:6.0f}x"
        )
        results["impact"].append(dict(label=label, ours_s=ours, scipy_s=ref, ratio=ref / ours))

    eps = np.round(np.arange(1, 100) * 0.01, 2)
    xi = np.round(np.arange(0, 100) * 0.01, 2)
    E, X = np.meshgrid(eps, xi, indexing="ij")
    ca.solve_alpha(E[:2, :2], X[:2, :2])
    t = time.perf_counter()
    s = ca.solve_alpha(E, X)
    grid_all = time.perf_counter() - t
    numba.set_num_threads(1)
    t = time.perf_counter()
    ca.solve_alpha(E, X)
    grid_one = time.perf_counter() - t
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    loaded = X > 0
    print(
        f"99 x 100 grid: {grid_all:.2f} s on {numba.config.NUMBA_NUM_THREADS} threads, "
        f"{grid_one:.2f} s on 1 thread (speed-up {grid_one / grid_all:.2f}x); "
        f"failed points {int((~s.ok).sum())}"
    )
    print(
        f"impacts per loaded point: mean {s.impacts[loaded].mean():.2f}, max {s.impacts[loaded].max()}; "
        f"steps per impact: mean {s.steps[loaded].sum() / s.impacts[loaded].sum():.0f}"
    )
    results.update(
        grid_s=grid_all,
        grid_one_thread_s=grid_one,
        failed=int((~s.ok).sum()),
        impacts_mean=float(s.impacts[loaded].mean()),
        impacts_max=int(s.impacts[loaded].max()),
    )
    if args.out:
        from contactalpha.io import write_json_atomic
        from contactalpha.provenance import result_attrs

        write_json_atomic(args.out, {**result_attrs(vars(args), "bench_core"), **results})


if __name__ == "__main__":
    main()
