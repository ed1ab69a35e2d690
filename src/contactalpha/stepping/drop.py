"""A whole drop through any engine's step map, from the exact free-flight parabola.

**Semi-implicit Euler in flight.**  The engines update the velocity first and the position with
the new velocity: ``w' = w - a h``, ``z' = z + h w'`` (z the height above the contact, w up).
Under a constant acceleration ``a`` the positions then lie exactly on a parabola whose velocity
at a stored state is ``w - a h / 2``.  So:

- a drop *arrives* with approach speed ``v_in`` when its parabola crosses z = 0 at that speed:
  ``touchdown_state`` gives the stored state a fraction ``phase`` of a step before the crossing
  (touchdown falls at ``phase`` of the first step);
- the *rebound* speed is the parabola's speed at z = 0 through the first state above the
  contact after it: ``v_out = sqrt((w - a h/2)^2 + 2 a z)`` (``rebound_speed``); a drop test
  reads the same number from the rebound height.

Stronge's coefficient comes from the energy identity with the deepest sampled penetration
``d_max``: ``eps^2 = (v_out^2/2 + a d_max) / (v_in^2/2 + a d_max)``; a drop that comes to rest
in contact at ``d_end`` (or still creeps there when the steps run out) has ``e_N = 0`` and ``eps^2 = a (d_max - d_end) / (v_in^2/2 + a d_max)``.

``run_drop`` takes the engine's kernel code (``kernels.step_map``), so one loop serves every
engine; ``drop_<engine>`` are the interface's per-engine drops.  A step that starts above the contact and moves up
must be free flight in every engine's map; a step that starts below it (z < 0) counts as a
contact step.
"""

import math

import numpy as np
from numba import njit

from .codes import D_EN, D_STATUS, D_STEPS
from .kernels import DRAKE, MUJOCO, PYBULLET, step_map
from .codes import CAPTURED, D_DMAX, D_EN, D_EPS, D_STATUS, D_STEPS, N_DROP, NON_FINITE, SEPARATED, STEP_LIMIT

# A body in contact whose velocity and its change over a step are both below this fraction of
# the approach speed is at rest: captured.
REST_FRACTION = 1e-10
# A body still in contact when the steps run out, creeping slower than this fraction of the
# approach speed, is captured too (an overdamped contact creeps to its rest without leaving).
CREEP_FRACTION = 1e-3


@njit(cache=True)
def touchdown_state(v_in, accel, h, phase):
    """Stored ``(z, w)`` a fraction ``phase`` of a step before the parabola meets z = 0 at ``-v_in``."""
    tc = phase * h
    w = -v_in + accel * tc  # the parabola's velocity at the start
    z0 = -(w * tc - 0.5 * accel * tc * tc)
    return z0, w + 0.5 * accel * h


@njit(cache=True)
def rebound_speed(z, w, accel, h):
    """Speed at z = 0 of the free-flight parabola through the stored state ``(z, w)``."""
    s = w - 0.5 * accel * h
    return math.sqrt(s * s + 2.0 * accel * z)


@njit(cache=True)
def run_drop(code, p, h, phase, v_in, accel, max_steps):
    """One drop through ``step``; the row of ``codes.D_*`` slots.

    Parameters
    ----------
    code : int
        The engine's kernel code (``kernels.step_map``).
    p : float64 array
        The engine's parameters (slots of the map's module).
    h : float
        Step, s.
    phase : float
        In [0, 1): where touchdown falls within its step.
    v_in : float
        Approach speed, m/s (> 0).
    accel : float
        Load acceleration pressing into the contact, m/s^2 (> 0).
    max_steps : int
        Steps at most.
    """
    out = np.empty(N_DROP)
    z, w = touchdown_state(v_in, accel, h, phase)
    entered = False
    n = 0
    d_max = 0.0
    w_c = 0.5 * v_in * v_in
    rest = REST_FRACTION * v_in
    status = STEP_LIMIT
    for _ in range(max_steps):
        if z < 0.0:
            entered = True
            n += 1
            d_max = max(d_max, -z)
        z1, w1 = step_map(code, z, w, p, h, accel)
        if not (math.isfinite(z1) and math.isfinite(w1)):
            status = NON_FINITE
            break
        if entered and z1 >= 0.0:
            v_out = rebound_speed(z1, w1, accel, h)
            out[D_EN] = v_out / v_in
            out[D_EPS] = math.sqrt((0.5 * v_out * v_out + accel * d_max) / (w_c + accel * d_max))
            out[D_STEPS] = n
            out[D_DMAX] = d_max
            out[D_STATUS] = SEPARATED
            return out
        if entered and abs(w1) <= rest and abs(w1 - w) <= rest:
            eps2 = accel * (d_max + z1) / (w_c + accel * d_max)
            out[D_EN] = 0.0
            out[D_EPS] = math.sqrt(max(eps2, 0.0))
            out[D_STEPS] = n
            out[D_DMAX] = d_max
            out[D_STATUS] = CAPTURED
            return out
        z, w = z1, w1
    if status == STEP_LIMIT and entered and z < 0.0 and abs(w) <= CREEP_FRACTION * v_in:
        out[D_EN] = 0.0
        out[D_EPS] = math.sqrt(max(accel * (d_max + z) / (w_c + accel * d_max), 0.0))
        out[D_STATUS] = CAPTURED
    else:
        out[D_EN] = math.nan
        out[D_EPS] = math.nan
        out[D_STATUS] = status
    out[D_STEPS] = n
    out[D_DMAX] = d_max
    return out


@njit(cache=True)
def run_drops(code, p, h, phases, v_in, accel, max_steps):
    """``run_drop`` at every phase: one row of ``codes.D_*`` slots per phase."""
    rows = np.empty((phases.size, N_DROP))
    for i in range(phases.size):
        rows[i] = run_drop(code, p, h, phases[i], v_in, accel, max_steps)
    return rows


@njit(cache=True)
def trajectory(code, p, h, phase, v_in, accel, n_steps):
    """The stored states ``(z, w)`` of ``n_steps`` steps from ``touchdown_state`` (row 0 the start)."""
    zs = np.empty(n_steps + 1)
    ws = np.empty(n_steps + 1)
    zs[0], ws[0] = touchdown_state(v_in, accel, h, phase)
    for i in range(n_steps):
        zs[i + 1], ws[i + 1] = step_map(code, zs[i], ws[i], p, h, accel)
    return zs, ws


@njit(cache=True)
def drop_mujoco(p, h, phase, v_in, accel, max_steps):
    """A whole MuJoCo drop (``mujoco_map``): ``(e_N, n_contact_steps, status)``."""
    row = run_drop(MUJOCO, p, h, phase, v_in, accel, max_steps)
    return row[D_EN], int(row[D_STEPS]), int(row[D_STATUS])


@njit(cache=True)
def drop_pybullet(p, h, phase, v_in, accel, max_steps):
    """A whole PyBullet drop (``pybullet_map``): ``(e_N, n_contact_steps, status)``."""
    row = run_drop(PYBULLET, p, h, phase, v_in, accel, max_steps)
    return row[D_EN], int(row[D_STEPS]), int(row[D_STATUS])


@njit(cache=True)
def drop_drake(p, h, phase, v_in, accel, max_steps):
    """A whole drop in Drake's discrete plant (``drake_map``): ``(e_N, n_contact_steps, status)``."""
    row = run_drop(DRAKE, p, h, phase, v_in, accel, max_steps)
    return row[D_EN], int(row[D_STEPS]), int(row[D_STATUS])
