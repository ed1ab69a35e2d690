"""Stage lines on stderr for long work: silent for the first ``after`` seconds, then one line per stage.

``Progress`` is handed to long computations (``calibrate``, an engine's refinement) as a callable
that they call with the name of each stage as it begins.  Nothing is printed while the work is
short; once it has run ``after`` seconds the current stage is printed (by a timer), and every
later stage as it begins, each with the seconds since the start.
"""

import sys
import threading
import time

# Seconds of work before the first line.
AFTER_S = 2.0


class Progress:
    """A stage reporter; use it as a context manager (the timer stops on exit).

    Parameters
    ----------
    label : str
        What runs (the start of every line).
    after : float
        Seconds of silence before the first line.
    stream : file, optional
        Where the lines go (default ``sys.stderr``).
    """

    def __init__(self, label, after=AFTER_S, stream=None):
        self.label = label
        self.stream = stream
        self.start = time.perf_counter()
        self.stage = "starting"
        self.shown = False
        self._lock = threading.Lock()
        self._timer = threading.Timer(after, self._show)
        self._timer.daemon = True
        self._timer.start()

    def __call__(self, stage):
        """Stage ``stage`` begins (printed once the work has run ``after`` seconds)."""
        with self._lock:
            self.stage = stage
            if self.shown:
                self._print()

    def _show(self):
        with self._lock:
            self.shown = True
            self._print()

    def _print(self):
        stream = self.stream or sys.stderr
        seconds = time.perf_counter() - self.start
        print(f"{self.label}: {self.stage} ({seconds:.0f} s)", file=stream, flush=True)

    def close(self):
        """Stop the timer: nothing more is printed."""
        self._timer.cancel()
        with self._lock:
            self.shown = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
