"""How much of a default `snakemake -c2` run is the surface itself, and how much is overhead?

Runs the workflow on the default config.yaml in a fresh temporary directory, with a warm numba
cache (a warm-up process loads every kernel first), and prints

- the wall time of `snakemake -c2` (whole process, DAG to last job);
- the surface compute time recorded in the chunk files (sum over chunks, and the span from the
  first chunk's start to the last chunk's end);
- the baseline: the same grid in one `compute_surface` call in this process, 2 threads;
- overhead ratios: snakemake wall / chunk span, snakemake wall / baseline.

Usage:  python benchmarks/bench_workflow.py [--all] [--cores 2] [--refine N] [--chunks K]
Default targets are the surface stage's (surface.h5, Figs. 4 and 5, end-state map, summary);
--all runs `rule all`, i.e. every stage.  --refine N divides the eps and xi steps of the default
grid by N (about N^2 times the points) and shows that the overhead is a fixed cost, not a share.

--fresh times the main job as a new user meets it (issue 14, item 6): `git clone` of this
repository into a temporary folder (--rev: at that commit, e.g. an older version), its own
sources on PYTHONPATH, an empty numba cache (NUMBA_CACHE_DIR), then `snakemake -c<cores>`
there on its config.yaml (every stage).  It prints the wall time, the CPU time of all jobs,
the load average before and after (the box is shared: a load above the core count slows
everything), and each job's wall time from Snakemake's log, longest first.
"""

import argparse
import os
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time
from datetime import datetime
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
SURFACE_TARGETS = [
    "results/surface.h5",
    "results/summary.md",
    *(
        f"results/figures/{n}.{e}"
        for n in ("fig4_alpha_surface", "fig5_alpha_section", "end_states")
        for e in ("png", "pdf")
    ),
]


def cpu_name():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def warm_cache():
    """Load (and if needed compile) every kernel once, in a separate process."""
    code = (
        "from contactalpha.paper.surface.compute import compute_surface; "
        "compute_surface([0.05, 0.5], [0.0, 0.001, 0.5])"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def children_cpu():
    """User + system CPU seconds of the finished child processes (and theirs)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


# Snakemake's log: "[Mon Nov 23 08:51:14 2026]" before a job starts or ends, then
# "rule NAME:" / "localrule NAME:" ... "jobid: N" at its start, "Finished jobid: N" at its end.
STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ [\d:]+ \d{4})\]$")
RULE = re.compile(r"^(?:local)?rule (\w+):$")
JOBID = re.compile(r"^\s+jobid: (\d+)$")
FINISHED = re.compile(r"^Finished jobid: (\d+)")


def job_times(log):
    """(rule, start s, wall s) of each finished job in a Snakemake log, in start order."""
    stamp = rule = first = None
    started, out = {}, []
    for line in log.splitlines():
        if m := STAMP.match(line):
            stamp = datetime.strptime(" ".join(m.group(1).split()), "%a %b %d %H:%M:%S %Y")
            first = first or stamp
        elif m := RULE.match(line):
            rule = m.group(1)
        elif (m := JOBID.match(line)) and rule is not None:
            started[m.group(1)] = (rule, stamp)
            rule = None
        elif (m := FINISHED.match(line)) and m.group(1) in started:
            name, start = started.pop(m.group(1))
            out.append((name, (start - first).total_seconds(), (stamp - start).total_seconds()))
    return out


def fresh_clone_run(cores, rev=None):
    """`snakemake -c<cores>` in a fresh clone (at ``rev``) with a cold numba cache; prints the timings."""
    with tempfile.TemporaryDirectory(prefix="bench_fresh_") as work:
        clone, cache = Path(work, "clone"), Path(work, "numba-cache")
        subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
        if rev:
            subprocess.run(["git", "-C", str(clone), "checkout", "-q", rev], check=True)
        git = ["git", "-C", str(clone)]
        commit = subprocess.run([*git, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout
        env = {**os.environ, "PYTHONPATH": str(clone / "src"), "NUMBA_CACHE_DIR": str(cache)}
        cmd = [sys.executable, "-m", "snakemake", "-c", str(cores)]
        load0, cpu0, t = os.getloadavg(), children_cpu(), time.perf_counter()
        done = subprocess.run(cmd, cwd=clone, env=env, capture_output=True, text=True)
        wall, cpu, load1 = time.perf_counter() - t, children_cpu() - cpu0, os.getloadavg()
        if done.returncode:
            sys.exit(f"snakemake failed:\n{done.stderr[-3000:]}")
        dirty = subprocess.run([*git, "status", "--porcelain"], capture_output=True, text=True).stdout.strip()
        jobs = job_times(done.stdout + done.stderr)
    before, after = (" ".join(f"{x:.2f}" for x in load) for load in (load0, load1))
    print(f"fresh clone at {commit.strip()}, empty numba cache, snakemake -c{cores} (every stage)")
    print(f"load average (1, 5, 15 min) before: {before}, after: {after}")
    print(f"wall: {wall:.1f} s; CPU of snakemake and its jobs: {cpu:.1f} s ({cpu / wall:.2f} cores busy)")
    print(f"jobs: {len(jobs)}; files of the checkout the run changed: {dirty or 'none'}")
    print("job wall times (s), longest first, with each start after the first job's:")
    for name, start, seconds in sorted(jobs, key=lambda j: -j[2]):
        print(f"  {seconds:6.0f}  start {start:5.0f}  {name}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="run rule all (every stage), not only the surface")
    parser.add_argument("--fresh", action="store_true", help="every stage in a fresh clone, cold numba cache")
    parser.add_argument("--rev", default=None, help="with --fresh: the commit to check out (default HEAD)")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--refine", type=int, default=1, help="divide the grid steps by this")
    parser.add_argument("--chunks", type=int, default=None, help="surface.chunks (default: config.yaml)")
    args = parser.parse_args()
    if args.fresh:
        print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs")
        fresh_clone_run(args.cores, args.rev)
        return

    print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start")
    t = time.perf_counter()
    warm_cache()
    print(f"warm-up (numba cache load or compile): {time.perf_counter() - t:.1f} s")

    import numba

    from contactalpha.io import load_surface_chunk
    from contactalpha.paper.surface.compute import compute_surface, grid_from_config

    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    section = config["surface"]
    for axis in ("epsilon", "xi"):
        section[axis]["range"]["step"] /= args.refine
    if args.refine > 1:
        section["epsilon"]["range"]["start"] /= args.refine
    section["chunks"] = args.chunks or section["chunks"]
    eps, xi = grid_from_config(section)
    numba.set_num_threads(min(args.cores, numba.config.NUMBA_NUM_THREADS))
    t = time.perf_counter()
    compute_surface(eps, xi, **section["solver"])
    baseline = time.perf_counter() - t
    print(
        f"baseline: compute_surface on {eps.size} x {xi.size} points, one process, "
        f"{args.cores} threads: {baseline:.2f} s"
    )

    with tempfile.TemporaryDirectory(prefix="bench_workflow_") as work:
        configfile = Path(work, "bench-config.yaml")
        configfile.write_text(yaml.safe_dump(config))
        cmd = [sys.executable, "-m", "snakemake", *([] if args.all else SURFACE_TARGETS)]
        cmd += ["-s", str(ROOT / "Snakefile"), "-d", work, "-c", str(args.cores)]
        cmd += ["--configfile", str(configfile)]
        t = time.perf_counter()
        done = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t
        if done.returncode:
            sys.exit(f"snakemake failed:\n{done.stderr[-3000:]}")
        chunk_files = sorted(Path(work, "results/surface/chunks").glob("chunk_*.h5"))
        chunks = [load_surface_chunk(p) for p in chunk_files]
    compute = sum(c.attrs["compute_seconds"] for c in chunks)
    span = max(c.attrs["finished"] for c in chunks) - min(c.attrs["started"] for c in chunks)
    what = "rule all" if args.all else "surface targets"
    print(f"snakemake -c{args.cores} ({what}, {len(chunks)} chunk jobs): {wall:.2f} s wall")
    print(f"surface compute in the chunk files: {compute:.2f} s summed, {span:.2f} s first start to last end")
    print(f"fixed cost, snakemake wall - chunk span:      {wall - span:.1f} s")
    print(f"overhead ratio, snakemake wall / chunk span:  {wall / span:.1f}")
    print(f"overhead ratio, snakemake wall / baseline:    {wall / baseline:.1f}")
    print(f"share of the wall time spent computing the surface: {100 * span / wall:.0f} %")


if __name__ == "__main__":
    main()
