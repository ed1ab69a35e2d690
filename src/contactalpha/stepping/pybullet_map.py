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

Parameters ``p`` (float64, the engine's own units), slots named below.  Importing this module does
not need PyBullet.
"""

import math

import numpy as np
from numba import njit

from contactalpha.stepping.codes import CAPTURED, NON_FINITE, SEPARATED, STEP_LIMIT
from contactalpha.stepping.flight import REST_FRACTION, rebound_speed, touchdown_state

# PyBullet's default time step, s (``setTimeStep``).
TIMESTEP = 1.0 / 240.0
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
    "mass", "stiffness_ball", "damping_ball", "stiffness_ground", "damping_ground", "breaking", "slop",
)  # fmt: skip


def breaking_threshold(radius, factor=BREAKING_FACTOR):
    """The contact breaking threshold (m) of a sphere-plane manifold: ``factor * sqrt(3) * radius``."""
    return factor * math.sqrt(3.0) * radius


def make_params(mass, stiffness_ball, damping_ball, stiffness_ground, damping_ground, radius):
    """``p`` for a sphere of ``radius`` (m) on a plane, at PyBullet's default threshold and slop."""
    p = np.empty(N_PARAMS)
    p[MASS] = mass
    p[STIFFNESS_BALL], p[DAMPING_BALL] = stiffness_ball, damping_ball
    p[STIFFNESS_GROUND], p[DAMPING_GROUND] = stiffness_ground, damping_ground
    p[BREAKING] = breaking_threshold(radius)
    p[SLOP] = LINEAR_SLOP
    return p


@njit(cache=True)
def pair_values(p):
    """The pair's ``(k, c)`` from the two bodies' (``btManifoldResult``'s combining rules)."""
    k = 1.0 / (1.0 / p[STIFFNESS_BALL] + 1.0 / p[STIFFNESS_GROUND])
    return k, p[DAMPING_BALL] + p[DAMPING_GROUND]


@njit(cache=True)
def impulse_pybullet(z, w, p, h, accel):
    """The normal impulse ``lambda`` (N s, >= 0) of one step from ``(z, w)``; 0 without a contact point."""
    if not (z - p[SLOP] < p[BREAKING]):
        return 0.0
    k, c = pair_values(p)
    v_star = w - h * accel
    denom = h * k + c
    if denom < SIMD_EPSILON:
        denom = SIMD_EPSILON
    cfm = 1.0 / denom / h
    erp = h * k / denom
    d_inv = 1.0 / (1.0 / p[MASS] + cfm)
    if z > 0.0:
        rhs = (-v_star - z / h) * d_inv
    else:
        rhs = (-z * erp / h) * d_inv + (-v_star) * d_inv
    return max(rhs, 0.0)


@njit(cache=True)
def step_pybullet(z, w, p, h, accel):
    """One PyBullet step of the height ``z`` (m, above the contact surface) and velocity ``w`` (m/s, up).

    ``accel`` (m/s^2, > 0) is the load's acceleration into the contact, ``h`` the step (s).
    """
    lam = impulse_pybullet(z, w, p, h, accel)
    w_next = w - h * accel + lam / p[MASS]
    return z + h * w_next, w_next


@njit(cache=True)
def drop_pybullet(p, h, phase, v_in, accel, max_steps):
    """A whole drop in PyBullet's steps: ``(e_N, n_contact_steps, status)`` (``stepping.codes``).

    Touchdown falls at ``phase`` in [0, 1) of the first step, at approach speed ``v_in`` (m/s, > 0).
    The contact ends at the first step that starts above the surface, applies no impulse and ends
    moving up; e_N is read from the flight parabola after it.  ``n_contact_steps`` counts the steps
    with an impulse.  A body that turns down again without leaving, or comes to rest in contact, is captured
    (e_N = 0);
    ``max_steps`` spent first: STEP_LIMIT and NaN.
    """
    z, w = touchdown_state(v_in, accel, h, phase)
    n_force = 0
    rising = False
    for _ in range(max_steps):
        lam = impulse_pybullet(z, w, p, h, accel)
        w_next = w - h * accel + lam / p[MASS]
        z_next = z + h * w_next
        if not (math.isfinite(z_next) and math.isfinite(w_next)):
            return math.nan, n_force, NON_FINITE
        if lam > 0.0:
            n_force += 1
        elif n_force > 0 and z > 0.0 and w_next > 0.0:
            return rebound_speed(z_next, w_next, accel, h) / v_in, n_force, SEPARATED
        if n_force > 0:
            if w_next > 0.0:
                rising = True
            elif rising or (abs(w_next) <= REST_FRACTION * v_in and abs(w_next - w) <= REST_FRACTION * v_in):
                return 0.0, n_force, CAPTURED
        z, w = z_next, w_next
    return math.nan, n_force, STEP_LIMIT
