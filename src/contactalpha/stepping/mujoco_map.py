"""MuJoCo's step for one frictionless contact (condim 1) of a body on a plane, as a map.

Read from MuJoCo's source (``src/engine/``):

- ``engine_core_constraint.c``: ``mj_diagApprox`` gives the contact row's ``diagApprox`` from the
  bodies' ``body_invweight0`` (1/m for a free body or a body on a slide joint);
  ``getimpedance`` returns the constant ``imp = d`` when ``solimp[0] == solimp[1]``;
  ``mj_makeImpedance`` sets ``R = max(mjMINVAL, (1 - imp)/imp * diagApprox)`` and, in the direct
  mode (``solref = (-stiffness, -damping)``), ``K = stiffness / solimp[1]^2``,
  ``B = damping / solimp[1]``; ``mj_referenceConstraint`` sets
  ``aref = -B * vel - K * imp * (pos - margin)`` with ``pos`` the contact distance.
- The constraint solver (Newton, the default) minimises the soft-constraint cost; for one
  normal row with ``A = J M^-1 J' = 1/m`` its exact solution is
  ``f = max(0, -(a0 - aref) / (A + R))`` with ``a0`` the unconstrained acceleration.
- ``engine_collision_driver.c`` excludes a contact with ``dist >= margin - gap``
  (``con->exclude``): the contact acts in every step that *starts* at ``z < 0`` (margin 0).
- ``engine_forward.c``: ``mj_Euler`` (``mj_EulerSkip``) and ``mj_implicitSkip`` then
  ``mj_advance``: ``qvel += h * qacc`` first, then ``mj_integratePos`` with the new velocity.

**Euler and implicitfast coincide here.**  ``implicitfast`` solves ``(M - h qDeriv) qacc = qfrc``
where ``qDeriv`` (``mjd_smooth_vel``) holds the velocity derivatives of the passive and actuator
forces only; the constraint force is not in it, so the contact's damping stays explicit.
Without joint damping or velocity-dependent actuators ``qDeriv = 0`` and both integrators apply
``qacc = M^-1 (qfrc_smooth + qfrc_constraint)``: the same map (checked against MuJoCo's own
``mj_step`` in tests/stepping).  Per unit mass:

    if z < 0:   w <- w + h (-a + max(0, -(-a - aref) / (1 + r (1 - d)/d))),
                aref = -(damping/d) w - (stiffness/d^2) d z
    else:       w <- w - h a
    z <- z + h w

with ``r = diagApprox * m`` (1 for a free body; other values model a contact inside a mechanism,
where MuJoCo's ``diagApprox`` differs from ``J M^-1 J'``).
"""

import numpy as np
from numba import njit

from .flight import euler_affine

# Slots of p (the engine's own parameters, in its units).
STIFFNESS = 0  # -solref[0] in the direct mode, s^-2 (per unit mass)
DAMPING = 1  # -solref[1] in the direct mode, s^-1 (per unit mass): the engine's damping parameter
IMPEDANCE = 2  # solimp[0] = solimp[1] = d, in (0, 1)
DIAG_RATIO = 3  # diagApprox * m: MuJoCo's approximate inverse mass over the true one (1: free body)
N_SLOTS = 4
SLOT_NAMES = ("stiffness", "damping", "impedance", "diag_ratio")
# MuJoCo's floor on R (mjMINVAL, mjmodel.h).
MINVAL = 1e-15
# MuJoCo's default timestep, s, and its integrators this map serves.
TIMESTEP = 0.002
INTEGRATORS = ("Euler", "implicitfast")


@njit(cache=True)
def _soft_row(p):
    """The contact row's ``(imp, R / A, K, B)`` of ``mj_makeImpedance`` (module docstring)."""
    imp = p[IMPEDANCE]
    return imp, max(MINVAL, (1.0 - imp) * p[DIAG_RATIO] / imp), p[STIFFNESS] / (imp * imp), p[DAMPING] / imp


@njit(cache=True)
def step_mujoco(z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One MuJoCo step (Euler or implicitfast) of height ``z`` and velocity ``w`` (module docstring)."""
    a0 = -accel
    qacc = a0
    if z < 0.0:
        imp, r, k, b = _soft_row(p)
        aref = -b * w - k * imp * z
        f = max(0.0, -(a0 - aref) / (1.0 + r))
        qacc = a0 + f
    w1 = w + h * qacc
    return z + h * w1, w1


# The linear forms ``alpha z + beta w + gamma`` whose signs pick the step's branch, and the branches
# (0: no force; 1: the constraint pushes).  On each branch the step is affine (``affine_phase``).
N_FORMS = 2
N_BRANCHES = 2


@njit(cache=True)
def branches_mujoco(p: np.ndarray, h: float, accel: float, forms: np.ndarray, maps: np.ndarray) -> int:
    """Fill ``forms[:N_FORMS]`` with ``(alpha, beta, gamma)``, ``maps[:N_BRANCHES]`` with each branch's step.

    The forms: ``z`` (the contact acts below 0) and ``aref - a0 = -(stiffness/d) z - (damping/d) w
    + accel`` (it pushes above 0).  A branch's step is ``z' = maps[b, 0:3] . (z, w, 1)``,
    ``w' = maps[b, 3:6] . (z, w, 1)``: ``step_mujoco``'s arithmetic collected by state
    (tests/stepping check that the two agree to rounding).
    """
    a0 = -accel
    imp, r, k, b = _soft_row(p)
    forms[0, 0], forms[0, 1], forms[0, 2] = 1.0, 0.0, 0.0
    forms[1, 0], forms[1, 1], forms[1, 2] = -k * imp, -b, -a0
    # free flight w' = w + h a0; pushed: qacc = a0 + (aref - a0) / (1 + r), aref = -b w - k imp z
    euler_affine(maps[0], h, 0.0, 1.0, h * a0)
    euler_affine(maps[1], h, -h * k * imp / (1.0 + r), 1.0 - h * b / (1.0 + r), h * (a0 - a0 / (1.0 + r)))
    return N_FORMS


@njit(cache=True)
def branch_mujoco(vals: np.ndarray) -> int:
    """The branch from the forms' values at a state: 1 where the contact pushes, else 0."""
    return 1 if vals[0] < 0.0 and vals[1] > 0.0 else 0


def contact_time(p: np.ndarray) -> float | np.ndarray:
    """The undamped contact's half period ``pi / sqrt(stiffness)``, s: the time scale of a contact."""
    return np.pi / np.sqrt(p[STIFFNESS])


def stable_damping(x: float | np.ndarray) -> float | np.ndarray:
    """The largest damping ratio at which the contact step ``x = omega h`` is stable.

    The step of ``z'' = -omega^2 z - 2 zeta omega z'`` (velocity first, then position) has the
    characteristic polynomial ``l^2 - (2 - 2 zeta x - x^2) l + (1 - 2 zeta x)``; both roots lie
    in the unit disc while ``2 zeta x <= 2 - x^2 / 2``.
    """
    return (1.0 - 0.25 * x * x) / x


def pack(
    stiffness: float | np.ndarray,
    damping: float | np.ndarray,
    impedance: float | np.ndarray,
    diag_ratio: float | np.ndarray = 1.0,
) -> np.ndarray:
    """``p`` from MuJoCo's direct-mode values (``solref = (-stiffness, -damping)``, ``solimp[0:2] = d``)."""
    # Arrays give one row of slots per scene.
    return np.stack(np.broadcast_arrays(stiffness, damping, impedance, diag_ratio), axis=-1).astype(float)


def from_block(block: dict, mass: float | np.ndarray | None, radius: float | np.ndarray | None) -> np.ndarray:
    """``p`` from the MuJoCo block of ``contact_parameters`` (direct-mode ``solref``, ``solimp``)."""
    del mass, radius  # per unit mass, and the map needs no geometry
    solref, solimp = np.asarray(block["solref"]), np.asarray(block["solimp"])  # a tuple, or a row per world
    return pack(-solref[..., 0], block_damping(block), solimp[..., 0])


def block_damping(block: dict) -> np.ndarray:
    """MuJoCo's own damping ``-solref[1]`` (direct mode, per unit mass) of a block; arrays go through."""
    return -np.asarray(block["solref"], dtype=float)[..., 1]


def law_damping(p: np.ndarray, approach_speed: float | np.ndarray) -> float | np.ndarray:
    """The law's damping ratio zeta = damping / (2 sqrt(stiffness)) of ``p`` (any approach speed)."""
    del approach_speed
    return p[DAMPING] / (2.0 * np.sqrt(p[STIFFNESS]))
