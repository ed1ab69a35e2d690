"""Benchmark of ``contactalpha ... --help``: the CPU time of each help against Python's own start.

Run: ``python benchmarks/bench_help.py`` (``--repeat N``, default 5).  Each measurement is a fresh
process, ``python -m contactalpha [SUBCOMMAND] --help``, its user + system CPU seconds (the child's
``getrusage``), the median over the repeats, beside the baseline ``python -c pass``.  The parser
imports no kernel (``cli``'s docstring), so a help costs about what Python's start does.
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SUBCOMMANDS = ("", "alpha", "impact", "scene", "check-config", "params", "hertz", "export-c", "warmup",
               "calibrate", "tune")  # fmt: skip


def cpu_seconds(args):
    """User + system CPU seconds of one run of ``python ARGS`` (src/ first on the path)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    subprocess.run([sys.executable, *args], env=env, stdout=subprocess.DEVNULL, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main(argv=None):
    """Print the median CPU seconds of each help and of ``python -c pass``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    repeat = parser.parse_args(argv).repeat
    base = statistics.median(cpu_seconds(["-c", "pass"]) for _ in range(repeat))
    print(f"{'command':34s} CPU s (median of {repeat})")
    print(f"{'python -c pass':34s} {base:.3f}")
    for name in SUBCOMMANDS:
        args = ["-m", "contactalpha", *([name] if name else []), "--help"]
        cpu = statistics.median(cpu_seconds(args) for _ in range(repeat))
        label = " ".join(["contactalpha", *([name] if name else []), "--help"])
        print(f"{label:34s} {cpu:.3f}   (+{cpu - base:.3f})")


if __name__ == "__main__":
    main()
