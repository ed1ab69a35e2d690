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
   compiled and runs compiled from then on.  The budget decides only *when* to compile,
   never a number.

Whatever numba compiles of this package outside the warm-up (array paths, the solver, the
ball...) is announced on stderr: one line the first time, then one line per kernel with its
compile time (``CompileNotice``).  ``contactalpha warmup`` compiles every kernel ahead of time
(``warmup.warm_up``), silently.
"""

import contextlib
import math
import os
import sys
import threading
import time
import types

import numpy as np
from numba.core import event
from numba.core.registry import CPUDispatcher

# Seconds of Python-twin time a process spends on one kernel before compiling it.
INTERPRET_BUDGET_S = 1.0
# numpy functions whose scalar form numba compiles to the C library's function: the twin calls
# the same function through ``math`` (numpy may use its own SIMD versions, a few ulp apart).
LIBM = (
    "exp", "log", "log1p", "expm1", "log10", "log2", "sqrt", "sin", "cos", "tan",
    "arcsin", "arccos", "arctan", "sinh", "cosh", "tanh", "arcsinh", "arccosh", "arctanh", "floor",
)  # fmt: skip
LIBM_NAMES = {"arcsin": "asin", "arccos": "acos", "arctan": "atan", "arcsinh": "asinh", "arccosh": "acosh",
              "arctanh": "atanh"}  # fmt: skip
# Two-argument ones: numpy's name -> math's.
LIBM_2 = {"arctan2": "atan2", "hypot": "hypot"}


def _scalar_libm(math_fn, numpy_fn, arity=1):
    def fn(*args):
        if len(args) == arity and all(type(x) in (float, np.float64) for x in args):
            try:
                return np.float64(math_fn(*args))
            except (OverflowError, ValueError):  # IEEE results (inf, nan) where math raises
                pass
        return numpy_fn(*args)

    return fn


class _NumpyForTwins(types.SimpleNamespace):
    """``numpy`` as the twins see it: the libm functions on scalars, the rest numpy's own."""

    def __getattr__(self, name):
        return getattr(np, name)


NUMPY_FOR_TWINS = _NumpyForTwins(
    **{name: _scalar_libm(getattr(math, LIBM_NAMES.get(name, name)), getattr(np, name)) for name in LIBM},
    **{name: _scalar_libm(getattr(math, m), getattr(np, name), 2) for name, m in LIBM_2.items()},
)

_TWINS: dict = {}
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


class CompileNotice(event.Listener):
    """Says on stderr when numba compiles a kernel of this package (not inside ``compiled_only``)."""

    def __init__(self):
        self.depth = 0
        self.said = False
        self.started = None
        self.announced = set()  # kernels defined outside the package that are announced too

    def ours(self, dispatcher):
        """True for a kernel of this package (or one a ``FirstCall`` wraps)."""
        module = getattr(dispatcher.py_func, "__module__", "") or ""
        return module.startswith("contactalpha.") or dispatcher in self.announced

    def on_start(self, ev):
        """A compile starts: the first line once, the kernel's name now, and its clock."""
        self.depth += 1
        if self.depth == 1 and _INTERPRET[0] and self.ours(ev.data["dispatcher"]):
            if not self.said:
                self.said = True
                print(
                    "contactalpha: compiling numba kernels on first use (once: numba caches them on "
                    "disk; `contactalpha warmup` compiles them all ahead of time)",
                    file=sys.stderr,
                    flush=True,
                )
            # Said as it starts: a compile can take minutes on a loaded machine.
            name = ev.data["dispatcher"].py_func.__name__
            print(f"contactalpha:   compiling {name} ...", file=sys.stderr, flush=True)
            self.started = time.perf_counter()

    def on_end(self, ev):
        """A compile ends: the kernel's name and compile time, for a top-level kernel."""
        self.depth -= 1
        if self.depth == 0 and self.started is not None:
            name = ev.data["dispatcher"].py_func.__name__
            seconds = time.perf_counter() - self.started
            self.started = None
            print(f"contactalpha:   {name} compiled in {seconds:.1f} s", file=sys.stderr, flush=True)


NOTICE = CompileNotice()
event.register("numba:compile", NOTICE)


def _numba_type(value):
    from numba import typeof

    return typeof(value)


class FirstCall:
    """A jitted scalar kernel that runs as its Python twin until compiled code is at hand.

    Parameters
    ----------
    dispatcher : numba dispatcher
        A ``cache=True`` kernel of this package.
    on_compiled : callable, optional
        Called with ``dispatcher`` once compiled code is at hand, so that the caller can call the
        dispatcher itself from then on (one Python call less per evaluation).
    interpret_if : callable, optional
        ``interpret_if(*args)`` False for arguments the twin would take long on (the kernel is
        compiled for them at once); default: every call may be interpreted.
    """

    def __init__(self, dispatcher, on_compiled=None, interpret_if=None):
        self.dispatcher = dispatcher
        self.on_compiled = on_compiled
        self.interpret_if = interpret_if
        # Under NUMBA_DISABLE_JIT=1 the "kernel" is its Python function already: call it as is.
        self.compiled = not isinstance(dispatcher, CPUDispatcher)
        self.interpreted_s = 0.0
        self._lock = threading.Lock()
        NOTICE.announced.add(dispatcher)

    def __call__(self, *args):
        """The kernel's result for ``args``: compiled if at hand, else from the Python twin."""
        if self.compiled:
            return self.dispatcher(*args)
        return self._first_calls(args)

    def _first_calls(self, args):
        if self._compiled_or_cached(args):
            return self.dispatcher(*args)
        if not _INTERPRET[0] or (self.interpret_if is not None and not self.interpret_if(*args)):
            self.compile(args)
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
            # numba has no public "is it on disk?" query: ``Dispatcher.compile`` itself asks its
            # ``_cache`` first.  Without that attribute (another numba) the kernel counts as not
            # cached: the twin runs, then the budget compiles it (which loads it if cached).
            if not _on_disk(disp, sig):
                return False
            disp.compile(sig)  # loads it from the cache again and registers it
        self._now_compiled()
        return True

    def _now_compiled(self):
        self.compiled = True
        if self.on_compiled is not None:
            self.on_compiled(self.dispatcher)

    def compile(self, args):
        """Compile the kernel for ``args``' types now, or load it from the cache (``NOTICE`` says so)."""
        with self._lock:
            if not (self.compiled or self._compiled_or_cached(args)):
                self.dispatcher.compile(tuple(_numba_type(a) for a in args))
                self._now_compiled()


class _RowState:
    """How far the Python twin of one row kernel got in this process."""

    def __init__(self):
        self.interpreted_s = 0.0
        self.done = False  # compiled code is at hand, or the twin used its budget
        self.lock = threading.Lock()


_ROWS: dict = {}
# Rows a twin runs between two looks at its clock: the first look comes after one row.
ROW_BLOCK_MAX = 64


def twin_rows(dispatcher):
    """Mark a row kernel of ``threads.run_rows`` whose first rows may run as its Python twin.

    Only kernels whose twins are tested bit-identical to their compiled code are marked
    (tests/laws/test_first_call.py); returns ``dispatcher``, so it can decorate one.
    """
    _ROWS.setdefault(dispatcher, _RowState())
    NOTICE.announced.add(dispatcher)
    return dispatcher


def interpret_rows(kernel, n, args):
    """Run the first rows of a ``twin_rows`` kernel ``kernel(*args, start, stop)`` as its Python twin.

    Returns the number of leading rows done (0 .. n): all of them while the twin stays within
    ``INTERPRET_BUDGET_S`` (counted per kernel and process), none when compiled code is at hand
    (in memory or in numba's disk cache), under ``compiled_only()`` or when the twin cannot run
    the kernel as Python.  The caller runs the other rows compiled; the twin writes the same bits.
    """
    state = _ROWS.get(kernel)
    if state is None or state.done or not _INTERPRET[0] or n <= 0 or not isinstance(kernel, CPUDispatcher):
        return 0
    with state.lock:
        if state.done or kernel.signatures or _cached(kernel, (*args, 0, n)):
            state.done = True
            return 0
        twin = python_twin(kernel)
        plain = tuple(map(_as_ieee, args))
        first, block = 0, 1
        while first < n and state.interpreted_s <= INTERPRET_BUDGET_S:
            stop = min(first + block, n)
            clock = time.perf_counter()
            try:
                with np.errstate(all="ignore"):
                    twin(*plain, first, stop)
            except Exception:  # a case the twin cannot run as Python: the compiled kernel does it
                state.done = True
                return first
            state.interpreted_s += time.perf_counter() - clock
            first, block = stop, min(2 * block, ROW_BLOCK_MAX)
        state.done = first < n
        return first


def _cached(dispatcher, args):
    """True when numba's disk cache holds ``dispatcher``'s code for ``args``' types (then loaded)."""
    sig = tuple(_numba_type(a) for a in args)
    if not _on_disk(dispatcher, sig):
        return False
    dispatcher.compile(sig)
    return True


def _on_disk(dispatcher, sig):
    """True when numba's disk cache holds code of ``dispatcher`` for ``sig``.

    A kernel without an index file on disk has nothing cached: that is told without asking numba,
    whose first cache query sets up its code generator (a second or more on a cold start).
    """
    cache = getattr(dispatcher, "_cache", None)
    if cache is None:
        return False
    index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
    if index is not None and not os.path.exists(index):
        return False
    return cache.load_overload(sig, dispatcher.targetctx) is not None


def _native(value):
    """The twin's result as the compiled kernel returns it (Python floats for float64 scalars)."""
    if type(value) is np.float64:
        return float(value)
    if type(value) is tuple:
        return tuple(_native(v) for v in value)
    return value
