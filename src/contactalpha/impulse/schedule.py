"""A restitution set each step: every touchdown rebounds as the loaded contact does, at any phase.

One constant coefficient delivers the target only on average over the touchdown phase: at
PyBullet's 1/240 s one drop's e_N spreads over tens of percent of it (the speculative contact
removes the remaining gap in the step that bounces), a loaded contact's e_N changes with the
approach speed (it falls towards the critical speed, below which it does not bounce), and the
impulse takes no time where the loaded contact lasts a while.  PyBullet lets a user change a
body's ``restitution`` before every step (``changeDynamics``), and the step's map (``bullet_map``)
is exact, so the coefficient for the coming step can be solved from the stored state.

``Rebounder(schedule).restitution(z, w)``, called before every step with the stored state
(height above the plane, m; velocity up, m/s), runs each contact in three parts:

1. **touchdown**: the first step whose free step would end below the solver's surface.  The
   approach speed ``v`` is the state's parabola's speed at the plane (``flight.rebound_speed``) and
   the touchdown time where that parabola meets it.  Restitution 0 this step: the row lands the
   body on the surface (the speculative row takes out the gap, the penetrating one the depth);
2. **hold**: restitution 0 while the loaded contact would still last (``durations``), the body
   resting on the solver's surface (its approach ``v* = -a h`` each step keeps the row's
   restitution able to act).  A body the held step would leave with ``v* >= 0`` (deep below the
   surface, where the contact point appeared only after it crossed, the position correction lifts
   it faster than ``a h``) is released at once instead, since restitution acts only on an
   approach; that contact's duration is lost (the next releases make up for it);
3. **release**: in the step whose launch meets the plane, going up, nearest the loaded contact's
   release time (touchdown + duration), the coefficient that sends the body off at
   ``u = e_N(v) v``, solved on the engine's step map (for Bullet's row it is the closed form
   ``w' = sqrt(u^2 - 2 a z) - a h / 2``, ``w' = e |v*| + positional``).  Below the critical speed
   ``u = 0``: the body stays.

The rebound speed is then the loaded contact's (to the table's interpolation), and each release
within half a step of the loaded contact's: the runner keeps how late the releases so far came and
asks the next one that much earlier, so the error does not add up over a sequence.  A flight
shorter than about a step (``u`` below ``a h``) lands in the step after it leaves: a height
reading sees one sample above the plane, or none.  The engine's ``restitutionVelocityThreshold``
must be 0 (the schedule is the threshold), and the value is the pair's: set it on the ball with
the plane's restitution 1 (Bullet multiplies the two).
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contactalpha.stepping.flight import rebound_speed

from .inverse import MAX_RESTITUTION
from .kernels import step_impulse
from .registry import impulse_engine

# The parts of a contact (``Rebounder.part``).
FLIGHT, HOLD, REST = 0, 1, 2


@dataclass(frozen=True)
class TouchdownSchedule:
    """The loaded contact per approach speed, and the engine's step it is set at.

    Attributes
    ----------
    speeds : approach speeds, m/s, ascending (interpolated in log speed; held beyond the ends).
    e_n : the loaded contact's e_N at each.
    durations : its contact's duration at each, s.
    critical : the critical approach speed, m/s: below it e_N is 0 and the body stays.
    accel, timestep : the load's acceleration (m/s^2) and the engine's step (s).
    radius : the sphere's radius, m (PyBullet's contact breaking threshold reads it).
    engine : the impulse engine (``registry.ENGINES``) whose step map solves each coefficient.
    """

    speeds: np.ndarray
    e_n: np.ndarray
    durations: np.ndarray
    critical: float
    accel: float
    timestep: float
    radius: float
    engine: str = "pybullet_impulse"

    def target(self, v: float) -> tuple[float, float]:
        """``(e_N, duration)`` of the loaded contact at approach speed ``v`` (m/s); e_N 0 below critical."""
        if v < self.critical or v <= 0.0:
            return 0.0, 0.0
        x, logs = math.log(v), np.log(self.speeds)
        return float(np.interp(x, logs, self.e_n)), float(np.interp(x, logs, self.durations))


class Rebounder:
    """The per-step restitution of one body under a ``TouchdownSchedule`` (the module docstring).

    ``restitution(z, w)`` is called once before every step, in order; ``time`` counts the steps.
    Each coefficient is solved on the engine's step map (``kernels.step_impulse``): the root of the
    rebound read after the step less the speed asked for (Brent's method; a release from rest,
    where the approach is ``a h``, takes a coefficient of several).
    """

    def __init__(self, schedule: TouchdownSchedule) -> None:
        self.schedule = schedule
        self.engine = impulse_engine(schedule.engine)
        self.time = 0.0
        self.part = FLIGHT
        self.rebound = 0.0  # the speed to leave at, m/s
        self.release = 0.0  # when to let go, s: the loaded contact's release less ``late``
        self.late = 0.0  # how much later than the loaded contact's the releases so far came, s

    def _step(self, z, w, e):
        s = self.schedule
        p = self.engine.params(e, s.radius, 0.0)
        return step_impulse(self.engine.code, z, w, p, s.timestep, s.accel)

    def restitution(self, z: float, w: float) -> float:
        """The pair restitution to set for the coming step from the stored state ``(z, w)``."""
        s, t = self.schedule, self.time
        a, h = s.accel, s.timestep
        self.time += h
        if self.part == REST:
            return 0.0
        z0, w0 = self._step(z, w, 0.0)
        if self.part == FLIGHT:
            if w0 == w - h * a:
                return 0.0  # no impulse this step even without restitution: no contact yet
            v = rebound_speed(z, w, a, h)
            e_n, duration = s.target(v)
            if e_n <= 0.0:
                self.part = REST
                return 0.0
            slope = w - 0.5 * a * h
            # when the state's parabola meets the plane (z + slope tau - a tau^2 / 2 = 0)
            touch = t + (slope + math.sqrt(max(slope * slope + 2.0 * a * z, 0.0))) / a
            self.part, self.rebound, self.release = HOLD, e_n * v, touch + duration - self.late
        # Holding lands the body (restitution 0); it can go on holding only if the next step still
        # approaches (v* < 0 there), since restitution acts only on an approach.
        can_hold = self.engine.holds and w0 - h * a < 0.0

        def gap(e: float) -> float:
            z_end, w_end = self._step(z, w, e)
            return rebound_speed(z_end, w_end, a, h) - self.rebound

        # from rest the approach is only a h: the coefficient can be the rebound over it, and more
        top = max(MAX_RESTITUTION, 4.0 * self.rebound / max(h * a - w, 1e-300))
        if gap(0.0) > 0.0 or gap(top) < 0.0:
            return 0.0  # no coefficient sends it off at that speed from here: land it
        e = brentq(gap, 0.0, top, xtol=1e-14, rtol=1e-14)
        z1, w1 = self._step(z, w, e)
        slope = w1 - 0.5 * a * h
        leaves = t + h + (slope - math.sqrt(max(slope * slope + 2.0 * a * z1, 0.0))) / a
        if leaves < self.release - 0.5 * h and can_hold:
            return 0.0  # hold: the loaded contact lasts on
        self.part = FLIGHT
        self.late = leaves - self.release
        return e
