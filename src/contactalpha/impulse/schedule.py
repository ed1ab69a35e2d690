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
   restitution able to act).  A body deep below the surface (the contact point appeared only
   after it crossed: ``v h`` above the breaking threshold) is released at once instead: holding it
   there would let the ERP lift it faster than ``a h`` (``v* > 0``), and restitution acts only on
   an approach; that contact's duration is lost (the next releases make up for it);
3. **release**: in the step whose launch meets the plane, going up, nearest the loaded contact's
   release time (touchdown + duration), the coefficient that sends the body off at
   ``u = e_N(v) v``: the step must end at ``w' = sqrt(u^2 - 2 a z) - a h / 2`` (the parabola
   through ``(z + h w', w')`` meets the plane at ``u``), and the row's ``w' = e |v*| + positional``
   gives ``e``.  Below the critical speed ``u = 0``: the body stays.

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

from contactalpha.stepping.flight import rebound_speed

from . import bullet_map as bm

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
    radius : the sphere's radius, m (its contact breaking threshold).
    erp : the engine's ``contactERP``.
    """

    speeds: np.ndarray
    e_n: np.ndarray
    durations: np.ndarray
    critical: float
    accel: float
    timestep: float
    radius: float
    erp: float = bm.CONTACT_ERP

    def target(self, v: float) -> tuple[float, float]:
        """``(e_N, duration)`` of the loaded contact at approach speed ``v`` (m/s); e_N 0 below critical."""
        if v < self.critical or v <= 0.0:
            return 0.0, 0.0
        x, logs = math.log(v), np.log(self.speeds)
        return float(np.interp(x, logs, self.e_n)), float(np.interp(x, logs, self.durations))


class Rebounder:
    """The per-step restitution of one body under a ``TouchdownSchedule`` (the module docstring).

    ``restitution(z, w)`` is called once before every step, in order; ``time`` counts the steps.
    """

    def __init__(self, schedule: TouchdownSchedule) -> None:
        self.schedule = schedule
        self.time = 0.0
        self.part = FLIGHT
        self.rebound = 0.0  # the speed to leave at, m/s
        self.release = 0.0  # when to let go, s: the loaded contact's release less ``late``
        self.late = 0.0  # how much later than the loaded contact's the releases so far came, s

    def restitution(self, z: float, w: float) -> float:
        """The pair restitution to set for the coming step from the stored state ``(z, w)``."""
        s, t = self.schedule, self.time
        a, h = s.accel, s.timestep
        self.time += h
        v_star = w - h * a
        d = z + bm.LINEAR_SLOP
        if self.part == FLIGHT:
            if d + h * v_star > 0.0:
                return 0.0  # the free step ends above the solver's surface: no contact yet
            v = rebound_speed(z, w, a, h)
            e_n, duration = s.target(v)
            slope = w - 0.5 * a * h
            # when the state's parabola meets the plane (z + slope tau - a tau^2 / 2 = 0)
            touch = t + (slope + math.sqrt(max(slope * slope + 2.0 * a * z, 0.0))) / a
            self.part, self.rebound = (HOLD, e_n * v) if e_n > 0.0 else (REST, 0.0)
            self.release = touch + duration - self.late
            return 0.0
        if self.part == REST or self.rebound * self.rebound < 2.0 * a * z:
            return 0.0
        w_end = math.sqrt(self.rebound**2 - 2.0 * a * z) - 0.5 * a * h
        z_end, slope = z + h * w_end, w_end - 0.5 * a * h
        leaves = t + h + (slope - math.sqrt(max(slope * slope + 2.0 * a * z_end, 0.0))) / a
        # Holding lands the body; below the surface the ERP then lifts it at -erp d / h, and a
        # lift faster than a h leaves no approach for the restitution to act on.
        can_hold = d > -bm.LINEAR_SLOP or -s.erp * d / h < h * a
        if leaves < self.release - 0.5 * h and can_hold:
            return 0.0  # hold: the loaded contact lasts on
        self.part = FLIGHT
        self.late = leaves - self.release
        positional = -d / h if d > 0.0 else -s.erp * d / h
        return max((w_end - positional) / -v_star, 0.0)
