"""Does the workflow's job server (workflow/scripts/prefork.py) pay?  Forced runs with it and without.

Run: ``python benchmarks/bench_prefork.py [--rounds 2] [--cores 2]``.
In a fresh clone of this repository (its own sources on PYTHONPATH, a numba cache of its own
that a first, unmeasured run fills), runs ``snakemake -c<cores> --forceall`` alternately with
the server and with ``--no-hooks`` (the Snakefile's ``onstart`` hook starts the server; without
hooks every script job imports numpy, xarray, numba, Matplotlib and the package itself).
Prints per run the wall time, the CPU time of the whole process tree (the server and its forks
included: the server is waited for) and the load average, then the medians and their ratios.
"""

import argparse
import os
import platform
import resource
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def timed_run(work, env, args):
    """(wall s, CPU s of the children) of one snakemake run in ``work``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    clock = time.perf_counter()
    subprocess.run(["snakemake", *args], cwd=work, env=env, check=True, capture_output=True)
    wall = time.perf_counter() - clock
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--cores", type=int, default=2)
    args = p.parse_args(argv)
    machine = platform.processor() or platform.machine()
    print(f"machine: {machine}, {os.cpu_count()} cores, {platform.platform()}")
    with tempfile.TemporaryDirectory(prefix="bench_prefork_") as tmp:
        work = Path(tmp) / "clone"
        subprocess.run(["git", "clone", "-q", str(ROOT), str(work)], check=True)
        env = {**os.environ, "PYTHONPATH": str(work / "src"), "NUMBA_CACHE_DIR": str(Path(tmp) / "numba")}
        base = [f"-c{args.cores}", "-q"]
        timed_run(work, env, base)  # results and the numba cache, unmeasured
        runs = {"server": [], "no server": []}
        for _ in range(args.rounds):
            for label, extra in (("server", []), ("no server", ["--no-hooks"])):
                load = os.getloadavg()[0]
                wall, cpu = timed_run(work, env, [*base, "--forceall", *extra])
                runs[label].append((wall, cpu))
                print(f"{label:10s} wall {wall:7.1f} s  CPU {cpu:7.1f} s  (load before {load:.2f})")
    med = {
        k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in runs.items()
    }
    (ws, cs), (wn, cn) = med["server"], med["no server"]
    print(f"median wall: server {ws:.1f} s, no server {wn:.1f} s (no server / server {wn / ws:.2f})")
    print(f"median CPU:  server {cs:.1f} s, no server {cn:.1f} s (no server / server {cn / cs:.2f})")


if __name__ == "__main__":
    main()
