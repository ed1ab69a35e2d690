"""Benchmark of the first call of every contact law, cold and after ``contactalpha warmup``.

Run: ``python benchmarks/bench_first_call.py`` (``--page`` also fills the first-call block of
docs/performance.md; ``--no-baseline`` skips the old path; ``--repeat N``, default 1).

Each measurement is a fresh Python process: the wall time of ``import contactalpha`` and of the
first ``contact_parameters(..., law=NAME)`` call, for one scene and for a batch of 1,000 scenes
(a 0.5 kg ball, random e_N and masses), for every law of ``contactalpha.laws.LAWS``:

- cold: an empty ``NUMBA_CACHE_DIR``: the kernels' Python twins answer (``engine/firstcall.py``);
- warm: a ``NUMBA_CACHE_DIR`` filled once by ``contactalpha warmup`` (its time is reported apart,
  as the compile time): the compiled kernels load from disk;
- baseline, the old path: cold, inside ``firstcall.compiled_only()``, which compiles every kernel
  at its first call as every first call did before (measured in the same run).

Prints the machine, its load before and after, a table of wall and CPU seconds (on a loaded machine
the CPU time is the better guess of a quiet machine's wall time), and the ratio baseline / cold.
"""

import argparse
import math
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
PAGE = ROOT / "docs" / "performance.md"
START, END = "<!-- first-call:start -->", "<!-- first-call:end -->"
BATCH = 1000
PROGRAM = """
import contextlib
import time
t0, c0 = time.perf_counter(), time.process_time()
import numpy as np
import contactalpha as ca
from contactalpha.engine import firstcall
t1, c1 = time.perf_counter(), time.process_time()
rng = np.random.default_rng(1)
n = {n}
scene = dict(approach_speed=0.5, accel=9.81, law={law!r}, stiffness={stiffness!r})
with {context}:
    if n:
        ca.contact_parameters(e_N=rng.uniform(0.2, 0.9, n), mass=rng.uniform(0.1, 2.0, n), **scene)
    else:
        ca.contact_parameters(e_N=0.5, mass=0.5, **scene)
t2, c2 = time.perf_counter(), time.process_time()
print(t1 - t0, t2 - t1, c2 - c1)
"""


def cpu_name():
    """The CPU's model name."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown cpu"


def first_call(law, n, cache, baseline=False):
    """(first-call wall s, its CPU s) of ``law`` on ``n`` scenes (0: one) in a fresh process.

    The CPU time (all the process's threads) is what a quiet machine's wall time would be, about.
    """
    stiffness = 1.0e8 if law.exponent == 1.5 else 1.0e5
    context = "firstcall.compiled_only()" if baseline else "contextlib.nullcontext()"
    code = PROGRAM.format(n=n, law=law.name, stiffness=stiffness, context=context)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": str(SRC)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    _, wall, cpu = map(float, out.stdout.split())
    return wall, cpu


def warm_cache(cache):
    """Fill ``cache`` by ``contactalpha warmup``; its wall time, s."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": str(SRC)}
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "contactalpha", "warmup"], env=env, capture_output=True, check=True)
    return time.perf_counter() - start


def _medians(runs):
    """(median wall, median CPU) of ``runs`` of (wall, CPU); NaNs for none."""
    if not runs:
        return math.nan, math.nan
    return tuple(statistics.median(x) for x in zip(*runs, strict=True))


def measure(repeat, baseline):
    """Rows ``(law, scenes, cold, warm, baseline)`` of median (wall, CPU) first-call s; the warm-up's s."""
    sys.path.insert(0, str(SRC))
    from contactalpha.laws import LAWS

    rows = []
    with tempfile.TemporaryDirectory() as warm:
        warmup_s = warm_cache(warm)
        for law in LAWS:
            for n in (0, BATCH):
                times = {"cold": [], "warm": [], "baseline": []}
                for _ in range(repeat):
                    with tempfile.TemporaryDirectory() as cold:
                        times["cold"].append(first_call(law, n, cold))
                    times["warm"].append(first_call(law, n, warm))
                    if baseline:
                        with tempfile.TemporaryDirectory() as cold:
                            times["baseline"].append(first_call(law, n, cold, baseline=True))
                med = {k: _medians(v) for k, v in times.items()}
                rows.append((law.name, n or 1, med["cold"], med["warm"], med["baseline"]))
                cells = " ".join(f"{w:6.2f}/{c:5.2f}" for w, c in med.values())
                print(f"{law.name:22s} {n or 1:6d} {cells}", flush=True)
    return rows, warmup_s


def table(rows, warmup_s, load_before, load_after):
    """The markdown block for docs/performance.md."""
    lines = [
        f"Measured on {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"{platform.system()}; load average {load_before:.1f} before and {load_after:.1f} after (the "
        "machine was shared with other sessions' jobs while it ran: on a quiet machine every time is "
        "lower). Wall time of the first `contact_parameters(..., law=NAME)` call in a fresh process "
        f"(import excluded), median; `contactalpha warmup` took {warmup_s:.1f} s (the compile time).",
        "",
        "Each cell is wall / CPU seconds; the CPU time is about what a quiet machine's wall time is.",
        "",
        "| law | scenes | cold cache | after `warmup` | old path (compile first) | old / cold (CPU) |",
        "|---|---|---|---|---|---|",
    ]

    def cell(wc):
        return "-" if math.isnan(wc[0]) else f"{wc[0]:.2f} / {wc[1]:.2f}"

    for name, n, cold, warm, base in rows:
        ratio = "-" if math.isnan(base[1]) else f"{base[1] / cold[1]:.1f}x"
        lines.append(f"| `{name}` | {n:,} | {cell(cold)} | {cell(warm)} | {cell(base)} | {ratio} |")
    return "\n".join(lines)


def fill_page(block, page=PAGE):
    """Put ``block`` between the first-call markers of ``page``."""
    text = page.read_text()
    pattern = re.compile(re.escape(START) + ".*?" + re.escape(END), flags=re.S)
    if not pattern.search(text):
        raise ValueError(f"{page} has no {START} ... {END} block")
    page.write_text(pattern.sub(lambda _: f"{START}\n{block}\n{END}", text))


def main(argv=None):
    """Run the benchmark and print its table (``--page``: also into docs/performance.md)."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=1, help="fresh processes per measurement (default 1)")
    p.add_argument("--no-baseline", action="store_true", help="skip the old path (it compiles every kernel)")
    p.add_argument("--page", action="store_true", help="fill the first-call block of docs/performance.md")
    args = p.parse_args(argv)
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores, {platform.platform()}")
    load_before = os.getloadavg()[0]
    print(f"load average before: {load_before:.2f}")
    print(f"{'law':22s} {'scenes':>6s} cold, warm, old path: wall/CPU s")
    rows, warmup_s = measure(args.repeat, not args.no_baseline)
    load_after = os.getloadavg()[0]
    print(f"warmup: {warmup_s:.1f} s; load average after: {load_after:.2f}")
    base = [b[1] / c[1] for _, _, c, _, b in rows if not math.isnan(b[1])]
    if base:
        print(f"old path / cold (CPU), median over laws and sizes: {statistics.median(base):.1f}x")
    block = table(rows, warmup_s, load_before, load_after)
    if args.page:
        fill_page(block)
    print(block)


if __name__ == "__main__":
    main()
