"""The impulse engines' steps behind one kernel code (numba), as ``stepping.kernels`` for the others.

``step_impulse(code, z, w, p, h, accel)`` is one step of the engine ``code`` names
(``BULLET``: ``bullet_map.step_bullet``; ``PHYSX``: ``physx_map.step_physx``), and
``surface(code, p)`` the height (above the plane) its solver holds a body at rest.
"""

from numba import njit

from . import bullet_map, physx_map

BULLET = 0
PHYSX = 1


@njit(cache=True)
def step_impulse(code, z, w, p, h, accel):
    """One step of engine ``code`` from ``(z, w)``."""
    if code == PHYSX:
        return physx_map.step_physx(z, w, p, h, accel)
    return bullet_map.step_bullet(z, w, p, h, accel)


@njit(cache=True)
def surface(code, p):
    """The height (m, above the plane) at which engine ``code``'s contact holds a body at rest."""
    if code == PHYSX:
        return 0.0
    return -p[bullet_map.SLOP]
