"""The workflow on a SLURM cluster: per-job overhead, scale, and faults (issue 14).

Needs a cluster (`.ci/slurm-cluster up` gives a one-node one).  Three parts, each writing a JSON file
under results/cluster/ (atomically, with version, commit, config and run time):

overhead  sbatch probes, each timed inside the job: submission to start, Python start, the package
          import, and the numba cache load (first solve in a process with a warm cache); plus the
          sbatch --wait round trip of an empty job.                      -> overhead.json
scale     the surface of a config (default workflow/configs/fine.yaml) through the cluster with
          workflow/profiles/slurm: wall time, points/s, per chunk job the time outside the solver
          (sacct start/end vs the chunk's own compute time); local points/s from one chunk solved
          in this process; the chunk count where overhead stops paying; a 1000 x 1000 estimate.
                                                                        -> scale.json
local     the same surface with local `snakemake -c2` (use --chunks 2): wall, points/s
                                                                        -> local_<K>chunks.json
faults    on the test config in 6 chunks: (a) scancel a running chunk job, with the profile
          (squeue status) and with the plugin's default sacct status; (b) kill -9 Snakemake while
          chunk jobs run, then rerun: which chunks were recomputed, temporaries left, bits equal
          to an uninterrupted run.                                       -> faults.json

Usage:  python benchmarks/bench_cluster.py overhead|scale|local|faults [--config PATH] [--chunks K]
Run with NUMBA_NUM_THREADS=1; timings depend on the machine's load (recorded).
"""

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "cluster"
PROFILE = ROOT / "workflow" / "profiles" / "slurm"
TEST_CONFIG = ROOT / "workflow" / "test-config.yaml"
FINE_CONFIG = ROOT / "workflow" / "configs" / "fine.yaml"
# The plugin's first status check comes 40 s after submission by default; 1 s for measurements.
FAST_STATUS = ["--slurm-init-seconds-before-status-checks", "1"]
SUBMITTED = re.compile(r"Job (\d+) has been submitted with SLURM jobid (\d+)")
# Repetitions of each overhead probe (the median is reported).
PROBE_REPEATS = 3
# Chunks of the fault runs: enough that some finish before Snakemake is killed.
FAULT_CHUNKS = 6
# A run still alive this long after the queue emptied waits on a job that no longer exists: hung
# (seconds; longer than the plugin's longest pause between status checks, 180 s).
HANG_LIMIT_S = 240
# How long a hung run gets to stop after each signal (seconds).
STOP_WAIT_S = 30
# Stop any single Snakemake run after this long (seconds).
RUN_LIMIT_S = 5400
PROBE_SCRIPT = """#!/bin/sh
t0=$(date +%s.%N)
python -c pass
t1=$(date +%s.%N)
python -c 'import contactalpha.paper.surface.compute'
t2=$(date +%s.%N)
python -c 'from contactalpha.paper.surface.compute import compute_surface; compute_surface([0.5], [0.2])'
t3=$(date +%s.%N)
echo "$t0 $t1 $t2 $t3"
"""


def machine():
    return {"cpus": os.cpu_count(), "load_average_1min": os.getloadavg()[0], "uname": os.uname().release}


def sh(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, check=True, **kw).stdout


def sacct(job_ids):
    """{job id: (state, submit, start, end)} with times as epoch seconds (SLURM's 1 s resolution)."""
    out = sh(["sacct", "-n", "-P", "-X", "-o", "JobID,State,Submit,Start,End", "-j", ",".join(job_ids)])
    rows = {}
    for line in out.splitlines():
        job, state, *stamps = line.split("|")
        times = [time.mktime(time.strptime(s, "%Y-%m-%dT%H:%M:%S")) for s in stamps]
        rows[job] = (state, *times)
    return rows


def snakemake(workdir, targets, *args, timeout=RUN_LIMIT_S):
    """Run Snakemake through the SLURM profile; (returncode, log, wall seconds)."""
    cmd = [sys.executable, "-m", "snakemake", *targets, "-s", str(ROOT / "Snakefile"), "-d", str(workdir)]
    t = time.perf_counter()
    done = subprocess.run([*cmd, *args], capture_output=True, text=True, timeout=timeout)
    return done.returncode, done.stdout + done.stderr, time.perf_counter() - t


def cluster_args(configfile):
    return ["--profile", str(PROFILE), *FAST_STATUS, "--configfile", str(configfile)]


def save(name, record, started):
    from contactalpha.io import write_json_atomic
    from contactalpha.provenance import result_attrs

    record = {
        **result_attrs(record.pop("config"), f"bench_cluster {name}"),
        "machine": machine(),
        "run_seconds": time.time() - started,
        **record,
    }
    path = write_json_atomic(OUT / f"{name}.json", record)
    print(f"wrote {path.relative_to(ROOT)}")
    return record


def overhead(args):
    started = time.time()
    probes = []
    with tempfile.TemporaryDirectory(prefix="bench_cluster_") as work:
        script = Path(work, "probe.sh")
        script.write_text(PROBE_SCRIPT)
        for i in range(PROBE_REPEATS):
            out = Path(work, f"probe{i}.out")
            t = time.time()
            job = sh(["sbatch", "--parsable", "--wait", "-o", str(out), str(script)]).strip()
            back = time.time()
            t0, t1, t2, t3 = map(float, out.read_text().split()[-4:])
            _, submit, start, end = sacct([job])[job]
            probes.append(
                {
                    "job": job,
                    "sbatch_wait_roundtrip_s": back - t,
                    "submit_to_script_start_s": t0 - t,
                    "script_s": t3 - t0,
                    "python_start_s": t1 - t0,
                    # Importing the surface module loads numba and the cached kernels' modules.
                    "import_s": t2 - t1 - (t1 - t0),
                    # The first solve's extra over an import alone: the kernels' cache load.
                    "first_solve_s": t3 - t2 - (t2 - t1),
                }
            )
        t = time.time()
        sh(["sbatch", "--parsable", "--wait", "-o", "/dev/null", "--wrap", "true"])
        empty = time.time() - t
    medians = {key: float(np.median([p[key] for p in probes])) for key in probes[0] if key != "job"}
    for key, value in medians.items():
        print(f"{key:40s} {value:7.2f} s (median of {PROBE_REPEATS})")
    print(f"{'empty job, sbatch --wait round trip':40s} {empty:7.2f} s")
    return save(
        "overhead",
        {
            "config": {"repeats": PROBE_REPEATS},
            "probes": probes,
            "median": medians,
            "empty_job_roundtrip_s": empty,
        },
        started,
    )


def local_rate(section, chunk, chunks):
    """Points per second of one chunk solved in this process (one thread, warm cache)."""
    from contactalpha.paper.surface.compute import compute_chunk, compute_surface, grid_from_config

    compute_surface([0.5], [0.2])  # load the kernels first: not part of the rate
    eps, xi = grid_from_config(section)
    t = time.perf_counter()
    ds = compute_chunk(eps, xi, chunk, chunks, **section["solver"])
    return ds.alpha.size / (time.perf_counter() - t), int(ds.alpha.size)


def surface_section(args):
    """The surface section of config.yaml updated by the --config file (and --chunks)."""
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    section = {**config["surface"], **yaml.safe_load(Path(args.config).read_text())["surface"]}
    if args.chunks:
        section["chunks"] = args.chunks
    return section


def local(args):
    """The same surface with local `snakemake -c2` (no cluster): wall time and points/s."""
    from contactalpha.paper.surface.compute import grid_from_config

    started = time.time()
    section = surface_section(args)
    eps, xi = grid_from_config(section)
    with tempfile.TemporaryDirectory(prefix="bench_cluster_local_") as work:
        configfile = Path(work, "config.yaml")
        configfile.write_text(yaml.safe_dump({"surface": section}, sort_keys=False))
        code, log, wall = snakemake(work, ["results/surface.h5"], "-c2", "--configfile", str(configfile))
        if code:
            sys.exit(f"local run failed:\n{log[-4000:]}")
    points = eps.size * xi.size
    print(f"local snakemake -c2, {section['chunks']} chunks: {wall:.1f} s wall, {points / wall:.0f} points/s")
    record = {"config": {"surface": section}, "points": points, "wall_s": wall, "points_per_s": points / wall}
    return save(f"local_{section['chunks']}chunks", record, started)


def scale(args):
    from contactalpha.io import load_surface, load_surface_chunk
    from contactalpha.paper.surface.compute import grid_from_config

    started = time.time()
    section = surface_section(args)
    chunks = section["chunks"]
    eps, xi = grid_from_config(section)
    points = eps.size * xi.size
    print(f"grid {eps.size} x {xi.size} = {points} points in {chunks} chunks; load {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory(prefix="bench_cluster_") as work:
        configfile = Path(work, "config.yaml")
        configfile.write_text(yaml.safe_dump({"surface": section}, sort_keys=False))
        code, log, wall = snakemake(work, ["results/surface.h5"], *cluster_args(configfile))
        if code:
            sys.exit(f"cluster run failed:\n{log[-4000:]}")
        jobs = chunk_jobs(log)
        times = sacct(list(jobs))
        done = {jobs[j]: j for j, row in times.items() if row[0] == "COMPLETED"}
        per_job = []
        for path in sorted(Path(work, "results/surface/chunks").glob("chunk_*.h5")):
            part = load_surface_chunk(path)
            job = done[int(part.attrs["chunk"])]
            _, submit, start, end = times[job]
            per_job.append(
                {
                    "chunk": int(part.attrs["chunk"]),
                    "job": job,
                    "points": int(part.alpha.size),
                    "compute_s": float(part.attrs["compute_seconds"]),
                    "queue_s": start - submit,
                    "job_s": end - start,
                    "outside_solver_s": (end - start) - float(part.attrs["compute_seconds"]),
                }
            )
        surface = load_surface(Path(work, "results/surface.h5"))
        failed = int((surface.status != 0).sum())
    compute = sum(j["compute_s"] for j in per_job)
    outside = float(np.median([j["outside_solver_s"] for j in per_job]))
    rate_local, sample = local_rate(section, 0, chunks)
    slots = int(sh(["sinfo", "-h", "-o", "%C"]).split("/")[-1])  # CPUs of the partition
    record = {
        "config": {"surface": section},
        "grid": [int(eps.size), int(xi.size)],
        "points": points,
        "chunks": chunks,
        "failed_points": failed,
        "cluster": {
            "slots": slots,
            "wall_s": wall,
            "points_per_s": points / wall,
            "solver_cpu_s": compute,
            "solver_points_per_cpu_s": points / compute,
            "median_job_outside_solver_s": outside,
            "jobs": per_job,
        },
        "local": {
            "sample_chunk_points": sample,
            "points_per_s_one_thread": rate_local,
            "estimated_wall_s_two_threads": points / (2 * rate_local),
        },
        # A chunk pays for its job while its solve takes longer than the job's fixed cost.
        "break_even_chunks": compute / outside,
        "estimate_1000x1000_per_node_s": {
            str(n): 1e6 / (points / compute) / (n * slots) + outside for n in (1, 4, 16, 64)
        },
    }
    print(f"cluster: {wall:.0f} s wall, {points / wall:.0f} points/s")
    print(f"solver: {points / compute:.0f} points per job-second")
    print(f"per job outside the solver (median): {outside:.1f} s")
    print(f"break-even: {compute / outside:.0f} chunks")
    print(f"local, one thread: {rate_local:.0f} points/s")
    return save("scale", record, started)


def chunk_jobs(log):
    """{SLURM job id: chunk} of the surface_chunk jobs in a Snakemake log (a retried chunk has several)."""
    chunk_of = dict(re.findall(r"jobid: (\d+)\n[^\[]*?wildcards: chunk=(\d+)", log))
    return {slurm: int(chunk_of[snake]) for snake, slurm in SUBMITTED.findall(log) if snake in chunk_of}


def wait_for(predicate, limit, step=0.2):
    end = time.time() + limit
    while time.time() < end:
        found = predicate()
        if found:
            return found
        time.sleep(step)
    return None


def running_chunk_job():
    queue = sh(["squeue", "-h", "-o", "%i|%T|%k"])
    for line in queue.splitlines():
        job, state, comment = line.split("|", 2)
        if state == "RUNNING" and comment.startswith("rule_surface_chunk"):
            return job
    return None


def surface_bytes(workdir):
    from contactalpha.io import load_surface

    ds = load_surface(Path(workdir, "results/surface.h5"))
    return {name: np.ascontiguousarray(ds[name].values).tobytes() for name in ds.variables}


def scancel_run(configfile, status_command):
    """Run the surface through the cluster and scancel the first chunk job seen running."""
    work = tempfile.mkdtemp(prefix="bench_cluster_fault_")
    cmd = [sys.executable, "-m", "snakemake", "results/surface.h5", "-s", str(ROOT / "Snakefile"), "-d", work]
    cmd += [*cluster_args(configfile), "--slurm-status-command", status_command]
    t = time.time()
    logfile = open(Path(work).parent / f"{Path(work).name}.log", "w+")  # a pipe could fill and block
    proc = subprocess.Popen(cmd, stdout=logfile, stderr=subprocess.STDOUT, text=True)
    job = wait_for(running_chunk_job, 600)
    subprocess.run(["scancel", job], check=True)
    hung, empty_since = False, None
    while proc.poll() is None:
        if sh(["squeue", "-h", "-o", "%i"]).split():
            empty_since = None
        elif empty_since is None:
            empty_since = time.time()
        elif time.time() - empty_since > HANG_LIMIT_S:
            hung = True
            break
        time.sleep(1.0)
    stopped_by = None
    if hung:  # Ctrl-C first (Snakemake would cancel its jobs), then SIGTERM, then SIGKILL
        for stop in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
            proc.send_signal(stop)
            try:
                proc.wait(timeout=STOP_WAIT_S)
                stopped_by = stop.name
                break
            except subprocess.TimeoutExpired:
                continue
    proc.wait()
    logfile.seek(0)
    log = logfile.read()
    logfile.close()
    return (
        work,
        {
            "status_command": status_command,
            "cancelled_job": job,
            "sacct_state": sacct([job])[job][0],
            "reported": f"SLURM-job '{job}' failed" in log,
            "retried": "Trying to restart job" in log,
            "hung_past_s": HANG_LIMIT_S if hung else None,
            "hung_run_stopped_by": stopped_by,
            "returncode": proc.returncode,
            "wall_s": time.time() - t,
        },
        log,
    )


def faults(args):
    started = time.time()
    section = yaml.safe_load(TEST_CONFIG.read_text())["surface"]
    section["chunks"] = FAULT_CHUNKS
    config_dir = Path(tempfile.mkdtemp(prefix="bench_cluster_cfg_"))
    configfile = config_dir / "config.yaml"
    base = yaml.safe_load(TEST_CONFIG.read_text())
    base["surface"] = section
    configfile.write_text(yaml.safe_dump(base, sort_keys=False))
    reference = Path(tempfile.mkdtemp(prefix="bench_cluster_ref_"))
    code, log, _ = snakemake(reference, ["results/surface.h5"], "-c2", "--configfile", str(configfile))
    assert code == 0, log[-3000:]
    ref = surface_bytes(reference)
    outcomes = {}

    work, squeue, _ = scancel_run(configfile, "squeue")
    squeue["bits_equal_reference"] = squeue["returncode"] == 0 and surface_bytes(work) == ref
    outcomes["scancel_chunk_profile_squeue"] = squeue
    print("scancel, squeue status:", squeue)

    work, sacct_run, _ = scancel_run(configfile, "sacct")
    if sacct_run["returncode"] != 0:  # the next run completes the surface
        code, log, _ = snakemake(work, ["results/surface.h5"], *cluster_args(configfile))
        sacct_run["rerun_returncode"] = code
    sacct_run["bits_equal_reference"] = surface_bytes(work) == ref
    outcomes["scancel_chunk_plugin_default_sacct"] = sacct_run
    print("scancel, sacct status:", sacct_run)

    # kill -9 Snakemake once two chunks are finished and others run; then the same command again.
    work = Path(tempfile.mkdtemp(prefix="bench_cluster_kill_"))
    cmd = [
        sys.executable,
        "-m",
        "snakemake",
        "results/surface.h5",
        "-s",
        str(ROOT / "Snakefile"),
        "-d",
        str(work),
    ]
    cmd += cluster_args(configfile)
    logfile = work.parent / f"{work.name}.first.log"
    with open(logfile, "w") as fh:
        proc = subprocess.Popen(cmd, stdout=fh, stderr=subprocess.STDOUT, text=True)
        chunk_dir = work / "results/surface/chunks"
        wait_for(lambda: len(list(chunk_dir.glob("chunk_*.h5"))) >= 2 and running_chunk_job(), 1800, 0.5)
        finished_before = {p.name: p.stat().st_mtime_ns for p in chunk_dir.glob("chunk_*.h5")}
        running = sh(["squeue", "-h", "-o", "%i"]).split()
        proc.kill()
        proc.wait()
    wait_for(lambda: not sh(["squeue", "-h", "-o", "%i"]).split(), 900, 1.0)  # orphaned jobs end
    after_orphans = {p.name: p.stat().st_mtime_ns for p in chunk_dir.glob("chunk_*.h5")}
    code, log, wall = snakemake(work, ["results/surface.h5"], *cluster_args(configfile))
    rerun_jobs = [f"chunk_{c}.h5" for c in re.findall(r"wildcards: chunk=(\d+)", log)]
    temporaries = [str(p.relative_to(work)) for p in (work / "results").rglob("*.tmp")]
    kill = {
        "chunks_done_before_kill": sorted(finished_before),
        "jobs_in_queue_at_kill": running,
        "chunks_present_after_orphans_ended": sorted(after_orphans),
        "rerun_returncode": code,
        "rerun_computed": sorted(rerun_jobs),
        "finished_chunks_recomputed": sorted(set(rerun_jobs) & set(finished_before)),
        "finished_chunks_untouched": all(
            (chunk_dir / n).stat().st_mtime_ns == m for n, m in finished_before.items()
        ),
        "temporaries_left": temporaries,
        "bits_equal_reference": code == 0 and surface_bytes(work) == ref,
        "rerun_wall_s": wall,
    }
    outcomes["kill_snakemake"] = kill
    print("kill -9 snakemake:", kill)
    return save("faults", {"config": {"surface": section}, "outcomes": outcomes}, started)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part", choices=["overhead", "scale", "local", "faults"])
    parser.add_argument("--config", default=str(FINE_CONFIG), help="scale, local: surface config")
    parser.add_argument("--chunks", type=int, default=None, help="scale, local: override surface.chunks")
    args = parser.parse_args()
    {"overhead": overhead, "scale": scale, "local": local, "faults": faults}[args.part](args)


if __name__ == "__main__":
    main()
