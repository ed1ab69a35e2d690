"""Benchmark of the user-facing scalar calls and of the exact lookup for both restitutions (issue 11).

Run: ``python benchmarks/bench_front_door.py`` (``--quick`` for a smoke run).
Prints, measured side by side in this run (best of several repeats, one thread):
- the lookup, vectorised, in evaluations per second, for Stronge's eps and Newton's e_N, and its
  largest relative error against the solver at random points;
- per scalar call of ``impact``, ``solve_alpha``, ``alpha`` and ``contact_parameters``: its time,
  the time of the jitted kernel it wraps called directly from Python (for the lookup, the packed
  evaluator the scalar path runs; the nine-array evaluator's time is printed after the table),
  the overhead (the difference) and the ratio overhead / kernel (the target is < 1); and the full
  array path on a 0-d array (what a scalar call cost before the fast paths) beside it.
"""

import argparse
import os
import platform
import time

import numpy as np

# Alternating rounds of call and kernel timing per row.
ROUNDS = 5


def best_per_call(fn, calls, repeat):
    """Best over ``repeat`` runs of the mean time of ``calls`` calls, in seconds."""
    fn()
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - t) / calls)
    return best


def main(argv=None):
    """Steady state: the scalar paths' kernels compiled, not their first calls' Python twins."""
    from contactalpha.engine.firstcall import compiled_only

    with compiled_only():
        run(argv)


def run(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="smaller counts")
    args = p.parse_args(argv)
    import numba

    import contactalpha as ca
    from contactalpha.engine.codes import N_REC
    from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL
    from contactalpha.engine.kernel import impact_kernel
    from contactalpha.engine.scaling import scaled_load, xi_of_load_scalar
    from contactalpha.engine.solver import EPS_TOL, _guess_arrays, solve_point
    from contactalpha.engine.table import (
        alpha_from_packed,
        alpha_from_table,
        alpha_tabulated,
        kinematic_alpha_from_packed,
        scalar_lookup,
        table_arrays,
    )
    from contactalpha.engine.table_build import random_points

    n_look = 100_000 if args.quick else 1_000_000
    n_acc = 200 if args.quick else 2000
    calls = 200 if args.quick else 2000
    repeat = 3 if args.quick else 7
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"numba threads {numba.get_num_threads()}"
    )
    eps, xi = random_points(n_look, seed=11)
    for kind in ("energetic", "kinematic"):
        alpha_tabulated(eps[:10], xi[:10], restitution=kind)
        t = min(
            (lambda t0: (alpha_tabulated(eps, xi, restitution=kind), time.perf_counter() - t0)[1])(
                time.perf_counter()
            )
            for _ in range(repeat)
        )
        e, x = eps[:n_acc], xi[:n_acc]
        ref = ca.solve_alpha(e, x, restitution=kind, guess="formula", tol=1e-13)
        rel = np.abs(alpha_tabulated(e, x, restitution=kind) / ref.alpha - 1.0)
        print(
            f"lookup {kind:10s}: {n_look / t:.3g} evaluations/s ({n_look} points);"
            f" max rel error {np.nanmax(rel):.2e} at {n_acc} random points"
            f" (solver failures: {int((~ref.ok).sum())})"
        )

    rec = np.empty((0, N_REC))
    a_, x_, e_ = 0.5, 0.3, 0.5
    A = float(scaled_load(x_))
    _, tb, _ = _guess_arrays(True, False)
    _, _, tk = _guess_arrays(True, True)
    tbl = table_arrays()
    # The evaluators the scalar paths run: one packed array instead of nine array arguments.
    flat, kflat = scalar_lookup("energetic")[1], scalar_lookup("kinematic")[1]
    ball = dict(mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=9.81)
    xi_ball = ca.influence_factor(0.5, 1.4e8, 0.5, 9.81)
    alpha_ball = ca.alpha(0.8, xi_ball)
    A_ball = float(scaled_load(xi_ball))

    a_ball = 0.5 * 9.81 * ca.length_scale(0.5, 1.4e8, 0.5) / 0.5**2  # Eq. 10's scaled load
    # The same damping at half and twice the speed (contact_parameters' e_n_half/twice_speed).
    other = [(f, 9.81 * ca.length_scale(0.5, 1.4e8, 0.5 * f) / (0.5 * f) ** 2) for f in (0.5, 2.0)]

    def front_door_kernels():
        # The compiled work of one contact_parameters call: Eq. 10's Newton solve for xi
        # (a fixed 60 steps), the table lookup and one impact; then xi and one impact at half
        # and at twice the speed.
        xi_of_load_scalar(a_ball)
        alpha_from_packed(0.8, xi_ball, flat)
        impact_kernel(alpha_ball, A_ball, RTOL, ATOL, MAX_STEPS, rec, np.inf)
        for f, a_other in other:
            xi_of_load_scalar(a_other)
            impact_kernel(alpha_ball * f, a_other, RTOL, ATOL, MAX_STEPS, rec, np.inf)

    rows = [
        (
            "impact",
            lambda: ca.impact(a_, x_),
            lambda: impact_kernel(a_, A, RTOL, ATOL, MAX_STEPS, rec, np.inf),
            lambda: ca.impact(np.asarray(a_), np.asarray(x_)),
        ),
        (
            "solve_alpha",
            lambda: ca.solve_alpha(e_, x_),
            lambda: solve_point(e_, A, x_, EPS_TOL, RTOL, ATOL, MAX_STEPS, True, True, tb, False, tk),
            lambda: ca.solve_alpha(np.asarray(e_), np.asarray(x_)),
        ),
        (
            "solve_alpha kinematic",
            lambda: ca.solve_alpha(e_, x_, restitution="kinematic"),
            lambda: solve_point(e_, A, x_, EPS_TOL, RTOL, ATOL, MAX_STEPS, True, True, tb, True, tk),
            lambda: ca.solve_alpha(np.asarray(e_), np.asarray(x_), restitution="kinematic"),
        ),
        (
            "alpha exact",
            lambda: ca.alpha(e_, x_),
            lambda: alpha_from_packed(e_, x_, flat),
            lambda: ca.alpha(np.asarray(e_), np.asarray(x_)),
        ),
        (
            "alpha exact kinematic",
            lambda: ca.alpha(e_, x_, restitution="kinematic"),
            lambda: kinematic_alpha_from_packed(e_, x_, kflat),
            lambda: ca.alpha(np.asarray(e_), np.asarray(x_), restitution="kinematic"),
        ),
        (
            "contact_parameters",
            lambda: ca.contact_parameters(0.8, **ball),
            front_door_kernels,
            None,
        ),
    ]
    head = ("call us", "kernel us", "overhead", "ovh/kern", "0-d array us")
    print(f"{'scalar call':24s} " + " ".join(f"{h:>12s}" for h in head))
    for name, call, kernel, full in rows:
        # Call and kernel in alternating rounds, so that a burst of load on the shared machine
        # hits both rather than one of them; the best round of each counts.
        tc = tk_ = np.inf
        for _ in range(ROUNDS):
            tc = min(tc, best_per_call(call, calls // ROUNDS, repeat))
            tk_ = min(tk_, best_per_call(kernel, calls // ROUNDS, repeat))
        tf = best_per_call(full, calls // 4 or 1, repeat) if full is not None else np.nan
        over = tc - tk_
        cells = (tc * 1e6, tk_ * 1e6, over * 1e6, over / tk_, tf * 1e6)
        print(f"{name:24s} " + " ".join(f"{c:12.2f}" for c in cells))
    nine = best_per_call(lambda: alpha_from_table(e_, x_, *tbl), calls, repeat)
    packed = best_per_call(lambda: alpha_from_packed(e_, x_, flat), calls, repeat)
    print(
        f"energetic lookup kernel from Python: nine table arrays {nine * 1e6:.2f} us,"
        f" packed {packed * 1e6:.2f} us"
    )


if __name__ == "__main__":
    main()
