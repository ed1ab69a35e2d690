"""Benchmark of the first call on a cold numba cache (issue 25, item 4).

Run: ``python benchmarks/bench_first_call.py`` (``--repeat N`` alternating rounds, default 2).
Each measurement is a fresh Python process with an empty ``NUMBA_CACHE_DIR``: the wall time of
``import contactalpha`` and of the first call, for ``ca.alpha(0.5, 0.2)`` (the default model,
through the table) and ``ca.contact_parameters(...)`` (a 2 kg foot, through the table), each

- as shipped: the Python twins of the kernels answer the first calls (``engine/firstcall.py``);
- baseline, the old path: the same call inside ``firstcall.compiled_only()``, which compiles
  the kernels first, as every call did before (measured in the same run, rounds alternating).

Prints the machine, its load, and the best and median of each, and the ratio baseline / new.
"""

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
CALLS = {
    "alpha": "ca.alpha(0.5, 0.2)",
    "contact_parameters": "ca.contact_parameters(0.5, 2.0, 2.51e6, 0.5, accel=9.81)",
}
PROGRAM = """
import contextlib
import time
t0 = time.perf_counter()
import contactalpha as ca
from contactalpha.engine import firstcall
t1 = time.perf_counter()
with {context}:
    value = {call}
t2 = time.perf_counter()
print(t1 - t0, t2 - t1)
"""


def cpu_name():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown cpu"


def cold_run(call, baseline):
    """(import seconds, first-call seconds) in a fresh process with an empty numba cache."""
    context = "firstcall.compiled_only()" if baseline else "contextlib.nullcontext()"
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache, "PYTHONPATH": str(SRC)}
        out = subprocess.run(
            [sys.executable, "-c", PROGRAM.format(context=context, call=call)],
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
    imp, first = map(float, out.stdout.split())
    return imp, first


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=2, help="alternating rounds (default 2)")
    args = p.parse_args(argv)
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores, {platform.platform()}")
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    print(f"{'call':20s} {'path':10s} {'import s':>9s} {'first call s (best, median)':>28s}")
    for name, call in CALLS.items():
        times = {"new": [], "baseline": []}
        for _ in range(args.repeat):
            for path in times:
                times[path].append(cold_run(call, baseline=path == "baseline"))
        for path, runs in times.items():
            firsts = [f for _, f in runs]
            imp = min(i for i, _ in runs)
            print(f"{name:20s} {path:10s} {imp:9.2f} {min(firsts):14.2f} {statistics.median(firsts):12.2f}")
        ratio = statistics.median(f for _, f in times["baseline"]) / statistics.median(
            f for _, f in times["new"]
        )
        print(f"{name:20s} baseline / new (median first call): {ratio:.1f}x")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
