"""The inverse at an impulse engine's step: the restitution and the velocity threshold to set.

- ``restitution_for``: the pair's (combined) restitution whose phase-mean e_N at the engine's step,
  under the scene's load, is the target (Brent's method on ``delivered.phase_stats``' mean, which
  rises with the coefficient); each body then gets ``per_body`` of it (Bullet multiplies the two
  bodies' values);
- ``threshold_for``: the velocity threshold at which half the touchdown phases of a drop at the
  loaded contact's critical speed stop bouncing: above the critical speed the engine bounces, below
  it not, as the compliant contact does (the engine compares the threshold with the speed of the
  step its contact acts in, which lies up to ``a h`` above the approach speed: the phase decides
  within that band).
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from . import bullet_map as bm
from .delivered import PHASES, ImpulseStats, phase_drops, phase_stats

# The largest pair restitution searched (Bullet takes any value; above 1 the row asks for more
# speed than came in, which the load can need).
MAX_RESTITUTION = 4.0
# Tolerance of the root in the coefficient, and the phases of the threshold's captured fraction.
XTOL = 1e-12
THRESHOLD_PHASES = 1024


@dataclass(frozen=True)
class RestitutionAnswer:
    """``restitution`` (the pair's, NaN when unreachable), ``stats`` with it, ``status``, ``nearest``."""

    restitution: float
    stats: ImpulseStats | None
    status: str
    nearest: float


def per_body(pair: float) -> float:
    """Each body's restitution for a pair value (``btManifoldResult::calculateCombinedRestitution``: a product)."""
    return math.sqrt(pair)


def _mean(e, radius, threshold, h, v, a, n):
    return phase_stats(bm.make_params(e, radius, threshold), h, v, a, n).mean


def restitution_for(target: float, h: float, v: float, a: float, radius: float,
                    threshold: float = bm.VELOCITY_THRESHOLD, n: int = PHASES) -> RestitutionAnswer:  # fmt: skip
    """The pair restitution whose mean e_N over ``n`` midpoint phases is ``target``."""
    lo, hi = _mean(0.0, radius, threshold, h, v, a, n), _mean(MAX_RESTITUTION, radius, threshold, h, v, a, n)
    if not (lo <= target <= hi):
        return RestitutionAnswer(math.nan, None, "unreachable", lo if target < lo else hi)
    e = brentq(lambda x: _mean(x, radius, threshold, h, v, a, n) - target, 0.0, MAX_RESTITUTION, xtol=XTOL)
    return RestitutionAnswer(e, phase_stats(bm.make_params(e, radius, threshold), h, v, a, n), "ok", math.nan)


def captured_fraction(threshold: float, restitution: float, radius: float, h: float, v: float, a: float,
                      n: int = THRESHOLD_PHASES) -> float:  # fmt: skip
    """The fraction of ``n`` midpoint touchdown phases at speed ``v`` that do not bounce."""
    e, _, status = phase_drops(bm.make_params(restitution, radius, threshold), h, v, a, n)
    return float(np.mean(e == 0.0))


def threshold_for(critical: float, restitution: float, radius: float, h: float, a: float) -> float:
    """The velocity threshold (m/s) at which half the phases of a touchdown at ``critical`` m/s stop.

    ``critical`` is the loaded contact's critical approach speed (``scene.threshold.critical_speed``);
    0 (every impact separates) gives 0.
    """
    if critical <= 0.0:
        return 0.0
    hi = critical + 2.0 * a * h + critical

    def excess(t):
        return captured_fraction(t, restitution, radius, h, critical, a) - 0.5

    if excess(hi) < 0.0:
        return math.nan
    lo = 0.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if excess(mid) < 0.0 else (lo, mid)
    return hi
