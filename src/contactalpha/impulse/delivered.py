"""What an impulse engine's contact delivers: one drop, and its statistics over the touchdown phase.

A drop starts in free flight a fraction ``phase`` of a step before its parabola meets the
geometric surface at ``approach_speed`` (``stepping.flight.touchdown_state``) and runs the
engine's step (``kernels.step_impulse``: PyBullet's or PhysX's map) until

- **separated**: a sample after the first step with an impulse moves up and the step from it is
  free (``free_steps``' rule: the velocity changes by ``-a h`` and the position by ``h`` times the
  new velocity; PhysX's position iterations can push a body out of a penetration and give its
  velocity back, a step whose impulse shows only in the position); e_N is its parabola's speed
  at the surface over the approach speed (``stepping.flight.rebound_speed``: what a drop test
  reads from the rebound height), wherever the speculative contact left the ball (above the
  surface, mostly);
- **captured**: a step with an impulse leaves the ball at rest on the solver's surface (its speed
  under ``REST_FRACTION`` of the approach speed and its height within that fraction of a step's
  travel of the surface: the approach below the velocity threshold), or the
  contact *chatters*: ``CHATTER_STEPS`` steps in a row with an impulse and no free step (under a
  load whose ``a h`` exceeds the threshold the ball hops within the contact point's reach every
  step and never leaves): e_N = 0;
- neither within ``max_steps``: the step limit, e_N NaN.

``phase_stats`` evaluates ``n`` drops at the midpoints of ``n`` equal phase intervals: their mean
is the phase mean (a midpoint rule; e_N is piecewise smooth in the phase, with jumps where the
step the contact point catches changes), and their minimum and maximum the range one drop sees.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from contactalpha.stepping.codes import CAPTURED, DROP_STATUS, SEPARATED, STEP_LIMIT
from contactalpha.stepping.flight import rebound_speed, touchdown_state

from .kernels import BULLET, step_impulse, surface

# A captured body's speed, as a fraction of the approach speed.
REST_FRACTION = 1e-9
# Steps in a row with an impulse after which a contact that has not let go counts as captured.
CHATTER_STEPS = 200
# Steps a drop may take (flight to touchdown, contact, to separation or rest).
MAX_STEPS = 100_000
# Phases of ``phase_stats`` by default: midpoints of this many equal intervals.
PHASES = 4096


@njit(cache=True)
def drop_impulse(code, p, h, phase, v_in, accel, max_steps=MAX_STEPS):
    """``(e_N, steps with an impulse, status)`` of one drop through engine ``code``'s map (``kernels``)."""
    z, w = touchdown_state(v_in, accel, h, phase)
    rest = surface(code, p)
    contact = 0
    run = 0
    for _ in range(max_steps):
        z_next, w_next = step_impulse(code, z, w, p, h, accel)
        pushed = w_next != w - h * accel or abs(z_next - z - h * w_next) > REST_FRACTION * v_in * h
        if not pushed and contact > 0 and w > 0.0:
            return rebound_speed(z, w, accel, h) / v_in, contact, SEPARATED
        z, w = z_next, w_next
        run = run + 1 if pushed else 0
        if pushed:
            contact += 1
            at_rest = abs(w) <= REST_FRACTION * v_in and abs(z - rest) <= REST_FRACTION * v_in * h
            if at_rest or run >= CHATTER_STEPS:
                return 0.0, contact, CAPTURED
    return np.nan, contact, STEP_LIMIT


@njit(cache=True)
def drop_bullet(p, h, phase, v_in, accel, max_steps=MAX_STEPS):
    """``drop_impulse`` through PyBullet's map."""
    return drop_impulse(BULLET, p, h, phase, v_in, accel, max_steps)


@njit(cache=True)
def phase_drops(p, h, v_in, accel, n, code=BULLET):
    """e_N, steps with an impulse and status of the drops at the ``n`` midpoint phases."""
    e = np.empty(n)
    steps = np.empty(n, dtype=np.int64)
    status = np.empty(n, dtype=np.int64)
    for i in range(n):
        e[i], steps[i], status[i] = drop_impulse(code, p, h, (i + 0.5) / n, v_in, accel, MAX_STEPS)
    return e, steps, status


@dataclass(frozen=True)
class ImpulseStats:
    """e_N over a uniform touchdown phase: ``mean``, ``minimum``, ``maximum``, ``std``.

    ``steps`` (fewest, most): steps with an impulse; ``captured``: the fraction of phases that
    do not bounce; ``status``: "separated", "captured" (every phase) or why it is NaN;
    ``phase_min``, ``phase_max``: the phases of the minimum and the maximum.
    """

    mean: float
    minimum: float
    maximum: float
    std: float
    steps: tuple
    captured: float
    status: str
    phase_min: float = float("nan")
    phase_max: float = float("nan")


def phase_stats(
    p: np.ndarray, h: float, v_in: float, accel: float, n: int = PHASES, code: int = BULLET
) -> ImpulseStats:
    """``ImpulseStats`` of the drops at ``n`` midpoint phases of a step ``h`` (s), engine ``code``."""
    e, steps, status = phase_drops(p, float(h), float(v_in), float(accel), int(n), int(code))
    if np.any(status == STEP_LIMIT):
        nan = float("nan")
        return ImpulseStats(
            nan, nan, nan, nan, (int(steps.min()), int(steps.max())), nan, DROP_STATUS[STEP_LIMIT]
        )
    captured = float(np.mean(status == CAPTURED))
    word = DROP_STATUS[CAPTURED] if captured == 1.0 else DROP_STATUS[SEPARATED]
    return ImpulseStats(
        float(e.mean()), float(e.min()), float(e.max()), float(e.std()),
        (int(steps.min()), int(steps.max())), captured, word,
        (int(np.argmin(e)) + 0.5) / n, (int(np.argmax(e)) + 0.5) / n,
    )  # fmt: skip


@dataclass(frozen=True)
class Bounces:
    """A drop sequence read from per-step states: each rebound's speed and when it lands again (s)."""

    rebound_speeds: np.ndarray
    landings: np.ndarray

    @property
    def count(self) -> int:
        """The number of bounces."""
        return int(self.rebound_speeds.size)


def free_steps(z: np.ndarray, w: np.ndarray, accel: float, h: float, w_tol: float, z_tol: float):
    """Whether each step between per-step states is free flight (``len(z) - 1`` booleans).

    Free: the velocity changed by ``-a h`` (within ``w_tol``, m/s) and the position by ``h`` times
    the new velocity (within ``z_tol``, m), as the engines' semi-implicit Euler steps a free body.
    A step that pushed only the position (PhysX's TGS position iterations take a penetration out
    and the clamped impulse gives the velocity back) is not free: the flight starts after it.
    """
    z, w = np.asarray(z, dtype=float), np.asarray(w, dtype=float)
    return (np.abs(np.diff(w) + accel * h) <= w_tol) & (np.abs(np.diff(z) - h * w[1:]) <= z_tol)


def read_bounces(
    z: np.ndarray, w: np.ndarray, accel: float, h: float, free_rtol: float = 1e-9, z_atol: float = 0.0
) -> Bounces:
    """The bounces in per-step states (``z`` height above the plane, m; ``w`` up, m/s; from t = 0).

    A bounce is a step with an impulse (a velocity change other than ``-a h``) after which the body
    moves up (faster than the reading resolves: ``free_rtol`` of the scale; a landing in single
    precision can read a float's step above the plane, moving up at 1e-12 m/s) and either is above
    the plane or flies the next step freely (a landing leaves it on
    the solver's surface, below the plane, or still moving down; a lift by the ERP is followed by
    more impulses).  A free step is ``free_steps``' (its position within ``resolution h`` or
    ``z_atol``, m: the reading's position resolution, a single-precision engine's float step).
    Its speed is its parabola's at the plane, and it lands again ``2 u / a`` after
    that parabola left the plane.
    """
    z, w = np.asarray(z, dtype=float), np.asarray(w, dtype=float)
    resolution = free_rtol * max(accel * h, float(np.abs(w).max()))
    free = free_steps(z, w, accel, h, resolution, max(resolution * h, z_atol))
    speeds, landings = [], []
    for j in range(1, w.size - 1):
        if not free[j - 1] and w[j] > resolution and (z[j] > 0.0 or free[j]):
            u = rebound_speed(z[j], w[j], accel, h)
            slope = w[j] - 0.5 * accel * h
            left = j * h + (slope - np.sqrt(max(slope * slope + 2.0 * accel * z[j], 0.0))) / accel
            speeds.append(u)
            landings.append(left + 2.0 * u / accel)
    return Bounces(np.array(speeds), np.array(landings))
