"""PyBullet's step for one frictionless contact, as a map (numba).

What PyBullet does in one ``stepSimulation`` of a free sphere (``createMultiBody``, a
``btMultiBody``) on a plane, with ``contactStiffness`` and ``contactDamping`` set, read from Bullet's
source (bullet3, the tree PyBullet 3.2.7 is built from; double precision):

1. **Collision at the step's start.**  ``btConvexPlaneCollisionAlgorithm::processCollision`` adds a
   contact point while the geometric distance is below the manifold's contact breaking threshold
   (``btManifoldResult::addContactPoint``).  The threshold is relative (the dispatcher's default
   ``CD_USE_RELATIVE_CONTACT_BREAKING_THRESHOLD``, ``btCollisionDispatcher::getNewManifold``):
   ``gContactBreakingThreshold`` (0.02) times ``btCollisionShape::getAngularMotionDisc``, the half
   diagonal of the shape's box, ``sqrt(3) r`` for a sphere of radius r (the plane's is unbounded,
   and the smaller one is taken).  ``breaking_threshold`` computes it.
2. **External forces first.**  ``btMultiBodyDynamicsWorld::solveConstraints`` calls
   ``solveExternalForces`` before the contact solver: the velocity becomes ``v* = w - h a``.
3. **The normal row** (``btMultiBodyConstraintSolver::setupMultiBodyContactConstraint``).  With the
   pair's stiffness ``k`` and damping ``c`` (``btManifoldResult::calculateCombinedContactStiffness``
   ``1/(1/k1 + 1/k2)`` and ``calculateCombinedContactDamping`` ``c1 + c2``; a body without values
   keeps ``btCollisionObject``'s defaults 1e30 and 0.1, which ``UNSET_STIFFNESS`` and
   ``UNSET_DAMPING`` name): ``erp = h k / (h k + c)`` and ``cfm = 1 / (h (h k + c))``;
   ``D = 1 / (1/m + cfm)``.  The solver's distance is ``dist = distance + m_linearSlop`` (PyBullet sets
   1e-5): this module's ``z`` is that distance, the height above the contact surface.  The target is
   ``rhs = D (-v* - dist / h)`` for ``dist > 0`` (a speculative row: it pushes only if the step would
   end below the surface) and ``rhs = D (-v* - erp dist / h)`` otherwise.  Restitution is 0 here
   (``restitutionCurve`` gives 0), and the split impulse is not used by multibody contacts (the
   branch is commented out in ``setupMultiBodyContactConstraint``, whatever ``useSplitImpulse``).
4. **The solve** (``resolveSingleConstraintRowGeneric``, ``numSolverIterations`` 50): for one row the
   projected Gauss-Seidel sweep lands on ``lambda = max(0, rhs)`` in its first iteration, from any
   warm start, and later sweeps change it by rounding only.
5. **Semi-implicit Euler** (``integrateMultiBodyTransforms``): ``w <- v* + lambda / m``,
   ``z <- z + h w``.

In the penetrating branch the impulse is ``lambda = -h (k z' + c w')`` with the step's *end* state
``(z', w')``: an implicit spring-dashpot.  The speculative branch gives ``lambda = -(h k + c) z'``.

Parameters ``p`` (float64, the engine's own units), slots named below: the ball's and the plane's
values apart, as PyBullet's ``changeDynamics`` takes them (the registry's inverse gives both
bodies the same ``contactDamping``; a plane left unset keeps Bullet's defaults, ``UNSET_*``).
A whole drop through this map is ``stepping.drop.drop_pybullet``.  Importing this module does
not need PyBullet.
"""

import math

import numpy as np
from numba import njit

from .flight import euler_affine

# PyBullet's default time step, s (``setTimeStep``), and its integrator.
TIMESTEP = 1.0 / 240.0
INTEGRATORS = ("semi-implicit Euler",)
# ``m_linearSlop`` that PyBullet's server sets (PhysicsServerCommandProcessor.cpp), m: the solver
# reads a penetration as ``distance + m_linearSlop``, so the contact surface lies this far below
# the geometric one.
LINEAR_SLOP = 1e-5
# ``gContactBreakingThreshold`` (btPersistentManifold.cpp), PyBullet's ``contactBreakingThreshold``.
BREAKING_FACTOR = 0.02
# ``btCollisionObject``'s stiffness and damping for a body whose values were never set (double build).
UNSET_STIFFNESS = 1e30
UNSET_DAMPING = 0.1
# Bullet's ``SIMD_EPSILON`` (DBL_EPSILON): the floor of ``h k + c``.
SIMD_EPSILON = np.finfo(np.float64).eps

# Slots of ``p``.
MASS = 0  # the sphere's mass, kg
STIFFNESS_BALL = 1  # the sphere's contactStiffness, N/m
DAMPING_BALL = 2  # the sphere's contactDamping, N s/m
STIFFNESS_GROUND = 3  # the plane's contactStiffness, N/m
DAMPING_GROUND = 4  # the plane's contactDamping, N s/m
BREAKING = 5  # the manifold's contact breaking threshold, m (``breaking_threshold``)
SLOP = 6  # the solver's linear slop, m
N_PARAMS = 7
SLOT_NAMES = (
    "mass",
    "stiffness_ball",
    "damping_ball",
    "stiffness_ground",
    "damping_ground",
    "breaking",
    "slop",
)


def breaking_threshold(radius: float | np.ndarray, factor: float = BREAKING_FACTOR) -> float | np.ndarray:
    """The contact breaking threshold (m) of a sphere-plane manifold: ``factor * sqrt(3) * radius``."""
    return factor * math.sqrt(3.0) * radius


def make_params(
    mass: float | np.ndarray,
    stiffness_ball: float | np.ndarray,
    damping_ball: float | np.ndarray,
    stiffness_ground: float | np.ndarray,
    damping_ground: float | np.ndarray,
    radius: float | np.ndarray,
) -> np.ndarray:
    """``p`` for a sphere of ``radius`` (m) on a plane, at PyBullet's default threshold and slop."""
    # Arrays give one row of slots per scene.
    cols = (
        mass,
        stiffness_ball,
        damping_ball,
        stiffness_ground,
        damping_ground,
        breaking_threshold(radius),
        LINEAR_SLOP,
    )
    return np.stack(np.broadcast_arrays(*cols), axis=-1).astype(float)


def contact_time(p: np.ndarray) -> float | np.ndarray:
    """The undamped contact's half period ``pi sqrt(m / k)`` with the pair's k, s."""
    k = 1.0 / (1.0 / p[STIFFNESS_BALL] + 1.0 / p[STIFFNESS_GROUND])
    return np.pi * np.sqrt(p[MASS] / k)


@njit(cache=True)
def surface_pybullet(p: np.ndarray) -> float:
    """Height in the map's z of the geometric surface a user reads a drop at: the slop above the solver's."""
    return p[SLOP]


@njit(cache=True)
def pair_values(p: np.ndarray) -> tuple[float, float]:
    """The pair's ``(k, c)`` from the two bodies' (``btManifoldResult``'s combining rules)."""
    k = 1.0 / (1.0 / p[STIFFNESS_BALL] + 1.0 / p[STIFFNESS_GROUND])
    return k, p[DAMPING_BALL] + p[DAMPING_GROUND]


@njit(cache=True)
def _row_terms(p, h):
    """The normal row's ``(erp, D)``.

    ``erp = h k / (h k + c)``, ``cfm = 1 / (h (h k + c))``, ``D = 1 / (1/m + cfm)``.
    """
    k, c = pair_values(p)
    denom = h * k + c
    if denom < SIMD_EPSILON:
        denom = SIMD_EPSILON
    cfm = 1.0 / denom / h
    return h * k / denom, 1.0 / (1.0 / p[MASS] + cfm)


@njit(cache=True)
def impulse_pybullet(z: float, w: float, p: np.ndarray, h: float, accel: float) -> float:
    """The normal impulse ``lambda`` (N s, >= 0) of one step from ``(z, w)``; 0 without a contact point."""
    if not (z - p[SLOP] < p[BREAKING]):
        return 0.0
    erp, d_inv = _row_terms(p, h)
    v_star = w - h * accel
    if z > 0.0:
        rhs = (-v_star - z / h) * d_inv
    else:
        rhs = (-z * erp / h) * d_inv + (-v_star) * d_inv
    return max(rhs, 0.0)


@njit(cache=True)
def step_pybullet(z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One PyBullet step of the height ``z`` (m, above the contact surface) and velocity ``w`` (m/s, up).

    ``accel`` (m/s^2, > 0) is the load's acceleration into the contact, ``h`` the step (s).
    """
    lam = impulse_pybullet(z, w, p, h, accel)
    w_next = w - h * accel + lam / p[MASS]
    return z + h * w_next, w_next


# The linear forms ``alpha z + beta w + gamma`` whose signs pick the step's branch, and the branches
# (0: no impulse; 1: the speculative row pushes; 2: the penetrating row pushes).
N_FORMS = 4
N_BRANCHES = 3


@njit(cache=True)
def branches_pybullet(p: np.ndarray, h: float, accel: float, forms: np.ndarray, maps: np.ndarray) -> int:
    """Fill ``forms[:N_FORMS]`` with ``(alpha, beta, gamma)``, ``maps[:N_BRANCHES]`` with each branch's step.

    The forms: a contact point (``z - slop - breaking < 0``), the speculative row (``z > 0``) and
    the sign of each row's target, ``-v* - z/h`` and ``-v* - erp z/h`` with ``v* = w - h accel``.
    A branch's step is ``z' = maps[b, 0:3] . (z, w, 1)``, ``w' = maps[b, 3:6] . (z, w, 1)``:
    ``impulse_pybullet``'s arithmetic collected by state (tests/stepping check the two agree).
    """
    erp, d_inv = _row_terms(p, h)
    d_m = d_inv / p[MASS]  # D / m
    forms[0, 0], forms[0, 1], forms[0, 2] = 1.0, 0.0, -p[SLOP] - p[BREAKING]
    forms[1, 0], forms[1, 1], forms[1, 2] = 1.0, 0.0, 0.0
    forms[2, 0], forms[2, 1], forms[2, 2] = -1.0 / h, -1.0, h * accel
    forms[3, 0], forms[3, 1], forms[3, 2] = -erp / h, -1.0, h * accel
    # w' = v* + lambda/m, lambda/m = D/m (-v* - g z/h): g = 1 (speculative) or erp (penetrating)
    w1 = -h * accel + d_m * h * accel
    euler_affine(maps[0], h, 0.0, 1.0, -h * accel)
    euler_affine(maps[1], h, -d_m / h, 1.0 - d_m, w1)
    euler_affine(maps[2], h, -d_m * erp / h, 1.0 - d_m, w1)
    return N_FORMS


@njit(cache=True)
def branch_pybullet(vals: np.ndarray) -> int:
    """The branch from the forms' values at a state (``branches_pybullet``)."""
    if not vals[0] < 0.0:
        return 0
    if vals[1] > 0.0:
        return 1 if vals[2] > 0.0 else 0
    return 2 if vals[3] > 0.0 else 0


def from_block(block: dict, mass: float | np.ndarray, radius: float | np.ndarray | None) -> np.ndarray:
    """``p`` from PyBullet's block of ``contact_parameters`` (each body's contactStiffness, contactDamping).

    The contact breaking threshold needs the sphere's ``radius`` (m); ValueError without one.
    """
    if radius is None:
        raise ValueError("PyBullet's step needs radius= (its contact breaking threshold is 0.02 sqrt(3) r)")
    k, c = np.asarray(block["contactStiffness"], dtype=float), block_damping(block)
    return make_params(mass, k, c, k, c, radius)


def block_damping(block: dict) -> np.ndarray:
    """PyBullet's own damping, each body's ``contactDamping`` (N s/m), of a block; arrays go through."""
    return np.asarray(block["contactDamping"], dtype=float)


def law_damping(p: np.ndarray, approach_speed: float | np.ndarray) -> float | np.ndarray:
    """The spring-dashpot's damping ratio zeta = c / (2 sqrt(k m)) of the pair in ``p`` (any speed)."""
    del approach_speed
    k, c = pair_values.py_func(p)  # numpy arithmetic: p may hold one column per scene
    return c / (2.0 * np.sqrt(k * p[MASS]))
