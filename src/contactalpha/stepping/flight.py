"""Free flight under semi-implicit Euler: where a drop starts, how its rebound is read.

The engines update the velocity first and the position with the new velocity: ``w' = w - a h``,
``z' = z + h w'`` (z the height above the contact, w up).  Under a constant acceleration ``a``
the positions then lie exactly on a parabola whose velocity at a stored state is ``w - a h / 2``:

- a drop *arrives* with approach speed ``v_in`` when its parabola crosses z = 0 at that speed:
  ``touchdown_state`` gives the stored state a fraction ``phase`` of a step before the crossing
  (touchdown falls at ``phase`` of the first step);
- the *rebound* speed is the parabola's speed at z = 0 through a state in free flight after the
  contact: ``v_out = sqrt((w - a h/2)^2 + 2 a z)`` (``rebound_speed``); a drop test reads the
  same number from the rebound height.
"""

import math

import numpy as np
from numba import njit

# A body in contact whose velocity and its change over a step are both below this fraction of
# the approach speed is at rest: captured.
REST_FRACTION = 1e-10


@njit(cache=True)
def touchdown_state(v_in: float, accel: float, h: float, phase: float) -> tuple[float, float]:
    """Stored ``(z, w)`` a fraction ``phase`` of a step before the parabola meets z = 0 at ``-v_in``."""
    tc = phase * h
    w = -v_in + accel * tc  # the parabola's velocity at the start
    z0 = -(w * tc - 0.5 * accel * tc * tc)
    return z0, w + 0.5 * accel * h


@njit(cache=True)
def rebound_speed(z: float, w: float, accel: float, h: float) -> float:
    """Speed at z = 0 of the free-flight parabola through the stored state ``(z, w)``."""
    s = w - 0.5 * accel * h
    return math.sqrt(max(s * s + 2.0 * accel * z, 0.0))


@njit(cache=True)
def euler_affine(out: np.ndarray, h: float, wz: float, ww: float, w1: float) -> None:
    """A step ``w' = wz z + ww w + w1``, then ``z' = z + h w'``, written into ``out``.

    As ``z' = out[0:3] . (z, w, 1)``, ``w' = out[3:6] . (z, w, 1)``.
    """
    out[3], out[4], out[5] = wz, ww, w1
    out[0], out[1], out[2] = 1.0 + h * wz, h * ww, h * w1
