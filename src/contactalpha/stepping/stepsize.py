"""The step a scene needs: the largest step at which one drop stays within a tolerance of the target.

At a step ``h`` the damping is set for the target phase mean (``inverse.damping_for``); one
drop then sees a restitution anywhere in the phase range ``[minimum, maximum]``.  The range
narrows roughly in proportion to ``h`` over the contact time, but not monotonically (the steps
per contact are whole numbers), so ``step_for_tolerance`` scans down a geometric ladder of steps
from a few steps per contact, takes the first step that passes *and* whose next smaller rung
passes too, then bisects between it and the failing rung above.
"""

import math
from dataclasses import dataclass

from numpy.typing import ArrayLike

from contactalpha.validation import check_range

from .delivered import check_restitution, check_scene
from .inverse import StepInverse, damping_for
from .registry import stepper

# The ladder starts at this many steps per contact time and falls by RUNG per trial.
START_STEPS = 2.0
RUNG = 2.0**-0.25
RUNGS = 80
BISECTIONS = 8


@dataclass(frozen=True)
class StepNeeded:
    """The largest step at which one drop stays within ``tol`` of the target.

    Attributes
    ----------
    timestep : the step, s (NaN when none on the ladder passes).
    inverse : ``inverse.StepInverse`` at that step (the damping, the predicted mean and range).
    steps_per_contact : the contact time over the step.
    fails_at : the nearest larger step tried at which a drop strays beyond ``tol`` (the answer is
        within a factor ``fails_at / timestep <= 1 / RUNG`` of the true boundary; the range is not
        monotone in the step, so some larger steps may pass by luck of the phase pattern).
    status : "ok" or "not_found".
    """

    timestep: float
    inverse: StepInverse | None
    steps_per_contact: float
    fails_at: float
    status: str


def within(inv: StepInverse, target: float, tol: float, restitution: str) -> bool:
    """True when the inverse succeeded and its phase range lies within ``target +- tol``."""
    if inv.status != "ok":
        return False
    _, lo, hi = inv.stats.of(restitution)
    return max(hi - target, target - lo) <= tol


def step_for_tolerance(
    engine: str,
    p: ArrayLike,
    approach_speed: float,
    accel: float,
    target: float,
    tol: float,
    restitution: str = "kinematic",
) -> StepNeeded:
    """``StepNeeded``: the largest step at which a single drop's restitution is within ``tol`` of ``target``.

    Parameters
    ----------
    engine : str
        A name of ``registry.STEPPERS``.
    p : array
        The engine's parameters (the damping slots are solved for at every step).
    approach_speed, accel : float
        Touchdown speed (m/s), load acceleration pressing in (m/s^2).
    target : float
        Target mean restitution in (0, 1).
    tol : float
        Allowed distance of a single drop from the target, in (0, 1).
    restitution : str
        "kinematic" (e_N) or "energetic" (eps).
    """
    s = stepper(engine)
    p, _, v, a = check_scene(p, 2.0 * approach_speed / accel, approach_speed, accel)
    target = float(check_range("target", target, 0.0, 1.0, lo_open=True, hi_open=True))
    tol = float(check_range("tol", tol, 0.0, 1.0, lo_open=True, hi_open=True))
    check_restitution(restitution)
    t_c = s.contact_time(p)

    def solve(h):
        return damping_for(engine, p, h, v, a, target, restitution, remedies=False)

    above = math.inf
    h = min(t_c / START_STEPS, (2.0 - 1e-9) * v / a)  # a step the drop's flight spans (delivered)
    found = None
    for _ in range(RUNGS):
        inv = solve(h)
        if within(inv, target, tol, restitution) and within(solve(h * RUNG), target, tol, restitution):
            found = (h, inv)
            break
        above, h = h, h * RUNG
    if found is None:
        return StepNeeded(math.nan, None, math.nan, math.nan, "not_found")
    lo, best = found
    hi = above
    for _ in range(BISECTIONS if math.isfinite(hi) else 0):
        mid = math.sqrt(lo * hi)
        inv = solve(mid)
        if within(inv, target, tol, restitution):
            lo, best = mid, inv
        else:
            hi = mid
    return StepNeeded(lo, best, t_c / lo, hi, "ok")
