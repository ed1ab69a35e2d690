"""The inverse at an engine's step for a batch of scenes: exact, at formula speed, rows in parallel.

For an engine whose step is piecewise affine (``kernels.AFFINE``) and an e_N target, each row's
damping is solved on the exact phase mean of ``affine_phase`` (numba, rows in ``engine.threads``'
pool; a row never depends on another, so the result is the same bits at any thread count):

1. **From the guess** (the continuous law's damping, whose mean at the step is reported too):
   secant steps on ln(mean) against the damping (a linear oscillator's ln e is nearly linear in
   its damping), until the mean crosses the target or comes within ``STOP_TOL`` of it.  Where the
   guess's mean is more than ``FAR`` below the target, zero damping's mean instead: a target above
   it is out of reach, else ``[0, guess]`` is the bracket;
2. **else on ``inverse.damping_for``'s ladder**: zero damping (a target above its mean is out of
   reach, the mean nearest the target is kept), then ``BRACKET_START`` over the contact time
   doubled up to ``BRACKET_DOUBLINGS`` times, to the first rung whose mean is below the target;
3. **Brent's method** in the bracket, until the mean is within ``STOP_TOL`` of the target or the
   bracket is down to rounding.  A row is "ok" when its mean is within ``inverse.MEAN_TOL``.

Where the mean is not monotone in the damping there can be several roots; each row's answer is
a root (checked), and the same scene gives the same root on every call, but the scalar
``damping_for`` (which starts from its ladder) may give another.
"""

import math

import numpy as np
from numba import njit

from contactalpha.engine.threads import run_rows

from .affine_phase import QUAD_TOL, phase_row, workspace
from .codes import P_MAX, P_MEAN, P_MIN, P_STD, P_STEPS_MAX, P_STEPS_MIN
from .delivered import step_limit
from .inverse import BRACKET_DOUBLINGS, BRACKET_START, MEAN_TOL
from .kernels import engine_affine_map, for_engine
from .registry import Stepper

# Columns of a solved row.
(B_DAMPING, B_MEAN, B_MIN, B_MAX, B_STD, B_STEPS_MIN, B_STEPS_MAX, B_STATUS, B_NEAREST, B_GUESS_MEAN,
 B_GUESS_MIN, B_GUESS_MAX, B_MEANS) = range(13)  # fmt: skip
N_COLS = 13
# Row status.
B_OK, B_UNREACHABLE, B_NOT_CONVERGED, B_FAILED = range(4)
ROW_STATUS = {B_OK: "ok", B_UNREACHABLE: "unreachable", B_NOT_CONVERGED: "not_converged",
              B_FAILED: "no phase mean (a drop failed)"}  # fmt: skip
# A guess whose mean is this far below the target checks zero damping first (where the step itself
# dissipates, e.g. PyBullet's implicit one, the root lies far below the guess, or out of reach) and
# then solves in the bracket [0, guess].
FAR = 0.05
# Secant steps from the guess before the ladder takes over, and the most one step changes the damping by.
GUESS_STEPS = 8
MAX_FACTOR = 4.0
# Brent stops once the mean is this close to the target (well inside MEAN_TOL).
STOP_TOL = 0.1 * MEAN_TOL
BRENT_ITERATIONS = 100
# Rows of a row's step workspace (``affine_phase.workspace``; a longer drop grows its own copy).
WORK_ROWS = 128


@njit(cache=True)
def _mean(code, p, slots, c, h, v, a, max_steps, work):
    """The phase mean at damping ``c`` (``work``'s last array receives the row); NaN where a drop fails."""
    for s in slots:
        p[s] = c
    ws, forms, maps, zn, wn, buf, vals, acc = work
    phase_row(code, p, h, v, a, max_steps, QUAD_TOL, ws, forms, maps, zn, wn, buf, vals, acc)
    return acc[P_MEAN]


@njit(cache=True, inline="always")  # one call site: compiled inside it, not once more apart
def _brent(code, p, slots, h, v, a, max_steps, target, xa, fa, xb, fb, work, count):
    """Brent's method (scipy's ``brentq``) on ``mean - target`` in ``[xa, xb]``.

    Returns ``(root, f(root), means)``.
    """
    xpre, fpre, xcur, fcur = xa, fa, xb, fb
    xblk = fblk = spre = scur = 0.0
    for _ in range(BRENT_ITERATIONS):
        if fpre != 0.0 and fcur != 0.0 and (fpre > 0.0) != (fcur > 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (4.0 * np.finfo(np.float64).eps * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if abs(fcur) <= STOP_TOL or abs(sbis) < delta:
            break
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre, scur = sbis, sbis
        else:
            spre, scur = sbis, sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0.0 else -delta)
        fcur = _mean(code, p, slots, xcur, h, v, a, max_steps, work) - target
        count += 1
        if not math.isfinite(fcur):
            return xcur, fcur, count
    # The row in ``work`` must be the answer's: evaluate again if Brent's last point was not it.
    if work[-1][P_MEAN] - target != fcur:
        fcur = _mean(code, p, slots, xcur, h, v, a, max_steps, work) - target
        count += 1
    return xcur, fcur, count


@njit(cache=True, inline="always")  # one call site: compiled inside it, not once more apart
def solve_row(
    code: int,
    p: np.ndarray,
    slots: np.ndarray,
    h: float,
    v: float,
    a: float,
    target: float,
    guess: float,
    ladder_start: float,
    max_steps: int,
    out: np.ndarray,
) -> None:
    """One row (module docstring): fills ``out``'s ``B_*`` columns; ``p``'s damping slots are overwritten."""
    work = workspace(min(max_steps + 2, WORK_ROWS))
    acc = work[-1]
    out[:] = math.nan
    out[B_MEANS] = 0.0
    count = 0
    bracketed = False
    xa = fa = xb = fb = 0.0
    nearest = math.nan
    if guess >= 0.0 and math.isfinite(guess):
        f0 = _mean(code, p, slots, guess, h, v, a, max_steps, work) - target
        count += 1
        out[B_GUESS_MEAN], out[B_GUESS_MIN], out[B_GUESS_MAX] = acc[P_MEAN], acc[P_MIN], acc[P_MAX]
        x0 = guess
        # The first secant step starts from the continuous oscillator's e = 1 at zero damping.
        xp, yp = 0.0, 0.0
        if math.isfinite(f0) and f0 < -FAR and guess > 0.0:
            fz = _mean(code, p, slots, 0.0, h, v, a, max_steps, work) - target
            count += 1
            if math.isfinite(fz) and fz < 0.0:
                out[B_STATUS] = B_UNREACHABLE
                out[B_NEAREST] = fz + target
                out[B_MEANS] = count
                return
            if math.isfinite(fz):  # [0, guess] brackets a root: Brent from there
                xa, fa, xb, fb, bracketed = 0.0, fz, x0, f0, True
        yt = math.log(target)
        for _ in range(GUESS_STEPS if math.isfinite(f0) and guess > 0.0 and not bracketed else 0):
            if abs(f0) <= STOP_TOL:
                xa, fa, xb, fb, bracketed = x0, f0, x0, f0, True
                break
            if f0 + target <= 0.0:  # captured at every phase: less damping
                x1 = x0 / MAX_FACTOR
            else:
                y0 = math.log(f0 + target)
                x1 = (
                    x0 + (yt - y0) * (x0 - xp) / (y0 - yp)
                    if y0 != yp
                    else x0 * (MAX_FACTOR if f0 > 0.0 else 1.0 / MAX_FACTOR)
                )
                x1 = min(max(x1, x0 / MAX_FACTOR), x0 * MAX_FACTOR)
                xp, yp = x0, y0
            f1 = _mean(code, p, slots, x1, h, v, a, max_steps, work) - target
            count += 1
            if not math.isfinite(f1):
                break
            if abs(f1) <= STOP_TOL:  # close enough already: Brent's bracket [x1, x1]
                xa, fa, xb, fb, bracketed = x1, f1, x1, f1, True
                break
            if (f1 > 0.0) != (f0 > 0.0):
                xa, fa, xb, fb, bracketed = x0, f0, x1, f1, True
                break
            x0, f0 = x1, f1
    if not bracketed:  # inverse.damping_for's ladder
        f0 = _mean(code, p, slots, 0.0, h, v, a, max_steps, work) - target
        count += 1
        nearest = acc[P_MEAN]
        if not math.isfinite(f0):
            out[B_STATUS] = B_FAILED
            out[B_MEANS] = count
            return
        x0 = 0.0
        if f0 >= 0.0:
            x1 = ladder_start
            for _ in range(BRACKET_DOUBLINGS):
                f1 = _mean(code, p, slots, x1, h, v, a, max_steps, work) - target
                count += 1
                if not math.isfinite(f1):
                    break
                if abs(f1) < abs(nearest - target):
                    nearest = acc[P_MEAN]
                if f1 < 0.0:
                    xa, fa, xb, fb, bracketed = x0, f0, x1, f1, True
                    break
                x0, f0, x1 = x1, f1, 2.0 * x1
    if not bracketed:
        out[B_STATUS] = B_UNREACHABLE
        out[B_NEAREST] = nearest
        out[B_MEANS] = count
        return
    if xa == xb:  # the guess's steps landed within STOP_TOL: work holds that mean
        root, froot = xb, fb
    else:
        root, froot, count = _brent(code, p, slots, h, v, a, max_steps, target, xa, fa, xb, fb, work, count)
    out[B_MEANS] = count
    if not math.isfinite(froot):
        out[B_STATUS] = B_FAILED
        return
    out[B_DAMPING] = root
    out[B_MEAN], out[B_MIN], out[B_MAX], out[B_STD] = acc[P_MEAN], acc[P_MIN], acc[P_MAX], acc[P_STD]
    out[B_STEPS_MIN], out[B_STEPS_MAX] = acc[P_STEPS_MIN], acc[P_STEPS_MAX]
    out[B_STATUS] = B_OK if abs(froot) <= MEAN_TOL else B_NOT_CONVERGED


@njit(cache=True, nogil=True)
def rows_kernel(
    code: int,
    params: np.ndarray,
    slots: np.ndarray,
    h: float,
    v: np.ndarray,
    a: np.ndarray,
    target: np.ndarray,
    guess: np.ndarray,
    ladder_start: np.ndarray,
    max_steps: np.ndarray,
    out: np.ndarray,
    start: int,
    stop: int,
) -> None:
    """Rows ``start .. stop - 1`` of ``solve_rows`` into ``out`` (a template of ``kernels.for_engine``)."""
    for i in range(start, stop):
        p = params[i].copy()
        solve_row(code, p, slots, h, v[i], a[i], target[i], guess[i], ladder_start[i], max_steps[i], out[i])


def solve_rows(
    code: int,
    params: np.ndarray,
    slots: np.ndarray,
    h: float,
    v: np.ndarray,
    a: np.ndarray,
    target: np.ndarray,
    guess: np.ndarray,
    ladder_start: np.ndarray,
    max_steps: np.ndarray,
    threads: int | None = None,
) -> np.ndarray:
    """``solve_row`` for every row of ``params`` (one scene each): an ``(n, N_COLS)`` array.

    The rows run in ``engine.threads``' pool (``threads``, default numba's thread count); a row
    never depends on another, so the bits are the same at any count.
    """
    engine_affine_map(code)
    n = params.shape[0]
    out = np.empty((n, N_COLS))
    args = (code, params, slots, h, v, a, target, guess, ladder_start, max_steps, out)
    run_rows(for_engine(code, rows_kernel), n, *args, threads=threads)
    return out


def solve_batch(
    s: Stepper, params: np.ndarray, h: float, v: np.ndarray, a: np.ndarray, target: np.ndarray
) -> np.ndarray:
    """``solve_rows`` for stepper ``s`` (piecewise affine): rows of ``params`` from their own damping.

    Each row starts from the damping its ``params`` hold (the continuous law's); the ladder starts
    at ``BRACKET_START`` over its contact time and a drop takes ``delivered.step_limit`` steps.
    """
    params = np.ascontiguousarray(params, dtype=float)
    guess = params[:, s.damping_slots[0]].copy()
    limit = np.asarray(step_limit(s, params.T, h))
    return solve_rows(s.code, params, np.array(s.damping_slots), h, v, a, target, guess,
                      BRACKET_START / s.contact_time(params.T), limit)  # fmt: skip
