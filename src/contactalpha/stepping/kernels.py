"""The table of the engines' step maps: one compiled kernel serves every engine.

Numba cannot cache a kernel that takes a function argument (and compiles one copy per function,
seconds each), so the drop and phase kernels take an engine's *kernel code* and ``step_map``
dispatches on it, as ``laws.forces.scaled_force`` does for the laws.  Adding an engine's map is
its module with ``step_<engine>``, one code here and one branch in ``step_map``; the registry
(``registry.py``) carries the code with the engine's capabilities.
"""

import numpy as np
from numba import njit

from . import mujoco_map, pybullet_map
from .drake_map import step_drake
from .mujoco_map import branch_mujoco, branches_mujoco, step_mujoco
from .pybullet_map import branch_pybullet, branches_pybullet, step_pybullet

# Kernel codes: the position of each engine's step in ``step_map``'s table.
MUJOCO = 0
PYBULLET = 1
DRAKE = 2


@njit(cache=True)
def step_map(code: int, z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One step of the engine with kernel code ``code`` (the table above): ``(z, w)`` after it."""
    if code == PYBULLET:
        return step_pybullet(z, w, p, h, accel)
    if code == DRAKE:
        return step_drake(z, w, p, h, accel)
    return step_mujoco(z, w, p, h, accel)


# Piecewise-affine maps (``affine_phase``): linear forms in the state pick a step's branch, and
# the step is affine on each (branch 0 applies no force).  Codes of maps that are not piecewise
# affine (Drake's Hunt-Crossley step) have no entry.
AFFINE = {
    MUJOCO: (mujoco_map.N_FORMS, mujoco_map.N_BRANCHES),
    PYBULLET: (pybullet_map.N_FORMS, pybullet_map.N_BRANCHES),
}
MAX_FORMS = max(forms for forms, _ in AFFINE.values())
MAX_BRANCHES = max(count for _, count in AFFINE.values())


@njit(cache=True)
def surface(code: int, p: np.ndarray) -> float:
    """Height in the map's ``z`` of the surface a user reads a drop at.

    PyBullet's geometric surface lies ``slop`` above its solver's (``pybullet_map``); the other
    engines' surfaces are the same.
    """
    if code == PYBULLET:
        return p[pybullet_map.SLOP]
    return 0.0


@njit(cache=True)
def branches(code: int, p: np.ndarray, h: float, accel: float, forms: np.ndarray, maps: np.ndarray) -> int:
    """Fill the map's branch forms and affine steps (``<engine>_map.branches_<engine>``); the forms' count.

    They are written in the height above ``surface`` (``zeta = z - surface``), where a drop is read.
    """
    if code == PYBULLET:
        nf, nb = branches_pybullet(p, h, accel, forms, maps), pybullet_map.N_BRANCHES
    else:
        nf, nb = branches_mujoco(p, h, accel, forms, maps), mujoco_map.N_BRANCHES
    zs = surface(code, p)
    if zs != 0.0:
        for i in range(nf):
            forms[i, 2] += forms[i, 0] * zs
        for b in range(nb):
            maps[b, 2] += maps[b, 0] * zs - zs
            maps[b, 5] += maps[b, 3] * zs
    return nf


@njit(cache=True)
def branch_of(code: int, vals: np.ndarray) -> int:
    """The branch picked by the forms' values ``vals`` at a state."""
    if code == PYBULLET:
        return branch_pybullet(vals)
    return branch_mujoco(vals)
