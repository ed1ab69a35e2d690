"""One row of a twin-run row kernel is bounded in time (issue 44, S7b), tested on the stand-in path itself."""

import signal
import time

import numpy as np
from numba import njit

from contactalpha.engine import firstcall, threads
from contactalpha.laws import solve
from contactalpha.scene.threshold import critical_speed


class _Hung(BaseException):  # not an Exception: the twin's own handler must not swallow it
    pass


def _recorded_rows(monkeypatch):
    """Every ``damping_rows`` call of ``critical_speed(0.5, 0.5, 1e5, 9.81, hunt_crossley_linear)``."""
    calls = []
    real = threads.interpret_rows

    def spy(kernel, n, args):
        if kernel is solve.damping_rows:
            calls.append((n, tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)))
        return real(kernel, n, args)

    monkeypatch.setattr(threads, "interpret_rows", spy)
    v = critical_speed(0.5, 0.5, 1e5, 9.81, law="hunt_crossley_linear")
    monkeypatch.undo()
    return v, calls


def test_a_slow_row_of_the_python_twin_stops_at_the_budget_and_runs_compiled(monkeypatch):
    v, calls = _recorded_rows(monkeypatch)
    # The row of the largest load (A = 1e6): minutes as Python, where the compiled kernel takes ms.
    n, args = max(calls, key=lambda call: float(call[1][3][0]))
    assert float(args[3][0]) > 1e5
    fresh = firstcall.twin_rows(njit(solve.damping_rows.py_func))  # never compiled, never cached

    def hung(*_):
        raise _Hung

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(30)
    clock = time.perf_counter()
    try:
        done = firstcall.interpret_rows(fresh, n, args)  # the stand-in path, as on a cold cache
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    seconds = time.perf_counter() - clock
    assert done == 0 and seconds < 3.0 * firstcall.INTERPRET_BUDGET_S
    assert firstcall._ROWS[fresh].done  # from now on this kernel runs compiled
    assert np.isfinite(v) and v > 0.0


def test_run_bounded_returns_or_stops_and_leaves_nothing_pending():
    assert firstcall.run_bounded(lambda x: x + 1, (1,), 1.0) == 2
    clock = time.perf_counter()
    try:
        firstcall.run_bounded(lambda: [None for _ in iter(int, 1)], (), 0.2)  # runs forever
    except firstcall.TwinOverrun:
        stopped = time.perf_counter() - clock
    assert 0.2 <= stopped < 2.0
    # A result just in time: no exception arrives later.
    for _ in range(50):
        firstcall.run_bounded(sum, (range(1000),), 1e-4)
    time.sleep(0.05)
    assert sum(range(10)) == 45
