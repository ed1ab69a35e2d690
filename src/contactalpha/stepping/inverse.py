"""The engine's own damping whose mean restitution over the touchdown phase is the target.

The mean e_N (or eps) over a uniform phase is continuous in the damping (the jumps in phase move
continuously with it) and, at a step fine enough for a stable map, falls as the damping grows.
``damping_for`` brackets the root on a fixed ladder from zero damping upwards (the first rung
whose mean falls below the target) and solves it by Brent's method on the phase mean (of e_N on a
piecewise-affine map's pieces, ``affine_phase``; else drop by drop, ``delivered``); the result's
mean, drop by drop, is within ``MEAN_TOL`` of the target by the map.  Zero damping gives the most the
engine can deliver at that step: a larger target is out of reach.  So is any target when the
step is so coarse that the map is unstable (damping then raises the mean).  ``damping_for`` then
reports the mean nearest the target and the largest step (and the largest stiffness at the given
step) at which some damping reaches it.
"""

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

from contactalpha.validation import check_range

from .affine_phase import QUAD_TOL as AFFINE_TOL
from .affine_phase import phase_mean_affine
from .codes import P_MAX, P_MEAN, P_MIN, P_STD
from .delivered import PhaseStats, check_restitution, check_scene, over_phase_unchecked, step_limit
from .registry import stepper

# The phase mean at the solution is within this of the target (by the map).
MEAN_TOL = 1e-6
# Brent's tolerance on the damping, relative.
DAMPING_RTOL = 1e-12
# The bracket's ladder: from BRACKET_START over the contact time (the same ladder for every call,
# so that an answer does not hang on a first guess where a coarse step makes the mean non-monotone),
# doubled at most BRACKET_DOUBLINGS times.
BRACKET_START = 1e-2
BRACKET_DOUBLINGS = 48
# Step (or stiffness) search for an unreachable target: factor per trial and trials at most.
SHRINK = 2.0 ** -0.25
SHRINK_TRIALS = 80
BISECTIONS = 6


@dataclass(frozen=True)
class StepInverse:
    """The engine's damping for a target mean restitution at a step.

    Attributes
    ----------
    damping : the engine's own damping parameter (NaN when out of reach).
    p : the engine's parameters with it (``damping`` slots set; zero damping when out of reach).
    stats : ``PhaseStats`` at ``p``: mean (the target within ``MEAN_TOL``), range, steps.
    status : "ok", "unreachable" (no damping delivers the target at this step) or "not_converged".
    nearest : the mean nearest the target that the damping scan met, when unreachable.
    timestep_reachable : the largest step (s) at which some damping reaches the target (NaN when
        reachable at the given step, or not found).
    stiffness_reachable : the largest value of the stiffness slot at which some damping reaches
        the target at the given step (NaN likewise, or not searched; None for a map without a
        stiffness slot).
    """

    damping: float
    p: np.ndarray
    stats: PhaseStats
    status: str
    nearest: float
    timestep_reachable: float
    stiffness_reachable: float


def _mean(engine, p, h, v, a, restitution):
    """The phase mean alone: on the affine pieces where the map has them (e_N), else drop by drop.

    The scene was checked where it entered (``damping_for``; a smaller step in the searches below
    keeps v >= a h / 2).  Where the affine sweep gives no number (its quadrature's budget) the
    drop-by-drop quadrature answers, as it does for eps.
    """
    s = stepper(engine)
    if restitution == "kinematic" and s.affine:
        m = float(phase_mean_affine(s.code, p, h, v, a, step_limit(s, p, h), AFFINE_TOL)[P_MEAN])
        if math.isfinite(m):
            return m
    return over_phase_unchecked(s, p, h, v, a).of(restitution)[0]


def _stats(engine, p, h, v, a, restitution):
    """``PhaseStats`` drop by drop (eps, steps), once per answer; e_N's from the affine pieces where the map has them.

    The drop-by-drop quadrature can run out of intervals (it then keeps an estimate, off by up to
    5e-4 in e_N where the affine mean is exact); the answer's e_N statistics are the affine ones.
    """
    s = stepper(engine)
    st = over_phase_unchecked(s, p, h, v, a)
    if restitution == "kinematic" and s.affine:
        row = phase_mean_affine(s.code, p, h, v, a, step_limit(s, p, h), AFFINE_TOL)
        if math.isfinite(row[P_MEAN]):
            st = replace(st, mean=float(row[P_MEAN]), minimum=float(row[P_MIN]), maximum=float(row[P_MAX]),
                         std=float(row[P_STD]))  # fmt: skip
    return st


def damping_for(
    engine, p, timestep, approach_speed, accel, target, restitution="kinematic", *, remedies=True
):
    """``StepInverse``: the damping slot of ``p`` whose phase-mean restitution is ``target``.

    Parameters
    ----------
    engine : str
        A name of ``registry.STEPPERS``.
    p : array
        The engine's parameters (the damping slots' values are ignored).
    timestep, approach_speed, accel : float
        Step (s), touchdown speed (m/s), load acceleration pressing in (m/s^2).
    target : float
        Target mean restitution in (0, 1).
    restitution : str
        "kinematic" (Newton's e_N) or "energetic" (Stronge's eps).
    remedies : bool or str
        When the target is out of reach: True searches the largest step that reaches it, "both"
        also the largest stiffness at the given step, False neither.
    """
    s = stepper(engine)
    p, h, v, a = check_scene(p, timestep, approach_speed, accel)
    target = float(check_range("target", target, 0.0, 1.0, lo_open=True, hi_open=True))
    check_restitution(restitution)
    def with_damping(c):
        q = p.copy()
        q[list(s.damping_slots)] = c
        return q

    top = _mean(engine, with_damping(0.0), h, v, a, restitution)
    lo, hi, bracketed, nearest = 0.0, None, False, top
    if top >= target:
        hi = BRACKET_START / s.contact_time(p)
        for _ in range(BRACKET_DOUBLINGS):
            m = _mean(engine, with_damping(hi), h, v, a, restitution)
            if abs(m - target) < abs(nearest - target):
                nearest = m
            if m < target:
                bracketed = True
                break
            lo, hi = hi, 2.0 * hi
    if not bracketed:
        # Out of reach at this step: no damping brings the mean down to, or up to, the target.
        step = stiff = math.nan
        if remedies:
            step = reachable_timestep(engine, p, h, v, a, target, restitution)
            if remedies == "both":
                stiff = reachable_stiffness(engine, p, h, v, a, target, restitution)
        st0 = _stats(engine, with_damping(0.0), h, v, a, restitution)
        return StepInverse(math.nan, with_damping(0.0), st0, "unreachable", nearest, step, stiff)
    root = brentq(lambda c: _mean(engine, with_damping(c), h, v, a, restitution) - target, lo, hi,
                  xtol=1e-300, rtol=DAMPING_RTOL)  # fmt: skip
    q = with_damping(root)
    st = _stats(engine, q, h, v, a, restitution)
    m = st.of(restitution)[0]
    status = "ok" if abs(m - target) <= MEAN_TOL else "not_converged"
    return StepInverse(root, q, st, status, math.nan, math.nan, math.nan)


def largest_passing(reaches, x0, shrink=SHRINK, trials=SHRINK_TRIALS, bisections=BISECTIONS):
    """The largest x < x0 with ``reaches(x)``: a geometric scan by ``shrink``, then bisection; NaN if none.

    ``reaches`` need not be monotone: the answer passes, and the scan's rung above it fails.
    """
    prev, x = x0, x0 * shrink
    for _ in range(trials):
        if reaches(x):
            break
        prev, x = x, x * shrink
    else:
        return math.nan
    lo, hi = x, prev
    for _ in range(bisections):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if reaches(mid) else (lo, mid)
    return lo


def _solved(engine, p, h, v, a, target, restitution):
    return damping_for(engine, p, h, v, a, target, restitution, remedies=False).status == "ok"


def reachable_timestep(engine, p, h, v, a, target, restitution="kinematic"):
    """The largest step below ``h`` at which some damping delivers the target phase mean (NaN if none)."""
    return largest_passing(lambda x: _solved(engine, p, x, v, a, target, restitution), h)


def reachable_stiffness(engine, p, h, v, a, target, restitution="kinematic"):
    """The largest stiffness below ``p``'s at which some damping delivers the target at step ``h``.

    The stiffness slots keep their ratios; the value returned is the first slot's.
    """
    s = stepper(engine)
    if not s.stiffness_slots:
        return None
    k = list(s.stiffness_slots)

    def reaches(x):
        q = p.copy()
        q[k] = x * p[k] / p[k[0]]
        return _solved(engine, q, h, v, a, target, restitution)

    return largest_passing(reaches, float(p[k[0]]))
