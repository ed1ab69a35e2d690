"""Rows in threads: every row once, the same bits for any thread count, failures raised."""

import multiprocessing

import numba
import numpy as np
import pytest
from numba import njit

from contactalpha.engine import driver, solver
from contactalpha.engine.codes import OUT_EPS2
from contactalpha.engine.exact import restitution_exact
from contactalpha.engine.threads import BLOCKS_PER_THREAD, run_rows


@njit(nogil=True)
def _count_rows(out, start, stop):
    for i in range(start, stop):
        out[i] += 1.0


@pytest.mark.parametrize("n", [1, 7, 64, 1001])
@pytest.mark.parametrize("threads", [1, 2, 3])
def test_every_row_is_filled_exactly_once(n, threads):
    out = np.zeros(n)
    run_rows(_count_rows, n, out, threads=threads)
    assert np.array_equal(out, np.ones(n))


def test_a_failing_block_raises_in_the_caller():
    def kernel(out, start, stop):
        if start > 0:
            raise RuntimeError(f"block at {start}")
        out[start:stop] = 1.0

    with pytest.raises(RuntimeError, match="block at"):
        run_rows(kernel, 100, np.zeros(100), threads=2)


def test_blocks_are_smaller_than_one_share_per_thread():
    # Costs differ by orders of magnitude between rows, so each thread takes several blocks.
    starts = []
    run_rows(lambda out, a, b: starts.append((a, b)), 1000, None, threads=2)
    sizes = sorted(b - a for a, b in starts)
    assert len(starts) == 2 * BLOCKS_PER_THREAD
    assert sum(sizes) == 1000 and sizes[-1] <= 1000 // 2 // (BLOCKS_PER_THREAD // 2)


def test_impacts_are_the_same_bits_on_one_and_two_threads():
    alpha = np.linspace(0.05, 8.0, 97)
    xi = np.linspace(0.0, 0.95, 97)
    A = driver.scaled_load(xi)
    one = driver.impact_many(alpha, A, driver.RTOL, driver.ATOL, driver.MAX_STEPS, threads=1)
    two = driver.impact_many(alpha, A, driver.RTOL, driver.ATOL, driver.MAX_STEPS, threads=2)
    assert np.array_equal(one, two, equal_nan=True)
    # Real rows, not a shared mistake: the first (xi = 0) against the exact unloaded relation.
    assert np.sqrt(one[0, OUT_EPS2]) == pytest.approx(restitution_exact(np.array([alpha[0]]))[0], abs=1e-10)


def test_solves_are_the_same_bits_on_one_and_two_threads():
    eps, xi = np.linspace(0.02, 0.98, 97), np.linspace(0.0, 0.95, 97)[::-1]
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = solver.solve_alpha(eps, xi)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = solver.solve_alpha(eps, xi)
    finally:
        numba.set_num_threads(before)
    assert np.all(one.status == "ok")
    assert np.array_equal(one.alpha, many.alpha) and np.array_equal(one.steps, many.steps)


def _child_sum(_):
    out = np.zeros(500)
    run_rows(_count_rows, 500, out, threads=2)
    return out.sum()


def test_a_forked_child_gets_its_own_threads():
    run_rows(_count_rows, 500, np.zeros(500), threads=2)  # the parent's pool exists before the fork
    with multiprocessing.get_context("fork").Pool(1) as pool:
        assert pool.map(_child_sum, [0], chunksize=1) == [500.0]
