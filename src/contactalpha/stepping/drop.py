"""A whole drop through any engine's step map, from the exact free-flight parabola (``flight``).

The drop starts at ``flight.touchdown_state`` and is stepped by the engine's map until (heights
and speeds read at ``kernels.surface``: PyBullet's geometric surface, 1e-5 m above its solver's):

- **separation**: after the contact's first force, the first stored state above the surface
  (z > 0), what a user samples in the engine: e_N is the exit speed ``flight.rebound_speed`` of
  the free parabola through it over ``v_in``, whether the body then rises or lands again within
  the next step (a *short hop*, shorter than a step, under a heavy load at a coarse step).  The
  state is read at the end of the free step from it (the same parabola); where that step applies a
  force at once (PyBullet's speculative row on a re-landing), at the state itself;
- **capture** (e_N = 0): after the contact's first force the body rose and then turned down
  again in contact, below the surface, or came to rest in contact (velocity and its change over
  a step below ``flight.REST_FRACTION`` of ``v_in``), or still creeps slower than
  ``CREEP_FRACTION`` of ``v_in`` in contact when the steps run out (an overdamped contact
  creeping to rest);
- **failure**: a non-finite state, or the steps ran out: NaN.

A step applies a contact force when its end velocity differs from free flight's ``w - h a``
(every map computes free flight exactly so).  The steps in contact counted are the steps with a
force.  Stronge's coefficient comes from the energy identity with the deepest sampled
penetration ``d_max``: ``eps^2 = (v_out^2/2 + a d_max) / (v_in^2/2 + a d_max)``; a captured drop
ending at depth ``d_end`` has ``eps^2 = a (d_max - d_end) / (v_in^2/2 + a d_max)``.

``run_drop`` takes the engine's kernel code (``kernels.MAPS``): one loop's source serves every
engine, compiled and cached once per engine (``kernels.for_engine``); ``drop_mujoco`` is the
interface's MuJoCo drop.
"""

import math

import numpy as np
from numba import njit

from .codes import CAPTURED, D_DMAX, D_EN, D_EPS, D_STATUS, D_STEPS, N_DROP, NON_FINITE, SEPARATED, STEP_LIMIT
from .flight import REST_FRACTION, rebound_speed, touchdown_state
from .kernels import DRAKE, MAP_CODE, MUJOCO, PYBULLET, engine_step, engine_surface, for_engine

# A body still in contact when the steps run out, creeping slower than this fraction of the
# approach speed, is captured too (an overdamped contact creeps to its rest without leaving).
CREEP_FRACTION = 1e-3


def run_drop(
    code: int, p: np.ndarray, h: float, phase: float, v_in: float, accel: float, max_steps: int
) -> np.ndarray:
    """One drop through the engine's step map; the row of ``codes.D_*`` slots.

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
    return for_engine(code, drop_kernel)(code, p, h, phase, v_in, accel, max_steps)


@njit(cache=True)
def drop_kernel(
    code: int, p: np.ndarray, h: float, phase: float, v_in: float, accel: float, max_steps: int
) -> np.ndarray:
    """``run_drop``'s kernel (a template of ``kernels.for_engine``)."""
    out = np.empty(N_DROP)
    zs = engine_surface(code, p)  # heights are read from the surface a user reads (``kernels.surface``)
    z, w = touchdown_state(v_in, accel, h, phase)
    z += zs
    n = 0
    rising = False
    d_max = 0.0
    w_c = 0.5 * v_in * v_in
    rest = REST_FRACTION * v_in
    status = STEP_LIMIT
    for _ in range(max_steps):
        z1, w1 = engine_step(code, z, w, p, h, accel)
        if not (math.isfinite(z1) and math.isfinite(w1)):
            status = NON_FINITE
            break
        forced = w1 != w - h * accel
        if n > 0 and z > zs:  # the first sample above the surface after the contact
            v_out = rebound_speed(z - zs, w, accel, h) if forced else rebound_speed(z1 - zs, w1, accel, h)
            out[D_EN] = v_out / v_in
            out[D_EPS] = math.sqrt((0.5 * v_out * v_out + accel * d_max) / (w_c + accel * d_max))
            status = SEPARATED
            break
        if forced:
            n += 1
        if n > 0:
            d_max = max(d_max, zs - z1)
            if w1 > 0.0:
                rising = True
            elif rising or (abs(w1) <= rest and abs(w1 - w) <= rest):
                status = CAPTURED
                z = z1
                break
        z, w = z1, w1
    if status == STEP_LIMIT and n > 0 and z < zs and abs(w) <= CREEP_FRACTION * v_in:
        status = CAPTURED
    if status == CAPTURED:
        out[D_EN] = 0.0
        out[D_EPS] = math.sqrt(max(accel * (d_max + z - zs) / (w_c + accel * d_max), 0.0))
    elif status != SEPARATED:
        out[D_EN] = math.nan
        out[D_EPS] = math.nan
    out[D_STEPS] = n
    out[D_DMAX] = d_max
    out[D_STATUS] = status
    return out


@njit(cache=True)
def drops_kernel(
    code: int, p: np.ndarray, h: float, phases: np.ndarray, v_in: float, accel: float, max_steps: int
) -> np.ndarray:
    """``run_drops``' kernel (a template of ``kernels.for_engine``)."""
    rows = np.empty((phases.size, N_DROP))
    for i in range(phases.size):
        row = drop_kernel(code, p, h, phases[i], v_in, accel, max_steps)
        for j in range(N_DROP):  # not ``rows[i] = row``: a slice assignment compiles numba's shape error
            rows[i, j] = row[j]
    return rows


def run_drops(
    code: int, p: np.ndarray, h: float, phases: np.ndarray, v_in: float, accel: float, max_steps: int
) -> np.ndarray:
    """``run_drop`` at every phase: one row of ``codes.D_*`` slots per phase."""
    return for_engine(code, drops_kernel)(code, p, h, phases, v_in, accel, max_steps)


@njit(cache=True)
def trajectory_kernel(
    code: int, p: np.ndarray, h: float, phase: float, v_in: float, accel: float, n_steps: int
) -> tuple[np.ndarray, np.ndarray]:
    """``trajectory``'s kernel (a template of ``kernels.for_engine``)."""
    zs = np.empty(n_steps + 1)
    ws = np.empty(n_steps + 1)
    zs[0], ws[0] = touchdown_state(v_in, accel, h, phase)
    zs[0] += engine_surface(code, p)
    for i in range(n_steps):
        zs[i + 1], ws[i + 1] = engine_step(code, zs[i], ws[i], p, h, accel)
    return zs, ws


def trajectory(
    code: int, p: np.ndarray, h: float, phase: float, v_in: float, accel: float, n_steps: int
) -> tuple[np.ndarray, np.ndarray]:
    """The stored states ``(z, w)`` (the map's z) of ``n_steps`` steps from ``run_drop``'s start (row 0)."""
    return for_engine(code, trajectory_kernel)(code, p, h, phase, v_in, accel, n_steps)


@njit(cache=True)
def engine_drop(
    p: np.ndarray, h: float, phase: float, v_in: float, accel: float, max_steps: int
) -> tuple[float, int, int]:
    """A whole drop through the map of ``MAP_CODE`` (a template: ``drop_<engine>`` below).

    Returns ``(e_N, n_contact_steps, status)``.
    """
    code = np.int64(MAP_CODE)  # not a literal: the one compiled copy of drop_kernel, not a second
    row = drop_kernel(code, p, h, phase, v_in, accel, max_steps)  # type: ignore[arg-type]
    return row[D_EN], int(row[D_STEPS]), int(row[D_STATUS])


# The interface's whole drops, one compiled kernel per engine: ``(e_N, n_contact_steps, status)``.
drop_mujoco = for_engine(MUJOCO, engine_drop)  # MuJoCo (``mujoco_map``)
drop_pybullet = for_engine(PYBULLET, engine_drop)  # PyBullet (``pybullet_map``)
drop_drake = for_engine(DRAKE, engine_drop)  # Drake's discrete plant (``drake_map``)
