"""What every time-stepping engine (MuJoCo, Bullet, Drake's discrete plant) shares.

**Semi-implicit Euler in flight.**  These engines update the velocity first and the position with
the new velocity: ``v' = v - a h``, ``z' = z + h v'`` (z the height above touchdown, v upward).
In flight under a constant acceleration ``a`` the positions then lie exactly on a parabola whose
velocity at a step's end is ``v - a h / 2`` (the stored velocity is the mean over the step).  So:

- a drop *arrives* with approach speed ``v_minus`` when its parabola crosses z = 0 at that speed:
  ``touchdown_state`` (``contactalpha.stepping.drop``, re-exported here) gives the stored state one step-fraction ``phase`` before the crossing;
- the *rebound* speed is the speed of the flight parabola at z = 0, read at the first state
  reached by a step without contact force (``v_j - v_{j-1} = -a h``):
  ``e_N = sqrt((v_j - a h/2)^2 + 2 a z_j) / v_minus``.  A drop test reads the same number from the
  rebound height.

**Touchdown phase.**  A spring-dashpot contact switches its force on at touchdown, so where
touchdown falls within a step moves the rebound by O(h / contact time).  ``summarise`` averages
e_N over ``phases`` touchdowns spread evenly over one step and reports the spread; the
adapters warn when that spread, or the contact's length in steps, makes one drop's e_N untrustworthy.

**Refinement.**  Where the step moves the mean e_N away from the target by more than the
tolerance, ``refine`` adjusts the law's damping parameter by secant steps on the engine's own
drops until the mean delivered e_N is the target.
"""

import math
import warnings
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.measure import MeasuredImpact
from contactalpha.engine.codes import END_STATES, NONSEPARATION, SEPARATION
from contactalpha.stepping.drop import touchdown_state

# A contact spanning fewer steps than this is flagged: its rebound depends on the touchdown phase.
MIN_CONTACT_STEPS = 20
# Secant iterations of ``refine`` at most, and its tolerance on the mean delivered e_N.
REFINE_ITER = 12
REFINE_TOL = 1e-5
# Relative tolerance telling a free-flight step (the velocity changed by exactly -a h).
FREE_STEP_RTOL = 1e-9


class ContactStepsWarning(UserWarning):
    """A discrete engine's contact spans too few steps for its restitution to be trusted."""


def measure_steps(z, v, accel, h, approach_speed):
    """The impact in per-step states ``z`` (height above touchdown, m) and ``v`` (upward, m/s).

    Returns
    -------
    MeasuredImpact
        ``e_n`` from the flight parabola after the first free step (see the module docstring);
        ``eps`` from the energy identity with the deepest sampled deformation; ``t_*`` in steps
        times ``h`` from the first state.  No free step after the deepest point: "nonseparation"
        with e_N = 0.
    """
    z = np.asarray(z, dtype=float)
    v = np.asarray(v, dtype=float)
    i_max = int(np.argmin(z))
    d_max = -float(z[i_max])
    dv = np.diff(v)
    free = (np.abs(dv + accel * h) <= FREE_STEP_RTOL * max(accel * h, abs(approach_speed))) & (z[:-1] > 0.0)
    after = np.nonzero(free[i_max:] & (v[i_max + 1 :] > 0.0))[0]
    w_c = 0.5 * approach_speed**2 + accel * d_max
    if after.size == 0:
        d_end = -float(z[-1])
        eps2 = accel * (d_max - d_end) / w_c
        return MeasuredImpact(
            float(np.sqrt(max(eps2, 0.0))), 0.0, END_STATES[NONSEPARATION], approach_speed,
            0.0, i_max * h, (z.size - 1) * h, d_max, d_end, 0.0,
        )  # fmt: skip
    j = i_max + int(after[0]) + 1
    s = v[j] - 0.5 * accel * h
    rebound = math.sqrt(s * s + 2.0 * accel * z[j])
    e_n = rebound / approach_speed
    eps2 = (0.5 * rebound**2 + accel * d_max) / w_c
    return MeasuredImpact(
        float(np.sqrt(eps2)), float(e_n), END_STATES[SEPARATION], approach_speed,
        0.0, i_max * h, j * h, d_max, 0.0, -rebound,
    )  # fmt: skip


@dataclass(frozen=True)
class Delivered:
    """Newton's restitution a stepping engine delivers, over touchdown phases.

    Attributes
    ----------
    e_n : mean e_N over the phases (0 for a drop that does not separate).
    spread : max - min of e_N over the phases.
    contact_steps : fewest steps in contact over the phases.
    separated : every phase separated.
    """

    e_n: float
    spread: float
    contact_steps: int
    separated: bool


def float_or_array(arr):
    """A float for a 0-d result, else the float array (the adapters' parameters keep their input's shape)."""
    arr = np.asarray(arr, dtype=float)
    return float(arr) if arr.ndim == 0 else arr


def summarise(e_n_per_phase, contact_steps, separated):
    """``Delivered`` from per-phase results (arrays over the phases)."""
    e = np.asarray(e_n_per_phase, dtype=float)
    return Delivered(float(e.mean()), float(np.ptp(e)), int(np.min(contact_steps)), bool(np.all(separated)))


def warn_if_coarse(engine, result, tol, min_steps=MIN_CONTACT_STEPS):
    """Warn (``ContactStepsWarning``): a contact under ``min_steps`` steps or a phase spread over ``tol``."""
    if result.contact_steps < min_steps or result.spread > tol:
        warnings.warn(
            f"{engine}: the contact spans {result.contact_steps} steps (coarse below {min_steps}) and "
            f"one drop's e_N depends on where touchdown falls within a step by up to {result.spread:.3g} "
            f"(tolerance {tol:g}); the mean over touchdown phases is what the parameters deliver; "
            "a smaller time step narrows it",
            ContactStepsWarning,
            stacklevel=3,
        )


@dataclass(frozen=True)
class Refinement:
    """The outcome of ``refine``.

    Attributes
    ----------
    damping : the law's damping parameter that delivers the target (NaN when none does).
    e_n : the mean e_N delivered with it.
    start : the damping it started from (the continuous law's), and ``e_n_start`` its delivered e_N.
    iterations : engine evaluations after the start's.
    status : "ok", "unchanged" (the start already within the tolerance), "unreachable" (even zero
        damping delivers less than the target at this step), or "not_converged".
    """

    damping: float
    e_n: float
    start: float
    e_n_start: float
    iterations: int
    status: str


def refine(e_n_of, target, start, tol, *, max_iter=REFINE_ITER, refine_tol=REFINE_TOL):
    """Secant steps on ``e_n_of(damping) - target`` from ``start`` (the delivered e_N falls as damping grows).

    Parameters
    ----------
    e_n_of : callable
        The mean e_N the engine delivers with a damping parameter (>= 0).
    target : float
        Target e_N in (0, 1).
    start : float
        The continuous law's damping parameter (> 0).
    tol : float
        Below this |delivered - target| the start is kept ("unchanged").
    refine_tol : float
        The secant stops once |delivered - target| <= this.
    """
    e0 = e_n_of(start)
    if abs(e0 - target) <= tol:
        return Refinement(start, e0, start, e0, 0, "unchanged")
    x0, f0 = start, e0 - target
    x1 = start * (1.0 + 0.05 * np.sign(f0))
    f1 = e_n_of(x1) - target
    n = 1
    best = (abs(f0), x0, f0) if abs(f0) < abs(f1) else (abs(f1), x1, f1)
    while n < max_iter and best[0] > refine_tol:
        slope = (f1 - f0) / (x1 - x0) if x1 != x0 else -1.0
        if not (slope < 0.0 and math.isfinite(slope)):
            slope = -abs(f1) / max(abs(x1), 1e-12) - 1.0
        x2 = max(x1 - f1 / slope, 0.0)
        if x2 == 0.0 and x1 == 0.0:
            break
        f2 = e_n_of(x2) - target
        n += 1
        if x2 == 0.0 and f2 < 0.0:
            return Refinement(math.nan, f2 + target, start, e0, n, "unreachable")
        x0, f0, x1, f1 = x1, f1, x2, f2
        if abs(f2) < best[0]:
            best = (abs(f2), x2, f2)
    status = "ok" if best[0] <= refine_tol else "not_converged"
    return Refinement(best[1], best[2] + target, start, e0, n, status)
