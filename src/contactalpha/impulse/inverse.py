"""The inverse at an impulse engine's step: the restitution and the velocity threshold to set.

- ``restitution_for``: the pair's (combined) restitution whose phase-mean e_N at the engine's step,
  under the scene's load, is the target (Brent's method on ``delivered.phase_stats``' mean, which
  rises with the coefficient); each body then gets its share (``registry.ImpulseEngine.per_body``:
  Bullet multiplies the two bodies' values, PhysX averages them);
- ``threshold_for``: the velocity threshold that stops the bounces at the loaded contact's critical
  speed: above it the engine bounces, below it not, as the compliant contact does (the engine
  compares the threshold with the speed of the step its contact acts in, up to ``a h`` above the
  approach speed: within that band the phase decides).
"""

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from . import bullet_map as bm
from .delivered import PHASES, ImpulseStats, phase_stats
from .registry import impulse_engine

# The largest pair restitution searched (Bullet takes any value; above 1 the row asks for more
# speed than came in, which the load can need).
MAX_RESTITUTION = 4.0
# Tolerance of the root in the coefficient.
XTOL = 1e-12


@dataclass(frozen=True)
class RestitutionAnswer:
    """``restitution`` (the pair's, NaN when unreachable), ``stats`` with it, ``status``, ``nearest``."""

    restitution: float
    stats: ImpulseStats | None
    status: str
    nearest: float


def per_body(pair: float) -> float:
    """Each body's restitution for a pair value (``calculateCombinedRestitution`` multiplies them)."""
    return math.sqrt(pair)


def _mean(eng, e, radius, threshold, h, v, a, n):
    return phase_stats(eng.params(e, radius, threshold), h, v, a, n, eng.code).mean


def restitution_for(
    target: float,
    h: float,
    v: float,
    a: float,
    radius: float,
    threshold: float = bm.VELOCITY_THRESHOLD,
    n: int = PHASES,
    engine: str = "pybullet_impulse",
) -> RestitutionAnswer:
    """The pair restitution whose mean e_N over ``n`` midpoint phases of ``engine``'s step is ``target``.

    The mean rises with the coefficient, continuously except where a phase switches between
    bouncing and captured (a jump of that drop's e_N over ``n``): there the answer's mean is within
    such a jump of the target (``stats.mean`` says where it is).
    """
    eng = impulse_engine(engine)
    lo = _mean(eng, 0.0, radius, threshold, h, v, a, n)
    hi = _mean(eng, MAX_RESTITUTION, radius, threshold, h, v, a, n)
    if not (lo <= target <= hi):
        return RestitutionAnswer(math.nan, None, "unreachable", lo if target < lo else hi)
    e = brentq(
        lambda x: _mean(eng, x, radius, threshold, h, v, a, n) - target, 0.0, MAX_RESTITUTION, xtol=XTOL
    )
    stats = phase_stats(eng.params(e, radius, threshold), h, v, a, n, eng.code)
    return RestitutionAnswer(e, stats, "ok", math.nan)


def threshold_for(critical: float, h: float, a: float) -> float:
    """The velocity threshold (m/s) that stops the engine's bounces at the ``critical`` approach speed.

    The row compares the threshold with ``|v*|``, the speed at the end of the step its contact
    acts in after the step's gravity: for a touchdown at ``v`` within that step, ``v`` to
    ``v + a h``.  ``critical + a h / 2`` is its middle: a touchdown below ``critical - a h / 2``
    never bounces, one above ``critical + a h / 2`` is not stopped by the threshold, and between
    them the touchdown phase decides.  ``critical`` 0 (every impact separates) gives 0.
    """
    return critical + 0.5 * a * h if critical > 0.0 else 0.0
