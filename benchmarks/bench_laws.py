"""Benchmark: the contact laws' evaluators against today's Hunt-Crossley table (issue 26).

Run: ``python benchmarks/bench_laws.py`` (``--quick`` for a smoke run, ``--out FILE`` for JSON,
``--cold`` for an empty numba cache, so that the first calls are the compiles).
Prints, measured in this run on random points of each law's domain:
- the first call of each evaluator (numba's compile, or its cache load), apart;
- points per second of each law's fast evaluator (closed form: forward map and inverse; the
  tables: the inverse, for eps and e_N), of its exact reference (the integrator, forward), and of
  the baseline, the engine's spline table ``alpha_tabulated`` (n = 3/2), as a ratio to the baseline;
- the largest error of each fast evaluator against its reference on a subsample (for an inverse:
  the restitution its damping delivers through the integrator, minus the target).
"""

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np


def best_seconds(fn, repeat):
    """Shortest of ``repeat`` runs of ``fn()``."""
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def first_call(fn):
    """Seconds of the first call (compile or cache load)."""
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--out", type=Path)
    p.add_argument("--cold", action="store_true")
    args = p.parse_args(argv)
    if args.cold:
        import tempfile

        os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="bench_laws_")  # before numba's import

    import numba

    from contactalpha.engine.table import alpha_tabulated
    from contactalpha.laws import LAWS

    n = 100_000 if args.quick else 1_000_000
    n_ref = 200 if args.quick else 2000
    repeat = 3
    rng = np.random.default_rng(26)
    target = rng.uniform(0.01, 1.0, n)
    xi = 0.99 * rng.random(n)
    damping = np.exp(rng.uniform(np.log(1e-3), np.log(30.0), n))
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, numba threads {numba.get_num_threads()}")
    print(f"points: {n} (fast), {n_ref} (references)")

    compile_s = {"alpha_tabulated": first_call(lambda: alpha_tabulated(target[:10], xi[:10]))}
    base = n / best_seconds(lambda: alpha_tabulated(target, xi), repeat)
    rows = [("hunt_crossley", "engine table alpha(eps, xi) [baseline]", base, np.nan)]
    from contactalpha.laws import get_law

    # MuJoCo off its table's impedance: the closed form's inverse (root finding), for comparison.
    for law in [*LAWS, get_law("mujoco_soft", impedance=0.5)]:
        s = slice(0, n_ref)
        label = law.name if law in LAWS else f"{law.name} d={law.impedance}"
        tabulated = getattr(law.fast, "covers", lambda law: False)(law)
        compile_s[f"{label} impact"] = first_call(lambda law=law: law.impact(damping[:10], xi[:10]))
        ref_rate = n_ref / best_seconds(lambda law=law, s=s: law.impact(damping[s], xi[s]), 1)
        rows.append((label, "reference integrator, forward", ref_rate, np.nan))
        if law.fast is None:
            continue
        if law.piecewise_linear:
            compile_s[f"{label} fast forward"] = first_call(
                lambda law=law: law.fast_restitution(damping[:10], xi[:10])
            )
            fwd = n / best_seconds(lambda law=law: law.fast_restitution(damping, xi), repeat)
            err = np.max(np.abs(law.fast_restitution(damping[s], xi[s]) - law.impact(damping[s], xi[s]).eps))
            rows.append((label, "closed form, forward eps(zeta, xi)", fwd, err))
        # The closed form inverts by root finding, the tables by one spline evaluation.
        m = n if tabulated or not law.piecewise_linear else n // 10
        name = law.fast.name if tabulated or not law.piecewise_linear else "closed form"
        for kind in ("energetic", "kinematic"):
            compile_s[f"{label} fast inverse {kind}"] = first_call(
                lambda law=law, kind=kind: law.fast_damping(target[:10], xi[:10], kind)
            )
            inv = m / best_seconds(
                lambda law=law, m=m, kind=kind: law.fast_damping(target[:m], xi[:m], kind),
                repeat if m == n else 1,
            )
            got = law.restitution(law.fast_damping(target[s], xi[s], kind), xi[s], kind)
            rows.append((label, f"{name}, inverse ({kind})", inv, np.max(np.abs(got - target[s]))))
    print("\nfirst calls (compile or cache load), s:")
    for name, sec in compile_s.items():
        print(f"  {name:46s} {sec:8.2f}")
    print(f"\n{'law':22s} {'evaluator':40s} {'points/s':>12s} {'/ baseline':>11s} {'max error':>10s}")
    for law, what, r, err in rows:
        print(f"{law:22s} {what:40s} {r:12.3g} {r / base:11.3g} {err:10.2g}")
    if args.out:
        out = {"n": n, "compile_s": compile_s, "rows": [list(map(str, row)) for row in rows]}
        args.out.write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
