"""What bounds the batched front door of the default law (issue 36, item 5).

``contact_parameters`` with arrays of N random scenes (Hunt-Crossley, n = 3/2; Newton's e_N) is
timed whole, in numba's threads and in one, against the shipped e_N table alone on the same rows
(``alpha_tabulated``, the baseline measured in the same run: the ratio says how many table
lookups one scene of the front door costs).  Then where its time goes, per scene and one thread:

- the length scale delta_star (``engine.scaling``'s ``_scales``: five logarithms and a power);
- Eq. 10's Newton solve (two ``pow`` calls a step; the steps it takes, counted on a sample, and
  the kernel as it was before it stopped at a 1-ulp 2-cycle, the baseline of that change);
- the table lookup (four libm calls and a 6 x 6 tensor spline; de Boor's recursion where a row
  falls in the five spline intervals at either clamped end of a grid, which e_N above 0.63 does);
- numpy's passes over the arrays (checks, masks, engine blocks), the whole less the kernels;

and the libm costs that bound them (ns per ``pow``, ``log``, ``exp``, measured here).  The bound:
the kernels' time per scene over the cores, with numpy's passes, against the 1e7 scenes/s goal.
Every number stays the same bits; nothing here changes one.  The first (compiling) calls are
timed apart; the machine's load is printed before and after.

Usage:  python benchmarks/bench_batch_bound.py [--n 1000000] [--repeat 5] [--page]
(``--page`` also fills the batch-bound block of docs/performance.md).
"""

import argparse
import os
import platform
import re
import time
from pathlib import Path

import numba
import numpy as np
from bench_core import best_of  # this folder's runner (a script's folder is on sys.path)
from numba import njit

from contactalpha.engine import scaling
from contactalpha.engine.table import (
    G_COUNT,
    G_FIRST,
    G_K_ETA,
    G_K_Q,
    G_STEP,
    alpha_tabulated,
    eta_of_xi,
    kinematic_alpha_from_table_rows,
    kinematic_table_arrays,
)
from contactalpha.parameters.batch import _hertz_load_factor_rows, hertz_load_factor
from contactalpha.parameters.front_door import contact_parameters

PAGE = Path(__file__).resolve().parents[1] / "docs" / "performance.md"
START, END = "<!-- batch-bound:start -->", "<!-- batch-bound:end -->"
GOAL = 1e7  # scenes/s on 2 cores (issue 36)
_step = njit(inline="always")(scaling._xi_newton_step)


@njit(cache=True)
def _scales_loop(m, k, v, out):
    for i in range(m.size):
        out[i] = scaling.scales_kernel(m[i], k[i], v[i])[0]


@njit(cache=True)
def _newton_loop(A, out):
    for i in range(A.size):
        out[i] = scaling.xi_of_load_kernel(A[i])


@njit(cache=True)
def _newton_before(A, out):
    """Eq. 10 as the kernel ran before its stop at a 2-cycle: only a fixed point ends it early."""
    for i in range(A.size):
        a = A[i]
        xm = (1.0 + 2.0 * a) ** (2.0 / 3.0)
        for _ in range(scaling.XI_NEWTON_STEPS):
            nxt = _step(a, xm)
            if nxt == xm:
                break
            xm = nxt
        out[i] = a * xm / (0.5 + a * xm)


@njit(cache=True)
def _libm(x, which):
    acc = 0.0
    for i in range(x.size):
        if which == 0:
            acc += x[i] ** 2.5
        elif which == 1:
            acc += np.log(x[i])
        else:
            acc += np.exp(x[i])
    return acc


def steps_taken(A):
    """Newton steps (the confirming one included) until ``xi_of_load_kernel`` stops, and 2-cycles."""
    steps, cycles = [], 0
    for a in A:
        xm, before, taken = (1.0 + 2.0 * a) ** (2.0 / 3.0), np.nan, 0
        while taken < scaling.XI_NEWTON_STEPS:
            nxt = scaling._xi_newton_step(a, xm)
            taken += 1
            if nxt == xm or nxt == before:
                cycles += nxt == before
                break
            before, xm = xm, nxt
        steps.append(taken)
    return float(np.mean(steps)), cycles / len(A)


def edge_fraction(e_n, xi):
    """Share of rows whose e_N table lookup falls in a clamped end's intervals (de Boor's path)."""
    g = kinematic_table_arrays()[3]
    hits = np.zeros(e_n.shape, dtype=bool)
    for slot, x in ((G_K_ETA, eta_of_xi(xi)), (G_K_Q, np.log(e_n))):
        n = int(g[slot + G_COUNT])
        j = np.clip(np.floor((x - g[slot + G_FIRST]) / g[slot + G_STEP]), 0, n - 2)
        hits |= (j < 5) | (j > n - 7)
    return float(hits.mean())


def measure(n, repeat):
    rng = np.random.default_rng(0)
    m, k = rng.uniform(0.1, 2.0, n), 10.0 ** rng.uniform(6.0, 9.0, n)
    v, a, e = rng.uniform(0.2, 3.0, n), rng.uniform(0.0, 50.0, n), rng.uniform(0.05, 0.95, n)
    r = {"load_before": os.getloadavg()[0], "threads": numba.get_num_threads(), "n": n}
    scenes = {"mass": m, "stiffness": k, "approach_speed": v, "accel": a, "e_N": e}
    t = time.perf_counter()
    contact_parameters(**{key: x[:8] for key, x in scenes.items()})
    r["compile_s"] = time.perf_counter() - t
    xi = hertz_load_factor(m, k, v, a)
    alpha_tabulated(e[:8], xi[:8], restitution="kinematic")
    r["front"] = best_of(lambda: contact_parameters(**scenes), repeat)
    r["table"] = best_of(lambda: alpha_tabulated(e, xi, restitution="kinematic"), repeat)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        r["front_1"] = best_of(lambda: contact_parameters(**scenes), repeat)
        r["table_1"] = best_of(lambda: alpha_tabulated(e, xi, restitution="kinematic"), repeat)
    finally:
        numba.set_num_threads(threads)
    # The stages, one thread, by their own kernels.
    out, ok = np.empty(n), np.empty(n, dtype=np.bool_)
    A = a * scaling.length_scale(m, k, v) / v**2
    tab = kinematic_table_arrays()
    for f, args in (
        (_scales_loop, (m, k, v, out)),
        (_newton_loop, (A, out)),
        (_newton_before, (A, out)),
        (_hertz_load_factor_rows, (m, k, v, a, out, ok, 0, 8)),
        (kinematic_alpha_from_table_rows, (e, xi, *tab, out, 0, 8)),
    ):
        f(*[x[:8] if isinstance(x, np.ndarray) else x for x in args])
    r["scales"] = best_of(lambda: _scales_loop(m, k, v, out), repeat)
    r["newton"] = best_of(lambda: _newton_loop(A, out), repeat)
    r["newton_before"] = best_of(lambda: _newton_before(A, out), repeat)
    r["load_kernel"] = best_of(lambda: _hertz_load_factor_rows(m, k, v, a, out, ok, 0, n), repeat)
    r["lookup_kernel"] = best_of(lambda: kinematic_alpha_from_table_rows(e, xi, *tab, out, 0, n), repeat)
    lo = e < 0.55
    e_in, xi_in = np.ascontiguousarray(e[lo]), np.ascontiguousarray(xi[lo])
    r["lookup_inner"] = best_of(
        lambda: kinematic_alpha_from_table_rows(e_in, xi_in, *tab, out, 0, e_in.size), repeat
    ) * (n / e_in.size)
    r["edge_share"] = edge_fraction(e, xi)
    r["steps"], r["cycles"] = steps_taken(A[:20000])
    x = rng.uniform(1.0, 2.0, n)
    for which, name in enumerate(("pow", "log", "exp")):
        _libm(x[:8], which)
        r[name] = best_of(lambda w=which: _libm(x, w), repeat)
    r["load_after"] = os.getloadavg()[0]
    return r


def report(r):
    n, ns = r["n"], 1e9 / r["n"]
    kernels = (r["load_kernel"] + r["lookup_kernel"]) * ns
    rest = r["front_1"] * ns - kernels
    cores = os.cpu_count()
    bound = min(cores, r["threads"]) / (kernels * 1e-9)
    lines = [
        f"Measured on {platform.processor() or platform.machine()}, {cores} cores, numba "
        f"{numba.__version__}, {n:,} random scenes (mass 0.1–2 kg, k 1e6–1e9 N/m^1.5, speed "
        f"0.2–3 m/s, load 0–50 m/s², e_N 0.05–0.95); load average {r['load_before']:.1f} before and "
        f"{r['load_after']:.1f} after (other sessions' jobs on the same 2 cores); best of repeated "
        f"runs; first call (compile or cache load) {r['compile_s']:.2f} s, apart.",
        "",
        "| | scenes/s | front door / table (time) |",
        "|---|---|---|",
        f"| front door, {r['threads']} threads | {n / r['front']:.3g} | {r['front'] / r['table']:.1f} |",
        f"| e_N table alone, {r['threads']} threads | {n / r['table']:.3g} | 1 |",
        f"| front door, 1 thread | {n / r['front_1']:.3g} | {r['front_1'] / r['table_1']:.1f} |",
        f"| e_N table alone, 1 thread | {n / r['table_1']:.3g} | 1 |",
        "",
        "Where one scene's time goes, one thread (ns):",
        "",
        "| stage | ns per scene | what it costs |",
        "|---|---|---|",
        f"| delta_star | {r['scales'] * ns:.0f} | 6 `log`, 1 `pow` |",
        f"| Eq. 10 (Newton) | {r['newton'] * ns:.0f} | {r['steps']:.1f} steps of 2 `pow` on average "
        f"in a chain, each waiting for the last ({r['cycles']:.1%} of loads end in a 1-ulp 2-cycle; "
        f"run to all 60 steps there, as before the stop at it: {r['newton_before'] * ns:.0f}, "
        f"{r['newton_before'] / r['newton']:.1f} times as long) |",
        f"| load factor kernel (both, fused) | {r['load_kernel'] * ns:.0f} | |",
        f"| e_N lookup | {r['lookup_kernel'] * ns:.0f} | 2 `log1p`, `log`, `exp`, a 6 x 6 spline "
        f"({r['lookup_inner'] * ns:.0f} where e_N < 0.55); {r['edge_share']:.0%} of rows in a clamped "
        "end's intervals take de Boor's recursion (30 divisions) |",
        f"| numpy passes (checks, masks, engine blocks) | {rest:.0f} | the front door less its kernels |",
        "",
        f"libm here: `pow` {r['pow'] * ns:.1f} ns, `log` {r['log'] * ns:.1f} ns, `exp` "
        f"{r['exp'] * ns:.1f} ns per call.  The kernels alone need {kernels:.0f} ns of one core per "
        f"scene: at most {bound:.2g} scenes/s on {min(cores, r['threads'])} cores with nothing else "
        f"({bound / GOAL:.2f} of the 1e7 goal), before numpy's {rest:.0f} ns.",
    ]
    return "\n".join(lines)


def fill_page(block, page=PAGE):
    """Put ``block`` between the batch-bound markers of ``page``."""
    text = page.read_text()
    pattern = re.compile(re.escape(START) + r".*?" + re.escape(END), re.S)
    if not pattern.search(text):
        raise ValueError(f"{page} has no {START} ... {END} block")
    page.write_text(pattern.sub(lambda _: f"{START}\n{block}\n{END}", text))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--page", action="store_true", help="fill the batch-bound block of docs/performance.md")
    args = p.parse_args()
    block = report(measure(args.n, args.repeat))
    print(block)
    if args.page:
        fill_page(block)


if __name__ == "__main__":
    main()
