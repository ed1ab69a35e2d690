"""The workflow through a real SLURM cluster (`.ci/slurm-cluster up`, which `.ci/run` starts).

Checks that the surface chunks go through sbatch, that a chunk job cancelled while it runs is
reported and retried (the profile's `retries`), that `results/surface.h5` then holds the same bits
as a local `snakemake -c2` run of the same config, and that a job failing on the cluster ends the
run as failed instead of being waited on.  Skips with the reason where no cluster answers, except
under CI=true, where it fails.
"""

import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import contactalpha

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
TEST_CONFIG = ROOT / "workflow" / "test-config.yaml"
PROFILE = ROOT / "workflow" / "profiles" / "slurm"
# The plugin waits 40 s before its first status check by default; 1 s keeps the test short.
FAST_STATUS = ["--slurm-init-seconds-before-status-checks", "1"]
# A run that waits on a lost or failed job instead of ending is stopped here and fails the test.
RUN_TIMEOUT_S = 900
SUBMITTED = re.compile(r"submitted with SLURM jobid (\d+)")
# Attributes that define the surface (not the timings and history, which differ run to run).
DEFINING_ATTRS = ("config", "solver", "tol", "rtol", "atol", "max_steps", "chunks", "contactalpha_version")


def cluster_problem():
    """None where a SLURM cluster with accounting answers here, else the reason why not."""
    for command in ("sbatch", "sacct", "sinfo", "scancel"):
        if shutil.which(command) is None:
            return f"{command} not found (bring a cluster up with: .ci/slurm-cluster up)"
    nodes = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True, timeout=30)
    if nodes.returncode != 0 or not set(nodes.stdout.split()) & {"idle", "mix", "alloc"}:
        return f"no usable SLURM node: sinfo says {(nodes.stdout + nodes.stderr).strip()!r}"
    acct = subprocess.run(["sacct", "-n", "-X"], capture_output=True, text=True, timeout=30)
    if acct.returncode != 0:
        return f"sacct fails (the executor plugin needs accounting): {acct.stderr.strip()!r}"
    return None


@pytest.fixture(scope="module")
def cluster():
    problem = cluster_problem()
    if problem is None:
        return
    if os.environ.get("CI") == "true":
        pytest.fail(f"CI=true but no SLURM cluster: {problem}")
    pytest.skip(problem)


def snakemake(workdir, *args, snakefile=ROOT / "Snakefile", check=True):
    """Run Snakemake in workdir; (returncode, log text)."""
    cmd = [sys.executable, "-m", "snakemake", "-s", str(snakefile), "-d", str(workdir), *args]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=RUN_TIMEOUT_S, cwd=workdir)
    log = done.stdout + done.stderr
    if check:
        assert done.returncode == 0, log[-4000:]
    return done.returncode, log


def job_states(job_ids):
    """SLURM's accounting record of each job: {job id: (state, exit code)}."""
    cmd = ["sacct", "-n", "-P", "-X", "-o", "JobID,State,ExitCode", "-j", ",".join(job_ids)]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=30, check=True).stdout
    rows = [line.split("|") for line in out.splitlines() if line]
    return {job: (state.split()[0], code) for job, state, code in rows}


def cancel_when_running(comment, found, stop):
    """Watch the queue and scancel the first running job whose comment is `comment`."""
    while not stop.is_set():
        queue = subprocess.run(["squeue", "-h", "-o", "%i|%T|%k"], capture_output=True, text=True)
        for line in queue.stdout.splitlines():
            job, state, job_comment = line.split("|", 2)
            if state == "RUNNING" and job_comment == comment:
                subprocess.run(["scancel", job], check=True)
                found.append(job)
                return
        time.sleep(0.2)


@pytest.fixture(scope="module")
def runs(cluster, tmp_path_factory):
    """The surface of the test config through SLURM (chunk 0 cancelled once midway), and locally."""
    on_cluster = tmp_path_factory.mktemp("slurm")
    cancelled, stop = [], threading.Event()
    watcher = threading.Thread(
        target=cancel_when_running, args=("rule_surface_chunk_wildcards_0", cancelled, stop), daemon=True
    )
    watcher.start()
    try:
        _, cluster_log = snakemake(
            on_cluster, "results/surface.h5", "--profile", str(PROFILE), *FAST_STATUS,
            "--configfile", str(TEST_CONFIG),
        )  # fmt: skip
    finally:
        stop.set()
        watcher.join()
    local = tmp_path_factory.mktemp("local")
    _, local_log = snakemake(local, "results/surface.h5", "-c2", "--configfile", str(TEST_CONFIG))
    return {"cluster": on_cluster, "cluster_log": cluster_log, "cancelled": cancelled,
            "local": local, "local_log": local_log}  # fmt: skip


def test_chunks_went_through_sbatch(runs):
    job_ids = SUBMITTED.findall(runs["cluster_log"])
    # The numba warm-up's two parts and two chunks, plus the resubmission of the cancelled chunk;
    # the merge is a local rule.
    assert len(job_ids) == 5, runs["cluster_log"][-4000:]
    states = sorted(state for state, _ in job_states(job_ids).values())
    assert states == ["CANCELLED", *["COMPLETED"] * 4]
    assert "SLURM jobid" not in runs["local_log"]


def test_a_cancelled_chunk_is_reported_and_retried(runs):
    assert runs["cancelled"], "chunk 0 was never seen running, so it was not cancelled"
    (job,) = runs["cancelled"]
    assert job_states([job])[job][0] == "CANCELLED"
    assert f"SLURM-job '{job}' failed, SLURM status is: 'CANCELLED'" in runs["cluster_log"]
    assert "Trying to restart job" in runs["cluster_log"]
    assert (runs["cluster"] / "results" / "surface" / "chunks" / "chunk_0.h5").exists()


def test_surface_is_bit_identical_to_a_local_run(runs):
    on_cluster = contactalpha.load_surface(runs["cluster"] / "results" / "surface.h5")
    local = contactalpha.load_surface(runs["local"] / "results" / "surface.h5")
    assert sorted(on_cluster.variables) == sorted(local.variables)
    for name in local.variables:
        a, b = on_cluster[name].values, local[name].values
        assert a.dtype == b.dtype and a.shape == b.shape, name
        assert np.ascontiguousarray(a).tobytes() == np.ascontiguousarray(b).tobytes(), name
    for key in DEFINING_ATTRS:
        assert on_cluster.attrs[key] == local.attrs[key], key
    assert int((local.status != 0).sum()) == 0 and local.alpha.size == 12


FAILING_SNAKEFILE = """
rule fails:
    output: "never.txt"
    shell: "echo 'this job fails on purpose' >&2; exit 3"
"""


def test_a_job_failing_on_the_cluster_is_reported_not_waited_on(cluster, tmp_path):
    snakefile = tmp_path / "Snakefile"
    snakefile.write_text(FAILING_SNAKEFILE)
    # No retry here (the cancelled chunk above tests the profile's retries): one job, half the time.
    args = ["--profile", str(PROFILE), *FAST_STATUS, "--retries", "0"]
    code, log = snakemake(tmp_path, *args, snakefile=snakefile, check=False)
    assert code != 0
    job_ids = SUBMITTED.findall(log)
    assert len(job_ids) == 1, log[-4000:]
    assert {state for state, _ in job_states(job_ids).values()} == {"FAILED"}
    assert "Error in rule fails" in log and "SLURM status is: 'FAILED'" in log
    for job in job_ids:  # the failure is the rule's own, seen in the job's SLURM log
        (job_log,) = (tmp_path / ".snakemake" / "slurm_logs").rglob(f"{job}.log")
        assert "this job fails on purpose" in job_log.read_text()
    assert not (tmp_path / "never.txt").exists()
