"""Run the workflow's script jobs in forks of one process that has already imported everything.

Workflow machinery, not part of the library: the Snakefile puts this folder on ``sys.path``, and
Snakemake puts it there for every script job (``from prefork import delegate``).  Linux only.
Whether it pays is measured, not assumed: ``benchmarks/bench_prefork.py`` times forced runs of
the workflow with the server and without it (``--no-hooks``), alternating.

A job of the main workflow spends 1.5-2 s of CPU before its first line of work: a Python
start, Snakemake's preamble, then numpy, xarray/pandas, numba, Matplotlib and the package.
There are about 25 jobs, on 2 cores.  So, on a local run, the Snakefile's ``onstart`` hook
starts one *server* (``start_server``) that imports all of that once (``PRELOAD``) and then
waits on a Unix socket.  Each script calls ``delegate()`` first: its process (the *client*,
still Snakemake's job process) sends its script path, working directory, environment and
standard streams to the server, which forks a *child* that runs the script; the client waits
and exits with the child's status.  Where no server runs (cluster jobs, ``--sdm conda`` or
container jobs, a script run by hand), in another Python environment than the server's, or
when the server does not take the job within ``START_TIMEOUT``, ``delegate()`` returns and
the script runs in its own process as before.  The results are the same bits either way.

Guarantees (tests/workflow/test_prefork.py):

- the child starts as ``python script`` would: the client's working directory, environment
  (less this module's settings), argv and stdin/stdout/stderr, the script's folder first on
  ``sys.path``, numpy's global generator seeded afresh, and its exit handlers run at the end;
- the client ends as that process would: exit status 0, ``SystemExit`` codes, 1 after an
  uncaught exception (its traceback on the job's stderr), killed by SIGINT after an uncaught
  ``KeyboardInterrupt``;
- a SIGTERM, SIGINT or SIGHUP sent to the client (Snakemake cancelling a job) reaches the
  child; a client killed outright takes its child along (the child watches the connection),
  and forks of the job (process pools) do not keep the client waiting;
- the server forks from a single thread, reaps its children, dies with the Snakemake process
  that started it (``PR_SET_PDEATHSIG``) removing its socket, and is stopped by the
  ``onsuccess``/``onerror`` hooks; the socket of a server killed outright (SIGKILL) is removed
  by the next one; the socket lives in a private directory (mode 700) and the server serves
  only its own user (``SO_PEERCRED``).

The server imports the package once, at the start of the run: an edit of the sources during a
run reaches the jobs of the next run (Snakemake's code versions are taken at the start too).
"""

import importlib
import json
import os
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path

# The environment variables that tell scripts where the server listens, and which Python it
# runs (a job in another environment, e.g. a conda env of --sdm conda, runs in its own process).
SOCKET_ENV = "CONTACTALPHA_PREFORK"
PREFIX_ENV = "CONTACTALPHA_PREFORK_PREFIX"
# What the server imports before it serves: the libraries every job imports, and the package.
PRELOAD = (
    "numpy",
    "scipy.optimize",
    "scipy.integrate",
    "xarray",
    "h5netcdf",
    "matplotlib.pyplot",
    "matplotlib.backends.backend_pdf",  # with fontTools: ~0.1 s at a job's first PDF
    "snakemake.iocontainers",
    "snakemake.logging",
    "contactalpha.config",
    "contactalpha.io",
    "contactalpha.plotting",
    "contactalpha.models",
    "contactalpha.engine.driver",
    "contactalpha.engine.solver",
)
# Prefix of the private folder (in the temporary directory) that holds a server's socket.
FOLDER_PREFIX = "contactalpha-prefork-"
# Seconds ``start_server`` waits for the server's socket, and a client for the server to take its
# job (the server's imports included), before they run without it.
START_TIMEOUT = 30.0
# Seconds the server waits for a connected client's request before dropping it.
REQUEST_TIMEOUT = 5.0
# The BLAS libraries' thread settings (``one_blas_thread``).
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
_HEADER = struct.Struct("!I")  # request length, child pid, exit status (256 + N: killed by signal N)
_SIGNALLED = 256
_PR_SET_PDEATHSIG = 1
_FORWARDED = (signal.SIGTERM, signal.SIGINT, signal.SIGHUP)

# True in a child of the server: ``delegate()`` then lets the script run.
_in_child = False


def one_blas_thread():
    """BLAS on one thread in this process and its children; call it before numpy loads.

    The jobs' numerics are numba kernels and small fits; Snakemake sets these variables to a
    rule's threads, and 2 BLAS threads on 2 cores made the refit's SVDs about 12x slower.
    """
    for var in BLAS_THREADS:
        os.environ[var] = "1"


# --- client ---------------------------------------------------------------------------------


def delegate(script=None):
    """Run this script in a fork of the server, if one is running, and exit with its status.

    Call it first in a workflow script.  Returns (and the script runs here) in a child of the
    server, when no server is set (``SOCKET_ENV``), when this is another Python environment than
    the server's, or when the server does not take the job within ``START_TIMEOUT`` seconds.
    """
    path = os.environ.get(SOCKET_ENV)
    if _in_child or not path or os.environ.get(PREFIX_ENV) != sys.prefix:
        return
    script = os.path.abspath(script or sys.argv[0])
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        sock.settimeout(START_TIMEOUT)
        sock.connect(path)
        body = json.dumps({"script": script, "cwd": os.getcwd(), "env": dict(os.environ), "argv": sys.argv})
        body = body.encode()
        socket.send_fds(sock, [_HEADER.pack(len(body))], [0, 1, 2])
        sock.sendall(body)
        pid = _read_int(sock)
        sock.settimeout(None)
    except OSError as err:  # a late child finds the connection closed and never runs the job
        sock.close()
        print(f"prefork: no server at {path} ({err}); running in this process", file=sys.stderr)
        return
    sys.exit(_wait_for_child(sock, pid))


def _wait_for_child(sock, pid):
    forwarded = []

    def forward(signum, frame):
        forwarded.append(signum)
        try:
            os.kill(pid, signum)
        except ProcessLookupError:
            pass

    for s in _FORWARDED:
        signal.signal(s, forward)
    try:
        status = _read_int(sock)
    except OSError:
        # The child died without a status: killed by a signal.  End the same way, if ours.
        if forwarded:
            _die_by(forwarded[-1])
        print(f"prefork: job process {pid} ended without an exit status", file=sys.stderr)
        return 1
    if status >= _SIGNALLED:  # the job ended as Python ends on an uncaught KeyboardInterrupt
        _die_by(status - _SIGNALLED)
    return status


def _die_by(signum):
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)


def _read_exact(sock, n):
    data = b""
    while len(data) < n:
        part = sock.recv(n - len(data))
        if not part:
            raise ConnectionError("connection closed")
        data += part
    return data


def _read_int(sock):
    return _HEADER.unpack(_read_exact(sock, _HEADER.size))[0]


# --- server ---------------------------------------------------------------------------------


def start_server(timeout=START_TIMEOUT):
    """Start a server for this process's jobs and set ``SOCKET_ENV``; returns its ``Popen``.

    Returns None (and the jobs run in their own processes) off Linux, or when the server does
    not listen within ``timeout`` seconds.
    """
    if not sys.platform.startswith("linux"):  # PR_SET_PDEATHSIG and SO_PEERCRED are Linux's
        return None
    remove_stale_sockets()
    folder = tempfile.mkdtemp(prefix=FOLDER_PREFIX)  # mode 700
    path = os.path.join(folder, "socket")
    cmd = [sys.executable, str(Path(__file__).resolve()), path, str(os.getpid())]
    # Its own session: a Ctrl-C meant for Snakemake does not reach it (onerror and the
    # parent-death signal stop it).
    server = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, start_new_session=True)
    server.socket_folder = folder
    try:
        _wait_until_listening(server, path, timeout)
    except TimeoutError as err:
        print(f"prefork: {err}; jobs run in their own processes", file=sys.stderr)
        stop_server(server)
        return None
    os.environ[SOCKET_ENV] = path
    os.environ[PREFIX_ENV] = sys.prefix
    return server


def remove_stale_sockets():
    """Remove the socket folders of servers that are gone (killed with SIGKILL, which no handler sees).

    A folder is stale when its socket refuses a connection (a live server takes it into its
    backlog even while it imports), or has no socket ``START_TIMEOUT`` after it was made.
    """
    for folder in Path(tempfile.gettempdir()).glob(FOLDER_PREFIX + "*"):
        try:
            made = folder.stat()
            if made.st_uid != os.getuid():
                continue
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
                probe.connect(str(folder / "socket"))
        except ConnectionRefusedError:
            shutil.rmtree(folder, ignore_errors=True)
        except FileNotFoundError:
            if time.time() - made.st_mtime > START_TIMEOUT:  # not a server still starting
                shutil.rmtree(folder, ignore_errors=True)
        except OSError:
            continue


def _wait_until_listening(server, path, timeout):
    end = time.monotonic() + timeout
    while not os.path.exists(path):
        if server.poll() is not None:
            raise TimeoutError(f"the server exited with status {server.returncode} before listening")
        if time.monotonic() > end:
            raise TimeoutError(f"the server did not listen within {timeout:g} s")
        time.sleep(0.01)


def stop_server(server):
    """Stop a server of ``start_server`` (None: nothing) and remove its socket."""
    os.environ.pop(SOCKET_ENV, None)
    os.environ.pop(PREFIX_ENV, None)
    if server is None:
        return
    server.terminate()
    server.wait()
    shutil.rmtree(server.socket_folder, ignore_errors=True)


def serve(path, parent_pid):
    """Listen on ``path``, import ``PRELOAD``, then fork one child per request (never returns)."""
    signal.signal(signal.SIGTERM, lambda signum, frame: _remove_and_exit(path))
    _die_with_parent(parent_pid)  # SIGTERM when the parent dies
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path + ".tmp")
    listener.listen(64)
    os.rename(path + ".tmp", path)  # clients queue in the backlog while the imports run
    one_blas_thread()
    for name in PRELOAD:
        importlib.import_module(name)
    _load_numba_registries()
    signal.signal(signal.SIGCHLD, _reap)
    while True:
        conn, _ = listener.accept()
        try:
            conn.settimeout(REQUEST_TIMEOUT)  # a stalled client does not hold up the others
            request, fds = _read_request(conn)
            conn.settimeout(None)
        except EOFError:
            conn.close()
            continue
        except (OSError, ValueError) as err:
            print(f"prefork: bad request ({err})", file=sys.stderr)
            conn.close()
            continue
        if os.fork() == 0:
            listener.close()
            _run_child(conn, request, fds)  # never returns
        conn.close()
        for fd in fds:
            os.close(fd)


def _remove_and_exit(path):
    for remove in (os.unlink, os.rmdir):  # the socket, then its folder (``start_server``'s)
        try:
            remove(path)
        except OSError:
            pass
        path = os.path.dirname(path)
    os._exit(0)


def _load_numba_registries():
    """Numba's typing and lowering tables, which its first cache load in a process builds (~0.5 s)."""
    from numba.core.registry import cpu_target

    cpu_target.typing_context.refresh()
    cpu_target.target_context.refresh()


def _die_with_parent(parent_pid):
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    if os.getppid() != parent_pid:  # the parent died before prctl
        sys.exit(0)


def _reap(signum, frame):
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def _read_request(conn):
    uid = struct.unpack("3i", conn.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, 12))[1]
    if uid != os.getuid():
        raise ValueError(f"peer uid {uid} is not this user's")
    head, fds, _, _ = socket.recv_fds(conn, _HEADER.size, 3)
    if not head and not fds:
        raise EOFError  # a probe of remove_stale_sockets: it connects and closes
    if len(head) != _HEADER.size or len(fds) != 3:
        for fd in fds:
            os.close(fd)
        raise ValueError("expected a length and 3 file descriptors")
    return json.loads(_read_exact(conn, _HEADER.unpack(head)[0])), fds


def _run_child(conn, request, fds):
    """The forked child: become the client's process, run its script, report (never returns)."""
    global _in_child
    status = 1
    try:
        _in_child = True
        for s in (signal.SIGCHLD, signal.SIGTERM, signal.SIGHUP):
            signal.signal(s, signal.SIG_DFL)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
            os.close(fd)
        os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        for var in (SOCKET_ENV, PREFIX_ENV):  # the job's own subprocesses run in their own processes
            os.environ.pop(var, None)
        script = request["script"]
        sys.argv = list(request["argv"])
        sys.path[0] = os.path.dirname(script)  # as `python script` sets it
        if "numpy" in sys.modules:  # a fresh process seeds numpy's global generator afresh
            sys.modules["numpy"].random.seed()
        # The job's own forks (process pools) must not hold the client's connection open: the
        # client waits for it to close when the job dies.
        os.register_at_fork(after_in_child=conn.close)
        conn.sendall(_HEADER.pack(os.getpid()))  # fails if the client gave up waiting: no job
        threading.Thread(target=_die_without_client, args=(conn,), daemon=True).start()
        status = _run_script(script)
        for stream in (sys.stdout, sys.stderr):
            stream.flush()
        conn.sendall(_HEADER.pack(status))
    finally:
        os._exit(status & 0xFF)


def _die_without_client(conn):
    conn.recv(1)  # the client sends nothing more: this returns when it is gone
    os.kill(os.getpid(), signal.SIGKILL)


def _run_script(script):
    """Run ``script`` as ``__main__`` and return its exit status as Python's own exit would be."""
    import atexit
    import runpy

    try:
        runpy.run_path(script, run_name="__main__")
        status = 0
    except SystemExit as exit_:
        status = _exit_status(exit_.code)
    except KeyboardInterrupt:  # Python ends by SIGINT then; the client does
        traceback.print_exc()
        status = _SIGNALLED + signal.SIGINT
    except BaseException:  # the job's own error: reported as Python reports it (its hook), status 1
        sys.excepthook(*sys.exc_info())
        status = 1
    atexit._run_exitfuncs()  # the job's and its imports' exit handlers (logging's among them)
    return status


def _exit_status(code):
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    print(code, file=sys.stderr)
    return 1


if __name__ == "__main__":
    # Through the module ``prefork`` (this file's folder is first on sys.path), not this __main__
    # copy: the children's scripts import ``prefork`` and must see its _in_child flag.
    import prefork

    prefork.serve(sys.argv[1], int(sys.argv[2]))
