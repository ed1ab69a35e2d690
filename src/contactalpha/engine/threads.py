"""Run a jitted row kernel over an array in several threads, without numba's parallel compiler.

The array entry points (impacts, the alpha solver, the table lookups, the separation
boundary) each run one jitted loop ``kernel(*args, out, start, stop)`` that fills rows
``start .. stop - 1`` of ``out`` and releases the GIL (``nogil=True``).  ``run_rows`` hands
blocks of rows to a pool of Python threads.  Each row depends on its own inputs only, so the
result is the same bits however the rows are split and however many threads run.

Why not ``@njit(parallel=True)`` with ``prange``: numba compiles a parallel loop as a second,
separate function around the whole kernel, which doubled the cold compile of every array
entry point (about 9-10 s of CPU each for the impact and solver kernels on the 2-core box,
half of the workflow's warm-up); the threads here reuse the one compiled serial loop.
"""

import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np

from contactalpha.engine.firstcall import interpret_rows

# Blocks per thread: rows differ in cost by orders of magnitude (a creeping impact takes
# ~100 times the steps of a separating one), so each thread takes several blocks in turn
# rather than one fixed share.
BLOCKS_PER_THREAD = 8

_pools: dict = {}
_pools_lock = threading.Lock()


def _forget_pools():
    # A forked child inherits the dict but not the worker threads: start afresh.
    _pools.clear()


os.register_at_fork(after_in_child=_forget_pools)


def _pool(threads):
    with _pools_lock:
        pool = _pools.get(threads)
        if pool is None:
            pool = _pools[threads] = ThreadPoolExecutor(threads, thread_name_prefix="contactalpha")
        return pool


def thread_count():
    """Threads the array entry points use: numba's own setting.

    ``NUMBA_NUM_THREADS`` and ``numba.set_num_threads`` govern every loop, as they did
    numba's parallel loops.
    """
    return numba.get_num_threads()


def run_rows(kernel, n, *args, threads=None):
    """Call ``kernel(*args, start, stop)`` on blocks that cover rows ``0 .. n - 1`` once each.

    Parameters
    ----------
    kernel : numba dispatcher
        Jitted with ``nogil=True``; writes its rows into an output array among ``args``.
    n : int
        Number of rows.
    threads : int, optional
        Threads to use (default ``thread_count()``); 1 runs the kernel in this thread.

    A kernel with no compiled code at hand (none in memory, none in numba's disk cache) first
    runs rows as its Python twin (``firstcall.interpret_rows``: the same bits) and is compiled
    only for the rows left once the twin has used its time budget.
    """
    first = interpret_rows(kernel, n, args)  # rows its Python twin ran before it was compiled
    if first >= n:
        return
    threads = min(thread_count() if threads is None else int(threads), n - first)
    if threads <= 1:
        kernel(*args, first, n)
        return
    size = -(-(n - first) // (threads * BLOCKS_PER_THREAD))
    pool = _pool(threads)
    futures = [pool.submit(kernel, *args, start, min(start + size, n)) for start in range(first, n, size)]
    try:
        for future in futures:
            future.result()
    except BaseException:
        # Ctrl-C or a failed block: drop the blocks not yet started, then re-raise.
        for future in futures:
            future.cancel()
        raise


def flat_owned(a):
    """``a`` as a new contiguous 1-D float64 array that owns its data, for a jitted kernel.

    A view from ``np.broadcast_arrays`` carries numpy's warn-on-write flag, and numba's unboxing
    of it prints a FutureWarning ("future versions will not create a writeable array from
    broadcast_array"); a copy costs far less than the kernel's work per entry.
    """
    return np.array(a, dtype=np.float64, order="C").reshape(-1)
