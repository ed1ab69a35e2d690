"""Fast first calls on a cold numba cache: a kernel runs as its pure-Python twin until compiled.

Compiling the impact integrator takes seconds of CPU (tens on a loaded machine), far more than
one impact or one table lookup costs when the same source runs as plain Python (milliseconds).
``FirstCall`` wraps a scalar entry kernel of the package's fast paths:

1. if numba already holds compiled code for it, or its on-disk cache (``jitcache``) has it,
   the compiled kernel runs;
2. otherwise its *Python twin* runs: the kernel's own source (``py_func``) with every jitted
   callee replaced by its twin, executed on ``numpy.float64`` scalars with the libm functions
   numba calls (``math.exp``, ``math.log``, ...), so the arithmetic is the compiled kernel's,
   bit for bit (tests/engine/test_firstcall.py compares them);
3. once the twin has cost ``INTERPRET_BUDGET_S`` seconds in this process, the kernel is
   compiled (a line on stderr says so, and another when it is done) and runs compiled from
   then on.  The budget decides only *when* to compile, never a number.

``contactalpha warmup`` compiles every kernel ahead of time (``warmup.warm_up``).
"""

import contextlib
import math
import sys
import threading
import time
import types

import numpy as np
from numba.core.registry import CPUDispatcher

# Seconds of Python-twin time a process spends on one kernel before compiling it.
INTERPRET_BUDGET_S = 1.0
# numpy functions whose scalar form numba compiles to the C library's function: the twin calls
# the same function through ``math`` (numpy may use its own SIMD versions, a few ulp apart).
LIBM = ("exp", "log", "log1p", "expm1", "sqrt", "sin", "cos", "tan", "arctan", "floor")
LIBM_NAMES = {"arctan": "atan"}


def _scalar_libm(math_fn, numpy_fn):
    def fn(x, *rest):
        if not rest and type(x) in (float, np.float64):
            try:
                return np.float64(math_fn(x))
            except (OverflowError, ValueError):  # IEEE results (inf, nan) where math raises
                pass
        return numpy_fn(x, *rest)

    return fn


class _NumpyForTwins(types.SimpleNamespace):
    """``numpy`` as the twins see it: the libm functions on scalars, the rest numpy's own."""

    def __getattr__(self, name):
        return getattr(np, name)


NUMPY_FOR_TWINS = _NumpyForTwins(
    **{name: _scalar_libm(getattr(math, LIBM_NAMES.get(name, name)), getattr(np, name)) for name in LIBM}
)

_TWINS = {}
# False inside ``compiled_only()``: every FirstCall compiles at once, silently (the warm-up).
_INTERPRET = [True]


@contextlib.contextmanager
def compiled_only():
    """Within this block a first call compiles its kernel (or loads it) instead of interpreting."""
    saved = _INTERPRET[0]
    _INTERPRET[0] = False
    try:
        yield
    finally:
        _INTERPRET[0] = saved


def python_twin(dispatcher):
    """The pure-Python function running ``dispatcher``'s source, its jitted callees as twins too."""
    twin = _TWINS.get(dispatcher)
    if twin is None:
        fn = dispatcher.py_func
        scope = dict(fn.__globals__)
        twin = types.FunctionType(fn.__code__, scope, fn.__name__, fn.__defaults__, fn.__closure__)
        _TWINS[dispatcher] = twin
        for name, value in list(scope.items()):
            if isinstance(value, CPUDispatcher):
                scope[name] = python_twin(value)
            elif value is np:
                scope[name] = NUMPY_FOR_TWINS
    return twin


def _as_ieee(value):
    # Python floats raise on division by zero and overflow; numpy scalars follow IEEE as numba does.
    return np.float64(value) if type(value) is float else value


def _numba_type(value):
    from numba import typeof

    return typeof(value)


class FirstCall:
    """A jitted scalar kernel that runs as its Python twin until compiled code is at hand.

    Parameters
    ----------
    dispatcher : numba dispatcher
        A ``cache=True`` kernel of this package.
    what : str
        What it computes, for the line on stderr when it compiles ("the impact integrator").
    """

    def __init__(self, dispatcher, what):
        self.dispatcher = dispatcher
        self.what = what
        self.compiled = False
        self.interpreted_s = 0.0
        self._lock = threading.Lock()

    def __call__(self, *args):
        """The kernel's result for ``args``: compiled if at hand, else from the Python twin."""
        if self.compiled:
            return self.dispatcher(*args)
        return self._first_calls(args)

    def _first_calls(self, args):
        if self._compiled_or_cached(args):
            return self.dispatcher(*args)
        if not _INTERPRET[0]:
            self.compile(args, announce=False)
            return self.dispatcher(*args)
        clock = time.perf_counter()
        try:
            with np.errstate(all="ignore"):
                out = python_twin(self.dispatcher)(*map(_as_ieee, args))
        except Exception:  # a case the twin cannot run as Python: the compiled kernel decides
            self.compile(args)
            return self.dispatcher(*args)
        self.interpreted_s += time.perf_counter() - clock
        if self.interpreted_s > INTERPRET_BUDGET_S:
            self.compile(args)
        return _native(out)

    def _compiled_or_cached(self, args):
        disp = self.dispatcher
        if not disp.signatures:
            sig = tuple(_numba_type(a) for a in args)
            if disp._cache.load_overload(sig, disp.targetctx) is None:
                return False
            disp.compile(sig)  # loads it from the cache again and registers it
        self.compiled = True
        return True

    def compile(self, args, announce=True):
        """Compile the kernel for ``args``' types now (or load it), saying so on stderr if ``announce``."""
        with self._lock:
            if self.compiled or self._compiled_or_cached(args):
                return
            if not announce:
                self.dispatcher.compile(tuple(_numba_type(a) for a in args))
                self.compiled = True
                return
            print(
                f"contactalpha: compiling {self.what} (once; numba caches it on disk, "
                "`contactalpha warmup` compiles everything ahead of time) ...",
                file=sys.stderr,
                flush=True,
            )
            clock = time.perf_counter()
            self.dispatcher.compile(tuple(_numba_type(a) for a in args))
            self.compiled = True
            print(
                f"contactalpha: {self.what} compiled in {time.perf_counter() - clock:.1f} s", file=sys.stderr
            )


def _native(value):
    """The twin's result as the compiled kernel returns it (Python floats for float64 scalars)."""
    if type(value) is np.float64:
        return float(value)
    if type(value) is tuple:
        return tuple(_native(v) for v in value)
    return value
