"""A run killed at any point resumes with the same command and gives the same bits (issue 15, item 4).

Each test starts the workflow on workflow/test-config.yaml in a temporary directory, in its own
process group, waits for a point of the run (seen in the file system), signals the whole group as a
terminal (Ctrl-C) or ``kill -9`` would, then runs the same command once more.  The surface must then
hold exactly the data of an uninterrupted computation, with no lock or temporary file left.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

from contactalpha.io import TMP_TAG, load_surface
from contactalpha.paper.surface.compute import VARIABLES, compute_surface, grid_from_config

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
TEST_CONFIG = ROOT / "workflow" / "test-config.yaml"
TARGET = "results/surface.h5"
CHUNK0 = "results/surface/chunks/chunk_0.h5"
# The file-system poll that catches a point of the run: fast enough to land between a job's rename
# of its output and Snakemake's record of the job (the job's interpreter takes ~0.1 s to exit).
POLL_SECONDS = 0.002
RUN_TIMEOUT = 600
# Ctrl-C presses at most, 0.2 s apart, until the run stops (see interrupt_when).
CTRL_C_PRESSES = 5


def command(workdir):
    """The one documented command (here with the test config and a single target)."""
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(workdir)]
    return cmd + ["--configfile", str(TEST_CONFIG), "-c2", TARGET]


def interrupt_when(workdir, point, sig):
    """Start the run, wait until ``point(workdir)`` holds, send ``sig`` to its process group."""
    log = open(workdir / "interrupted.log", "w")  # noqa: SIM115 (closed below)
    # A terminal's Ctrl-C reaches a run whose SIGINT is the default; a test run started in the
    # background (``cmd &``, nohup) inherits SIGINT ignored, and Python keeps it so: reset it.
    proc = subprocess.Popen(
        command(workdir), stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    deadline = time.monotonic() + RUN_TIMEOUT
    try:
        while not point(workdir):
            assert proc.poll() is None, "the run ended first: " + (workdir / "interrupted.log").read_text()
            assert time.monotonic() < deadline, "the point was never reached"
            time.sleep(POLL_SECONDS)
        os.killpg(proc.pid, sig)
        if sig == signal.SIGINT:
            # Snakemake drops a Ctrl-C that lands while it writes a log line (its log handler
            # swallows KeyboardInterrupt, snakemake/logging.py); a user presses again.
            for _ in range(CTRL_C_PRESSES - 1):
                try:
                    proc.wait(timeout=0.2)
                    break
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, sig)
        proc.wait(timeout=RUN_TIMEOUT)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        log.close()
    assert proc.returncode != 0
    return proc.returncode


def resume(workdir):
    done = subprocess.run(command(workdir), capture_output=True, text=True, timeout=RUN_TIMEOUT)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return done.stdout + done.stderr


def leftovers(workdir):
    """Lock files of Snakemake and temporary files of write_atomic left in ``workdir``."""
    locks = workdir / ".snakemake" / "locks"
    found = sorted(locks.glob("*.lock")) if locks.is_dir() else []
    return found + sorted((workdir / "results").rglob(f".*.{TMP_TAG}-*.tmp"))


@pytest.fixture(scope="module")
def uninterrupted():
    """The test surface computed in one call, without the workflow."""
    section = yaml.safe_load(TEST_CONFIG.read_text())["surface"]
    eps, xi = grid_from_config(section)
    return compute_surface(eps, xi, **section["solver"])


def assert_same_surface(workdir, uninterrupted):
    ds = load_surface(workdir / TARGET)
    np.testing.assert_array_equal(ds.epsilon.values, uninterrupted.epsilon.values)
    np.testing.assert_array_equal(ds.xi.values, uninterrupted.xi.values)
    for name in VARIABLES:
        got, want = ds[name].values, uninterrupted[name].values
        assert got.dtype == want.dtype, name
        assert got.tobytes() == want.tobytes(), name  # bit for bit, NaN included


def started(workdir):
    """Snakemake has locked the directory and marked a job's outputs incomplete: jobs are running."""
    incomplete = workdir / ".snakemake" / "incomplete"
    return incomplete.is_dir() and any(incomplete.iterdir())


def chunk_renamed(workdir):
    """Chunk 0 is in place, and its job is not yet recorded (the window of the issue's failure)."""
    return (workdir / CHUNK0).exists()


def chunk_half_written(workdir):
    """write_atomic's temporary file of chunk 0 exists: the kill lands inside the write."""
    return any((workdir / CHUNK0).parent.glob(f".chunk_0.h5.{TMP_TAG}-*.tmp"))


def merged(workdir):
    return (workdir / TARGET).exists()


def test_kill_9_after_an_output_is_renamed_resumes_with_the_same_command(tmp_path, uninterrupted):
    interrupt_when(tmp_path, chunk_renamed, signal.SIGKILL)
    # The state the issue found: the output is complete, Snakemake still marks it incomplete and
    # its lock is left behind.  Before the fix the same command stopped on the lock, and after
    # `--unlock` with IncompleteFilesException.
    assert (tmp_path / CHUNK0).exists()
    assert any((tmp_path / ".snakemake" / "incomplete").iterdir())
    assert any((tmp_path / ".snakemake" / "locks").glob("*.lock"))
    log = resume(tmp_path)
    assert "IncompleteFilesException" not in log and "LockException" not in log
    assert_same_surface(tmp_path, uninterrupted)
    assert leftovers(tmp_path) == []


def test_ctrl_c_resumes_with_the_same_command(tmp_path, uninterrupted):
    interrupt_when(tmp_path, started, signal.SIGINT)
    assert not (tmp_path / TARGET).exists()
    resume(tmp_path)
    assert_same_surface(tmp_path, uninterrupted)
    assert leftovers(tmp_path) == []


@pytest.mark.slow
@pytest.mark.parametrize("point", [started, chunk_half_written, merged], ids=lambda f: f.__name__)
def test_kill_9_at_any_point_resumes_bit_for_bit(tmp_path, uninterrupted, point):
    interrupt_when(tmp_path, point, signal.SIGKILL)
    resume(tmp_path)
    assert_same_surface(tmp_path, uninterrupted)
    assert leftovers(tmp_path) == []
    again = subprocess.run([*command(tmp_path), "-n"], capture_output=True, text=True, timeout=RUN_TIMEOUT)
    assert "Nothing to be done" in again.stdout + again.stderr
