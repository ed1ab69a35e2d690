"""Scaled contact forces of the law family, one jitted function each.

Every law moves as ``x'' = A - max(0, f(x, x'))`` in its own scaling (docs/laws.md), with
``x(0) = 0``, ``x'(0) = 1`` and ``A`` the scaled load; a law without the floor (``FLOORLESS``)
moves as ``x'' = A - f`` while ``x > 0``, its force pulling where ``f < 0``.  Each function
returns the force argument ``f`` *before* the floor ``max(0, .)``; it is 0 wherever ``x <= 0``
except for the offset of MuJoCo's soft contact.  Signature: ``f(x, v, p, A, s)`` with ``p`` the
law's damping parameter and ``s`` its shape parameter (MuJoCo's impedance ``d``; unused elsewhere).
"""

import numpy as np
from numba import njit

# Hertz stiffness of the scaled n = 3/2 laws: (5/4) x^{3/2}, unit undamped unloaded compression.
HERTZ = 1.25
# Tsuji's scaled damping per unit of beta: eta = beta sqrt(m k) gives gamma = beta sqrt(5) / 2.
TSUJI_GAMMA = 0.5 * np.sqrt(5.0)
# Scaled damping of Hertz with sqrt(delta) damping per unit of kappa: eta = kappa m^{2/5} k^{3/5} / v^{1/5}
# gives eta delta_s^{3/2} / (m v) = kappa (5/4)^{3/5}.
VISCOELASTIC_GAMMA = 1.25**0.6
# Tsuji's law without its floor: at zero load it is the linear oscillator y'' + gamma y' + (25/16) y = 0
# in y = x^{5/4} (docs/laws.md), overdamped, so never back to x = 0, from beta = sqrt(5) (zeta = 1).
TSUJI_UNLOADED_CRITICAL = np.sqrt(5.0)


@njit(cache=True, error_model="numpy")
def hunt_crossley_force(x, v, p, A, s):
    """Hunt-Crossley, n = 3/2: ``(5/4) x^{3/2} (1 + alpha v)``."""
    xp = max(x, 0.0)
    return HERTZ * xp * np.sqrt(xp) * (1.0 + p * v)


@njit(cache=True, error_model="numpy")
def hunt_crossley_linear_force(x, v, p, A, s):
    """Hunt-Crossley, n = 1 (Drake's point contact): ``x (1 + alpha v)``."""
    return max(x, 0.0) * (1.0 + p * v)


@njit(cache=True, error_model="numpy")
def kelvin_voigt_force(x, v, p, A, s):
    """Spring-dashpot: ``x + 2 zeta v`` (0 once separated)."""
    if x <= 0.0:
        return 0.0
    return x + 2.0 * p * v


@njit(cache=True, error_model="numpy")
def mujoco_soft_force(x, v, p, A, s):
    """MuJoCo's soft contact with impedance ``d = s``: ``d A + x + 2 zeta v``."""
    if x <= 0.0:
        return 0.0
    return s * A + x + 2.0 * p * v


@njit(cache=True, error_model="numpy")
def hertz_tsuji_force(x, v, p, A, s):
    """Hertz with Tsuji damping: ``(5/4) x^{3/2} + beta (sqrt 5 / 2) x^{1/4} v``."""
    if x <= 0.0:
        return 0.0
    q = np.sqrt(np.sqrt(x))
    return HERTZ * x * np.sqrt(x) + TSUJI_GAMMA * p * q * v


@njit(cache=True, error_model="numpy")
def hertz_viscoelastic_force(x, v, p, A, s):
    """Hertz with sqrt(delta) damping: ``(5/4) x^{3/2} + kappa (5/4)^{3/5} x^{1/2} v``."""
    if x <= 0.0:
        return 0.0
    r = np.sqrt(x)
    return HERTZ * x * r + VISCOELASTIC_GAMMA * p * r * v


# Kernel codes: the position of each law's force in ``scaled_force``'s table.  One compiled kernel
# serves every law (numba cannot cache a kernel that takes a function argument, and compiles one
# copy per function, seconds each).
HUNT_CROSSLEY = 0
HUNT_CROSSLEY_LINEAR = 1
KELVIN_VOIGT = 2
MUJOCO_SOFT = 3
HERTZ_TSUJI = 4
HERTZ_TSUJI_UNFLOORED = 5
HERTZ_VISCOELASTIC = 6
HERTZ_VISCOELASTIC_UNFLOORED = 7
# The laws whose force is not floored: it pulls where f < 0 until x = 0.
FLOORLESS = (HERTZ_TSUJI_UNFLOORED, HERTZ_VISCOELASTIC_UNFLOORED)


@njit(cache=True, error_model="numpy")
def scaled_force(code, x, v, p, A, s):
    """The force argument of the law with kernel code ``code`` (the table above)."""
    if code == HUNT_CROSSLEY_LINEAR:
        return hunt_crossley_linear_force(x, v, p, A, s)
    if code == KELVIN_VOIGT:
        return kelvin_voigt_force(x, v, p, A, s)
    if code == MUJOCO_SOFT:
        return mujoco_soft_force(x, v, p, A, s)
    if code == HERTZ_TSUJI or code == HERTZ_TSUJI_UNFLOORED:
        return hertz_tsuji_force(x, v, p, A, s)
    if code == HERTZ_VISCOELASTIC or code == HERTZ_VISCOELASTIC_UNFLOORED:
        return hertz_viscoelastic_force(x, v, p, A, s)
    return hunt_crossley_force(x, v, p, A, s)


@njit(cache=True, error_model="numpy")
def floored(code):
    """True when the law with kernel code ``code`` floors its force at 0 (``FLOORLESS`` lists the others)."""
    return code != HERTZ_TSUJI_UNFLOORED and code != HERTZ_VISCOELASTIC_UNFLOORED


@njit(cache=True, error_model="numpy")
def creeps_unloaded(code, p):
    """True when the law, with no load, approaches ``x = 0`` after its maximum without reaching it.

    Only Tsuji's law without its floor does (from ``TSUJI_UNLOADED_CRITICAL``); the floored laws
    fly back to ``x = 0`` from their floor, and the sqrt(delta) damping without it, ``O(x^{1/2})``
    near ``x = 0``, cannot stop the body's coast there.
    """
    return code == HERTZ_TSUJI_UNFLOORED and p >= TSUJI_UNLOADED_CRITICAL
