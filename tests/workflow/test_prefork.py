"""The pre-imported job server (workflow/scripts/prefork.py): jobs run in its forks as in their own."""

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import pytest

# Workflow machinery, beside the scripts that import it (as Snakemake's script jobs do).
SCRIPTS = Path(__file__).resolve().parents[2] / "workflow" / "scripts"
sys.path.insert(0, str(SCRIPTS))
import prefork  # noqa: E402

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the server runs on Linux only")

# A job script: reports where it runs, then does what its environment says.
SCRIPT = textwrap.dedent(
    """
    import atexit, json, os, signal, subprocess, sys, time
    sys.path.append('SCRIPTS_DIR')  # as Snakemake's preamble does
    from prefork import delegate

    delegate()
    import numpy as np
    import prefork as p

    info = {"ppid": os.getppid(), "pid": os.getpid(), "in_child": p._in_child, "cwd": os.getcwd(),
            "x": os.environ.get("X"), "argv": sys.argv[1:], "path0": sys.path[0],
            "random": float(np.random.random())}
    nested = subprocess.run([sys.executable, "-c", "import os; print(os.environ.get(%r))" % p.SOCKET_ENV],
                            capture_output=True, text=True)
    info["nested"] = nested.stdout.strip()
    print(json.dumps(info), flush=True)
    atexit.register(lambda: print("atexit ran", flush=True))
    action = os.environ.get("ACTION", "")
    if action == "exit3":
        sys.exit(3)
    if action == "message":
        sys.exit("a message from the job")
    if action == "raise":
        raise ValueError("boom in the job")
    if action == "interrupt":
        raise KeyboardInterrupt
    if action == "catch":  # a job that handles the signals itself: proves they reach it
        def caught(signum, frame):
            open(os.environ["MARKER"], "w").write(str(signum))
            sys.exit(7)
        for s in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
            signal.signal(s, caught)
    if action == "pool" and os.fork() == 0:  # a process pool's worker: outlives the job
        open(os.environ["MARKER"], "w").write(str(os.getpid()))
        time.sleep(60)
        os._exit(0)
    if action in ("sleep", "catch", "pool"):
        open(os.environ["PIDFILE"], "w").write(str(os.getpid()))
        time.sleep(60)
    """
).replace("SCRIPTS_DIR", str(SCRIPTS))


@pytest.fixture
def script(tmp_path):
    path = tmp_path / "job.py"
    path.write_text(SCRIPT)
    return path


@pytest.fixture(scope="module")
def server():
    """One server for the module's tests (its imports take a few seconds); its settings set meanwhile."""
    names = (prefork.SOCKET_ENV, prefork.PREFIX_ENV)
    before = {k: os.environ.pop(k) for k in names if k in os.environ}
    s = prefork.start_server()
    assert s is not None
    yield s
    prefork.stop_server(s)
    os.environ.update(before)


def run(script, cwd, action=""):
    env = {**os.environ, "X": "from the client", "ACTION": action}
    return subprocess.run(
        [sys.executable, str(script), "one", "two"],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
    )


def info(done):
    return json.loads(done.stdout.splitlines()[0])


def alive(pid):
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(") ")[1][0] != "Z"  # a zombie is gone
    except (FileNotFoundError, IndexError):
        return False


def wait_dead(pid, seconds=10.0):
    end = time.monotonic() + seconds
    while alive(pid) and time.monotonic() < end:
        time.sleep(0.05)
    return not alive(pid)


def test_a_job_runs_in_a_fork_with_the_clients_directory_environment_argv_and_streams(
    server, script, tmp_path
):
    cwd = tmp_path / "work"
    cwd.mkdir()
    done = run(script, cwd)
    assert done.returncode == 0, done.stderr
    got = info(done)
    assert got["in_child"] is True and got["ppid"] == server.pid  # a fork of the server
    assert got["cwd"] == str(cwd) and got["x"] == "from the client" and got["argv"] == ["one", "two"]
    assert got["nested"] == "None"  # the job's own subprocesses do not delegate


def test_a_job_in_a_fork_starts_as_a_fresh_process_would(server, script, tmp_path):
    first, second = run(script, tmp_path), run(script, tmp_path)
    assert info(first)["in_child"] and info(second)["in_child"]
    assert info(first)["path0"] == str(script.parent)  # `python script` puts the script's folder first
    assert info(first)["random"] != info(second)["random"]  # numpy's global generator seeded afresh
    assert first.stdout.splitlines()[-1] == "atexit ran"  # the job's exit handlers run


def test_without_a_server_the_script_runs_in_its_own_process(script, tmp_path, monkeypatch):
    monkeypatch.delenv(prefork.SOCKET_ENV, raising=False)
    done = run(script, tmp_path)
    got = info(done)
    assert done.returncode == 0 and got["in_child"] is False and got["ppid"] == os.getpid()
    assert got["x"] == "from the client" and got["argv"] == ["one", "two"]
    assert got["path0"] == str(script.parent) and done.stdout.splitlines()[-1] == "atexit ran"


def test_a_server_that_is_gone_is_reported_and_the_script_runs_here(script, tmp_path, monkeypatch):
    monkeypatch.setenv(prefork.SOCKET_ENV, str(tmp_path / "no-socket"))
    monkeypatch.setenv(prefork.PREFIX_ENV, sys.prefix)
    done = run(script, tmp_path)
    assert done.returncode == 0 and info(done)["in_child"] is False
    assert "no server at" in done.stderr and "running in this process" in done.stderr


def test_a_server_that_does_not_take_the_job_in_time_is_left(tmp_path, monkeypatch, capsys):
    listening = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)  # listens, never accepts
    listening.bind(str(tmp_path / "s"))
    listening.listen(1)
    monkeypatch.setenv(prefork.SOCKET_ENV, str(tmp_path / "s"))
    monkeypatch.setenv(prefork.PREFIX_ENV, sys.prefix)
    monkeypatch.setattr(prefork, "START_TIMEOUT", 0.5)
    import threading

    waiting = threading.Thread(
        target=prefork.delegate, kwargs={"script": str(tmp_path / "job.py")}, daemon=True
    )
    waiting.start()
    waiting.join(10)
    assert not waiting.is_alive()  # delegate returned: the job runs here
    assert "timed out" in capsys.readouterr().err
    listening.close()


def test_a_job_of_another_python_environment_runs_in_its_own_process(tmp_path, monkeypatch, capsys):
    # e.g. a conda env of --sdm conda: it would not reach the server's interpreter and libraries
    monkeypatch.setenv(prefork.SOCKET_ENV, str(tmp_path / "no-socket"))
    monkeypatch.setenv(prefork.PREFIX_ENV, "/another/python")
    prefork.delegate(script=str(tmp_path / "job.py"))
    assert capsys.readouterr().err == ""  # it did not even try to connect


@pytest.mark.parametrize(
    ("action", "status", "stderr"),
    [("exit3", 3, ""), ("message", 1, "a message from the job"), ("raise", 1, "ValueError: boom in the job")],
)
def test_exit_status_and_errors_are_the_jobs(server, script, tmp_path, action, status, stderr):
    done = run(script, tmp_path, action)
    assert info(done)["in_child"] is True
    assert done.returncode == status
    assert stderr in done.stderr
    if action == "raise":
        assert "Traceback" in done.stderr


def test_an_uncaught_keyboard_interrupt_ends_the_client_as_it_ends_python(server, script, tmp_path):
    done = run(script, tmp_path, "interrupt")
    assert info(done)["in_child"] is True
    assert done.returncode == -signal.SIGINT and "KeyboardInterrupt" in done.stderr


def _started(script, tmp_path, action):
    pidfile, marker = tmp_path / "child.pid", tmp_path / "marker"
    env = {**os.environ, "ACTION": action, "PIDFILE": str(pidfile), "MARKER": str(marker)}
    client = subprocess.Popen([sys.executable, str(script)], cwd=tmp_path, env=env, stdout=subprocess.PIPE)
    end = time.monotonic() + 30
    while not (pidfile.exists() and pidfile.read_text()) and time.monotonic() < end:
        time.sleep(0.05)
    child = int(pidfile.read_text())
    assert child != client.pid and alive(child)
    return client, child, marker


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGHUP])
def test_a_signal_to_the_client_reaches_the_job(server, script, tmp_path, sig):
    client, child, marker = _started(script, tmp_path, "catch")
    client.send_signal(sig)
    assert client.wait(timeout=30) == 7  # the job's own handler ran and set the status
    assert marker.read_text() == str(int(sig))
    assert wait_dead(child)


def test_a_killed_client_takes_its_child_along(server, script, tmp_path):
    client, child, _ = _started(script, tmp_path, "sleep")
    client.kill()
    client.wait(timeout=30)
    assert wait_dead(child)


def test_a_cancelled_job_ends_although_its_own_fork_lives_on(server, script, tmp_path):
    # A process pool's workers, forked from the job, must not keep the client waiting.
    client, child, marker = _started(script, tmp_path, "pool")
    worker = int(marker.read_text())
    try:
        client.send_signal(signal.SIGTERM)
        assert client.wait(timeout=30) == -signal.SIGTERM
        assert wait_dead(child) and alive(worker)
    finally:
        os.kill(worker, signal.SIGKILL)


def test_the_server_leaves_no_zombies(server, script, tmp_path):
    for _ in range(3):
        assert run(script, tmp_path).returncode == 0
    time.sleep(0.5)
    children = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().split(") ")[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[1]) == server.pid:
            children.append(fields[0])
    assert "Z" not in children


def test_the_server_dies_with_the_process_that_started_it_and_removes_its_socket(tmp_path):
    code = (
        f"import os, sys, time; sys.path.insert(0, {str(SCRIPTS)!r}); import prefork; "
        "s = prefork.start_server(); "
        "print(s.pid, os.environ[prefork.SOCKET_ENV], flush=True); time.sleep(60)"
    )
    env = {k: v for k, v in os.environ.items() if k not in (prefork.SOCKET_ENV, prefork.PREFIX_ENV)}
    owner = subprocess.Popen([sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, text=True)
    pid, socket_path = owner.stdout.readline().split()
    assert alive(int(pid)) and Path(socket_path).exists()
    owner.kill()
    owner.wait()
    assert wait_dead(int(pid))
    assert not Path(socket_path).parent.exists()


def test_stop_server_removes_the_socket_and_the_setting(monkeypatch):
    for name in (prefork.SOCKET_ENV, prefork.PREFIX_ENV):
        monkeypatch.delenv(name, raising=False)
    s = prefork.start_server()
    path = Path(os.environ[prefork.SOCKET_ENV])
    assert path.exists() and (path.parent.stat().st_mode & 0o777) == 0o700
    assert os.environ[prefork.PREFIX_ENV] == sys.prefix
    prefork.stop_server(s)
    assert not path.parent.exists() and prefork.SOCKET_ENV not in os.environ
    assert s.returncode is not None


def test_the_server_forks_from_one_thread(server, script, tmp_path):
    # fork() copies only the calling thread: a preloaded library that started threads (a BLAS
    # pool, numba's workers) would leave its locks held in every job.
    assert run(script, tmp_path).returncode == 0  # the preload is done
    assert len(os.listdir(f"/proc/{server.pid}/task")) == 1


def test_a_new_server_removes_the_sockets_of_killed_ones_only(server, script, tmp_path):
    # SIGKILL (a killed process group) leaves a socket no handler could remove.
    stale = Path(tempfile.mkdtemp(prefix=prefork.FOLDER_PREFIX))
    dead = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    dead.bind(str(stale / "socket"))
    dead.close()  # bound, never listening: refuses connections
    empty = Path(tempfile.mkdtemp(prefix=prefork.FOLDER_PREFIX))  # a server still starting
    live = Path(os.environ[prefork.SOCKET_ENV]).parent
    try:
        prefork.remove_stale_sockets()
        assert not stale.exists()
        assert empty.exists() and live.exists()
        old = time.time() - 2 * prefork.START_TIMEOUT
        os.utime(empty, (old, old))
        prefork.remove_stale_sockets()
        assert not empty.exists() and live.exists()
        done = run(script, tmp_path)  # the probes did not disturb the live server
        assert done.returncode == 0 and info(done)["in_child"] is True
    finally:
        shutil.rmtree(stale, ignore_errors=True)
        shutil.rmtree(empty, ignore_errors=True)
