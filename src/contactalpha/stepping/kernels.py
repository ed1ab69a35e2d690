"""The table of the engines' step maps: one compiled kernel serves every engine.

Numba cannot cache a kernel that takes a function argument (and compiles one copy per function,
seconds each), so the drop and phase kernels take an engine's *kernel code* and ``step_map``
dispatches on it, as ``laws.forces.scaled_force`` does for the laws.  Adding an engine's map is
its module with ``step_<engine>``, one code here and one branch in ``step_map``; the registry
(``registry.py``) carries the code with the engine's capabilities.
"""

from numba import njit

from .drake_map import step_drake
from .mujoco_map import step_mujoco
from .pybullet_map import step_pybullet

# Kernel codes: the position of each engine's step in ``step_map``'s table.
MUJOCO = 0
PYBULLET = 1
DRAKE = 2


@njit(cache=True)
def step_map(code, z, w, p, h, accel):
    """One step of the engine with kernel code ``code`` (the table above): ``(z, w)`` after it."""
    if code == PYBULLET:
        return step_pybullet(z, w, p, h, accel)
    if code == DRAKE:
        return step_drake(z, w, p, h, accel)
    return step_mujoco(z, w, p, h, accel)
