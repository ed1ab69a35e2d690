"""PyBullet's rigid contact with ``restitution``, one step as a map (numba).

What one ``stepSimulation`` does to a free sphere on a plane when no ``contactStiffness`` is set
(Bullet's default rigid contact), read from bullet3 (the tree PyBullet 3.2.7 is built from):

1. **A contact point** exists while the geometric distance is below the manifold's contact
   breaking threshold (``btConvexPlaneCollisionAlgorithm::processCollision``; 0.02 sqrt(3) r for a
   sphere, ``stepping.pybullet_map.breaking_threshold``).  The solver's distance is
   ``d = distance + m_linearSlop`` (PyBullet sets 1e-5 m).
2. **The approach velocity.**  ``restitutionCurve(rel_vel, e, threshold)`` gives the target
   separating speed ``e (-rel_vel)``, 0 where ``|rel_vel| < m_restitutionVelocityThreshold``
   (0.2 m/s unless ``setPhysicsEngineParameter(restitutionVelocityThreshold=)``) and 0 where the
   bodies separate.  *Which* velocity differs between Bullet's two solvers:

   - a ``btMultiBody`` (``createMultiBody``, the default): ``setupMultiBodyContactConstraint``
     reads the multibody's velocity vector after ``solveExternalForces``, ``v* = w - h a``;
   - a ``btRigidBody`` (``useMaximalCoordinates=1``): ``setupContactConstraint`` reads
     ``getVelocityInLocalPoint``, and ``btDiscreteDynamicsWorld::predictUnconstraintMotion`` has
     already integrated the step's forces into it (``integrateVelocities``): ``v*`` again.

   So both paths are the same map (checked against both in the engine): **the step's gravity is
   in the approach speed**, and the row asks for ``e |v*|``, more than the ``e v`` of a touchdown
   at speed ``v``.

3. **The row.**  With ``cfm = m_globalCfm`` (0) and ``erp = m_erp2`` (PyBullet's ``contactERP``,
   0.08), ``velocityError = target - v*``; for ``d > 0`` (a speculative contact) it also takes
   out the remaining gap, ``- d / h``; for ``d <= 0`` the positional error is ``- erp d / h``.
   The split impulse (rigid bodies, ``useSplitImpulse``) applies only below
   ``splitImpulsePenetrationThreshold`` (-0.04 m): not for a ball's contact.  The multibody row
   never splits (the branch is commented out).
4. **The solve**: one row, no CFM: the projected Gauss-Seidel sweep lands on
   ``lambda = m max(0, velocityError + positionalError)``, from any warm start.
5. **Semi-implicit Euler**: ``w' = v* + lambda / m``, ``z' = z + h w'``.

So above the surface the step ends *at* ``h * target`` above the solver's surface (the gap is
removed in the same step that applies the restitution): the rebound starts from where the
touchdown phase left the ball, and the restitution acts on the speed of the step the contact
point caught, which is why even without gravity one drop's e_N moves with the touchdown phase.

The map carries ``z``, the height above the *geometric* surface (where a user reads a drop), and
``w`` (up).  The combined restitution is the product of the two bodies'
(``btManifoldResult::calculateCombinedRestitution``).  Importing this module needs no PyBullet.
"""

import math

import numpy as np
from numba import njit

from contactalpha.stepping.pybullet_map import BREAKING_FACTOR, LINEAR_SLOP, TIMESTEP

# PyBullet's defaults: ``contactERP`` (``m_erp2``, PhysicsServerCommandProcessor) and
# ``restitutionVelocityThreshold`` (btContactSolverInfo), m/s.
CONTACT_ERP = 0.08
VELOCITY_THRESHOLD = 0.2
DEFAULT_TIMESTEP = TIMESTEP

# Slots of ``p``.
RESTITUTION = 0  # the pair's (combined) restitution: the product of the two bodies'
THRESHOLD = 1  # restitutionVelocityThreshold, m/s
BREAKING = 2  # the contact breaking threshold, m
SLOP = 3  # the solver's linear slop, m
ERP = 4  # contactERP
N_PARAMS = 5


def make_params(
    restitution: float,
    radius: float,
    threshold: float = VELOCITY_THRESHOLD,
    erp: float = CONTACT_ERP,
) -> np.ndarray:
    """``p`` for the pair's ``restitution`` and a sphere of ``radius`` (m) at PyBullet's defaults."""
    p = np.empty(N_PARAMS)
    p[RESTITUTION], p[THRESHOLD], p[ERP] = restitution, threshold, erp
    p[BREAKING], p[SLOP] = BREAKING_FACTOR * math.sqrt(3.0) * radius, LINEAR_SLOP
    return p


@njit(cache=True)
def target_speed(rel_vel: float, restitution: float, threshold: float) -> float:
    """``restitutionCurve``: the separating speed the row asks for (>= 0), from the approach ``rel_vel``."""
    if abs(rel_vel) < threshold:
        return 0.0
    return max(restitution * -rel_vel, 0.0)


@njit(cache=True)
def impulse_bullet(z: float, w: float, p: np.ndarray, h: float, accel: float) -> float:
    """The normal impulse per unit mass (m/s, >= 0) of one step from ``(z, w)``."""
    if not z < p[BREAKING]:
        return 0.0
    v_star = w - h * accel
    err = target_speed(v_star, p[RESTITUTION], p[THRESHOLD]) - v_star
    d = z + p[SLOP]
    if d > 0.0:
        err -= d / h
    else:
        err -= d * p[ERP] / h
    return max(err, 0.0)


@njit(cache=True)
def step_bullet(z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One step of the height ``z`` (m, above the geometric surface) and velocity ``w`` (m/s, up)."""
    w_next = w - h * accel + impulse_bullet(z, w, p, h, accel)
    return z + h * w_next, w_next
