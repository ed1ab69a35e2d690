"""A failed job says why in its rule's log; a second run is told to wait, not to --unlock (issue 34, R8)."""

import fcntl
import os
import subprocess
import sys
from pathlib import Path

import pytest

from contactalpha.io import RUN_LOCK, other_run_alive

ROOT = Path(__file__).resolve().parents[2]
JOB = """
import sys
from contactalpha.io import script_logger
log = script_logger("job", sys.argv[1])
log.info("starting")
raise ValueError("boom at step 3")
"""


def test_a_jobs_uncaught_error_is_in_its_log_and_still_on_stderr(tmp_path):
    log = tmp_path / "logs" / "job.log"
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    run = subprocess.run([sys.executable, "-c", JOB, str(log)], env=env, capture_output=True, text=True)
    assert run.returncode == 1
    text = log.read_text()
    assert "job INFO: starting" in text and "job ERROR: uncaught exception" in text
    assert text.rstrip().endswith("ValueError: boom at step 3") and "Traceback" in text
    assert run.stderr.count("ValueError: boom at step 3") == 1  # Python's own report, once


def test_a_job_run_by_the_prefork_server_logs_its_error_too(tmp_path, monkeypatch):
    sys.path.insert(0, str(ROOT / "workflow" / "scripts"))
    try:
        import prefork
    finally:
        sys.path.remove(str(ROOT / "workflow" / "scripts"))
    script = tmp_path / "job.py"
    log = tmp_path / "job.log"
    script.write_text(JOB)
    monkeypatch.setattr(sys, "argv", [str(script), str(log)])
    monkeypatch.setattr(sys, "excepthook", sys.excepthook)  # the job's hook is undone afterwards
    assert prefork._run_script(str(script)) == 1
    assert log.read_text().rstrip().endswith("ValueError: boom at step 3")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="flock")
def test_a_second_run_is_told_to_wait_not_to_unlock(tmp_path):
    lock = tmp_path / RUN_LOCK
    lock.parent.mkdir(parents=True)
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # the first run, alive
    try:
        assert other_run_alive(tmp_path)
        cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(tmp_path)]
        cmd += ["--configfile", str(ROOT / "workflow" / "test-config.yaml"), "-c1", "results/surface.h5"]
        run = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=ROOT)
    finally:
        os.close(fd)
    out = run.stdout + run.stderr
    assert run.returncode == 1, out[-2000:]
    assert "another workflow run is alive in this directory" in out and "--unlock" in out
    assert "Do not use --unlock" in out and "LockException" not in out
    assert not (tmp_path / "results").exists()
    assert not other_run_alive(tmp_path)
