"""Benchmark: exact alpha at formula speed (issue: contact models).

Run: ``python benchmarks/bench_models.py`` (``--quick`` for a smoke run, ``--out FILE`` for JSON).
Prints, measured in this run on the same random points of the table's domain:
- evaluations per second of ``alpha(..., model="exact")`` (vectorised, and the jitted scalar
  form in a user's numba loop), of the published Eq. 40 and of ``solve_alpha``;
- the accuracy of each against ``solve_alpha`` (max and median relative error in alpha);
- the cost ratio exact / Eq. 40 (the target is at most 3);
- the closed form (model ``closed_form``, issue 13), vectorised and its jitted scalar in the
  same numba loop, and its cost ratio over Eq. 40 (the target is at most 1; Eq. 40 has no
  jitted scalar, so both closed-form rows are set against Eq. 40 vectorised).
"""

import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np


def rate(fn, n, repeat=5):
    """Best evaluations per second over ``repeat`` runs of ``fn()`` evaluating ``n`` points."""
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return n / best


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--out", type=Path)
    args = p.parse_args(argv)

    import numba
    from numba import njit

    import contactalpha as ca
    from contactalpha.engine.table_build import random_points
    from contactalpha.models import MODELS

    n = 100_000 if args.quick else 1_000_000
    n_solve = 300 if args.quick else 3000
    eps, xi = random_points(n, seed=7)
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, numba threads {numba.get_num_threads()}")

    ref = ca.solve_alpha(eps[:n_solve], xi[:n_solve], tol=1e-13, guess="formula")
    solve_rate = rate(lambda: ca.solve_alpha(eps[:n_solve], xi[:n_solve]), n_solve, repeat=2)

    ca.alpha(eps[:10], xi[:10], model="exact")
    exact_rate = rate(lambda: ca.alpha(eps, xi, model="exact"), n)
    f = ca.jit_alpha_tabulated()

    @njit
    def user_loop(e, x):
        s = 0.0
        for i in range(e.size):
            s += f(e[i], x[i])
        return s

    user_loop(eps[:10], xi[:10])
    jit_rate = rate(lambda: user_loop(eps, xi), n)

    rows = [
        ("exact (table, vectorised)", exact_rate, ca.alpha(eps[:n_solve], xi[:n_solve], model="exact")),
        ("exact (jitted scalar, user loop, 1 thread)", jit_rate, None),
        ("solve_alpha (Newton on the engine)", solve_rate, ref.alpha),
    ]
    eq40 = "shen_published"
    if eq40 in MODELS:
        ca.alpha(eps[:10], xi[:10], model=eq40)
        eq40_rate = rate(lambda: ca.alpha(eps, xi, model=eq40), n)
        rows.insert(
            2, ("Eq. 40 published (numpy)", eq40_rate, ca.alpha(eps[:n_solve], xi[:n_solve], model=eq40))
        )
    else:
        eq40_rate = float("nan")
        print(f"note: model {eq40!r} not registered; Eq. 40 row skipped")
    from contactalpha.models.closed_form import jit_alpha_closed_form

    ca.alpha(eps[:10], xi[:10], model="closed_form")
    closed_rate = rate(lambda: ca.alpha(eps, xi, model="closed_form"), n)
    g = jit_alpha_closed_form()

    @njit
    def closed_loop(e, x):
        s = 0.0
        for i in range(e.size):
            s += g(e[i], x[i])
        return s

    closed_loop(eps[:10], xi[:10])
    closed_jit_rate = rate(lambda: closed_loop(eps, xi), n)
    closed_alpha = ca.alpha(eps[:n_solve], xi[:n_solve], model="closed_form")
    rows += [
        ("closed form (vectorised)", closed_rate, closed_alpha),
        ("closed form (jitted, user loop, 1 thread)", closed_jit_rate, None),
    ]

    print(f"{'method':45s} {'evals/s':>12s} {'max rel err':>12s} {'median':>10s}")
    out = {"n": n, "n_solve": n_solve, "rows": []}
    for name, r, a in rows:
        if a is None:
            err_max = err_med = float("nan")
        else:
            rel = np.abs(np.asarray(a) / ref.alpha - 1)
            err_max, err_med = float(np.nanmax(rel)), float(np.nanmedian(rel))
        print(f"{name:45s} {r:12.3e} {err_max:12.2e} {err_med:10.1e}")
        out["rows"].append(dict(method=name, evals_per_s=r, max_rel_err=err_max, median_rel_err=err_med))
    ratio = eq40_rate / exact_rate
    print(
        f"cost ratio exact / Eq. 40: {ratio:.2f} (target <= 3); exact vs solve_alpha speed-up: "
        f"{exact_rate / solve_rate:.0f}x"
    )
    out.update(cost_ratio_exact_over_eq40=ratio, speedup_over_solve=exact_rate / solve_rate)
    closed_ratio, closed_jit_ratio = eq40_rate / closed_rate, eq40_rate / closed_jit_rate
    print(
        f"cost ratio closed form / Eq. 40: vectorised {closed_ratio:.2f}, jitted loop {closed_jit_ratio:.2f} "
        "(target <= 1)"
    )
    out.update(cost_ratio_closed_over_eq40=closed_ratio, cost_ratio_closed_jit_over_eq40=closed_jit_ratio)
    if args.out:
        from contactalpha.io import write_json_atomic
        from contactalpha.provenance import result_attrs

        write_json_atomic(args.out, {**result_attrs(vars(args), "bench_models"), **out})


if __name__ == "__main__":
    main()
