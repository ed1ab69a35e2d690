"""Benchmark of the C export (issue 11, part 4): C evaluations/s against the numba lookup, same run.

Run: ``python benchmarks/bench_export_c.py`` (``--quick`` for a smoke run).
Writes the export to a temporary folder, compiles it with the tested flags
(``-std=c99 -Wall -Wextra -Werror -O2``; compile time reported separately), then for Stronge's eps
and Newton's e_N evaluates the same random points (inside the tables' domain) with
``contactalpha_alpha_many`` (one ctypes call, the loop in C) and with the numba lookup's serial
array loop (``alpha_from_table_rows``, one thread; its compile time is excluded by a warm-up),
and prints both rates, their ratio and the largest relative difference.
"""

import argparse
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np


def best_time(fn, repeat):
    """Best wall time of ``repeat`` calls of ``fn`` (after one warm-up call), in seconds."""
    fn()
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="smaller counts")
    args = p.parse_args(argv)
    import numba

    from contactalpha.engine.table import (
        alpha_from_table_rows,
        kinematic_alpha_from_table_rows,
        kinematic_table_arrays,
        lookup_many,
        table_arrays,
    )
    from contactalpha.engine.table_build import random_points
    from contactalpha.export.c_source import (
        C_FLAGS,
        alpha_many,
        c_compiler,
        compile_shared,
        export_c,
        load_library,
    )

    n = 100_000 if args.quick else 1_000_000
    repeat = 3 if args.quick else 7
    compiler = c_compiler()
    if compiler is None:
        raise SystemExit("no C compiler (cc, gcc or clang) on PATH: nothing to benchmark")
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"numba threads {numba.get_num_threads()}, compiler {compiler} {' '.join(C_FLAGS)}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        export_c(tmp)
        t_export = time.perf_counter() - t
        t = time.perf_counter()
        lib = load_library(compile_shared(tmp, Path(tmp) / "libcontactalpha.so", compiler))
        t_compile = time.perf_counter() - t
        size = (Path(tmp) / "contactalpha.c").stat().st_size
        print(
            f"export {t_export:.2f} s ({size / 1e6:.1f} MB of C source), "
            f"compile {t_compile:.2f} s (not timed below)"
        )
        value, xi = random_points(n, seed=11)
        numba_lookups = {
            "energetic": (alpha_from_table_rows, table_arrays()),
            "kinematic": (kinematic_alpha_from_table_rows, kinematic_table_arrays()),
        }
        for kind, (serial, arrays) in numba_lookups.items():
            t_c = best_time(lambda kind=kind: alpha_many(lib, value, xi, kind), repeat)
            t_nb = best_time(
                lambda serial=serial, arrays=arrays: lookup_many(serial, value, xi, arrays, threads=1), repeat
            )
            c, ref = alpha_many(lib, value, xi, kind), lookup_many(serial, value, xi, arrays, threads=1)
            rel = np.max(np.abs(c - ref) / np.abs(ref))
            print(
                f"{kind:10s}: C {n / t_c:.3g} evaluations/s, numba {n / t_nb:.3g} evaluations/s, "
                f"C/numba {t_nb / t_c:.2f}; max rel difference {rel:.2e}, "
                f"bit-identical {int(np.sum(c == ref))}/{n} ({n} random points)"
            )


if __name__ == "__main__":
    main()
