"""Drake's discrete MultibodyPlant step for one frictionless point contact, as a map (numba).

What the discrete plant does in one step of a sphere on a half space with
``ContactModel.kPoint`` and Hunt-Crossley dissipation, read from Drake's source
(RobotLocomotion/drake):

1. **Contact at the step's start.**  ``QueryObject::ComputePointPairPenetration`` reports the pair
   while the sphere touches or penetrates (depth ``x0 = -z >= 0``: at depth 0 the pair is reported
   with ``fn0 = 0``, and its impulse ``h (-h k w')_+ ...`` still acts);
   ``DiscreteUpdateManager::AppendDiscreteContactPairsForPointContact`` gives it ``fn0 = k x0``,
   with the pair's ``k`` and ``d`` from the geometries' ``point_contact_stiffness`` and
   ``hunt_crossley_dissipation`` (``internal::CombinePointContactParameters``:
   ``k = k1 k2 / (k1 + k2)``, ``d = k2/(k1+k2) d1 + k1/(k1+k2) d2``).  Above the surface the step
   is free.
2. **The impulse** at the next velocity ``w'`` (up, i.e. ``vn`` of the contact frame), the same
   law for the ``lagged`` and ``similar`` approximations (``SapHuntCrossleyConstraint``,
   ``CalcDiscreteHuntCrossleyImpulse``, solved by ``SapSolver``) and for ``tamsi``
   (``TamsiSolver``): ``gamma = h (fn0 - h k w')_+ (1 - d w')_+ = h k (-z')_+ (1 - d w')_+`` with
   ``z' = z + h w'``: Hunt-Crossley at the step's end.  Without friction the two SAP
   approximations differ only in the friction terms, which vanish.
3. **Momentum and positions**: ``m (w' - w) = -m a h + gamma``, then ``z' = z + h w'``.

So ``w'`` is the root of ``m (w' - w*) = gamma(w')`` with ``w* = w - h a``, where ``gamma`` falls
with ``w'``: unique, and below ``v_hat = min(x0/h, 1/d)`` it is the smaller root of the quadratic
``h^2 k d w'^2 - (m + h k (d x0 + h)) w' + (h k x0 + m w*) = 0``.  The engine's solvers stop at
their tolerances (SAP: ``SapSolverParameters::rel_tolerance`` 1e-6 on the momentum residual,
after Newton steps that usually land far below it); this map is the exact root.

**What ``sap`` does.**  ``DiscreteContactApproximation::kSap`` ignores ``hunt_crossley_dissipation``:
its ``SapFrictionConeConstraint`` is a linear Kelvin-Voigt law ``gamma/h = (-k z' - tau k w')_+``
with the ``relaxation_time`` tau (default 0.1 s), and a near-rigid regularisation
``R = max(beta^2/(4 pi^2) w, 1/(h k (h + tau)))`` (beta = 1, w the Delassus estimate, here 1/m)
that takes over when ``h sqrt(k/m)`` exceeds about 2 pi.  It is not this map.

Parameters ``p`` (float64, the engine's own units), slots named below: each geometry's values, as
``AddContactMaterial`` takes them (the registry's inverse gives both geometries the same
``hunt_crossley_dissipation``).  A whole drop through this map is ``stepping.drop.drop_drake``.
Importing this module does not need Drake.
"""

import math

import numpy as np
from numba import njit

# MultibodyPlantConfig's default time_step, s, and the discrete contact approximations this map
# reproduces (the default ``lagged`` first; ``sap`` is another law, see above).
TIMESTEP = 1e-3
APPROXIMATIONS = ("lagged", "similar", "tamsi")

# Slots of ``p``.
MASS = 0  # the sphere's mass, kg
STIFFNESS_BALL = 1  # the sphere's point_contact_stiffness, N/m
DISSIPATION_BALL = 2  # the sphere's hunt_crossley_dissipation, s/m
STIFFNESS_GROUND = 3  # the half space's point_contact_stiffness, N/m
DISSIPATION_GROUND = 4  # the half space's hunt_crossley_dissipation, s/m
N_PARAMS = 5
SLOT_NAMES = ("mass", "stiffness_ball", "dissipation_ball", "stiffness_ground", "dissipation_ground")


def make_params(
    mass: float,
    stiffness_ball: float,
    dissipation_ball: float,
    stiffness_ground: float,
    dissipation_ground: float,
) -> np.ndarray:
    """``p`` for a sphere of ``mass`` (kg) on a half space, with each geometry's values."""
    p = np.empty(N_PARAMS)
    p[MASS] = mass
    p[STIFFNESS_BALL], p[DISSIPATION_BALL] = stiffness_ball, dissipation_ball
    p[STIFFNESS_GROUND], p[DISSIPATION_GROUND] = stiffness_ground, dissipation_ground
    return p


def contact_time(p: np.ndarray) -> float:
    """The undamped contact's half period ``pi sqrt(m / k)`` with the pair's k, s."""
    k = p[STIFFNESS_BALL] * p[STIFFNESS_GROUND] / (p[STIFFNESS_BALL] + p[STIFFNESS_GROUND])
    return math.pi * math.sqrt(p[MASS] / k)


@njit(cache=True)
def pair_values(p: np.ndarray) -> tuple[float, float]:
    """The pair's ``(k, d)`` from the geometries' (``CombinePointContactParameters``; 0/0 gives 0)."""
    k1, k2 = p[STIFFNESS_BALL], p[STIFFNESS_GROUND]
    s = k1 + k2
    if s == 0.0:
        return 0.0, 0.0
    return k1 * k2 / s, k2 / s * p[DISSIPATION_BALL] + k1 / s * p[DISSIPATION_GROUND]


@njit(cache=True)
def next_velocity_drake(z: float, w: float, p: np.ndarray, h: float, accel: float) -> float:
    """The step's end velocity ``w'`` (m/s, up) from ``(z, w)``; ``w - h accel`` without contact."""
    w_star = w - h * accel
    if not (z <= 0.0):
        return w_star
    k, d = pair_values(p)
    m = p[MASS]
    x0 = -z
    v_hat = x0 / h
    if d > 0.0 and 1.0 / d < v_hat:
        v_hat = 1.0 / d
    if w_star >= v_hat:
        return w_star
    a = h * h * k * d
    b = m + h * k * (d * x0 + h)
    c = h * k * x0 + m * w_star
    disc = b * b - 4.0 * a * c
    return 2.0 * c / (b + math.sqrt(max(disc, 0.0)))


@njit(cache=True)
def step_drake(z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One discrete-plant step of the height ``z`` (m, above the surface) and velocity ``w`` (m/s, up).

    ``accel`` (m/s^2, > 0) is the load's acceleration into the contact, ``h`` the step (s).
    """
    w_next = next_velocity_drake(z, w, p, h, accel)
    return z + h * w_next, w_next


def from_block(block: dict, mass: float, radius: float | None) -> np.ndarray:
    """``p`` from Drake's block of ``contact_parameters`` (each geometry's stiffness and dissipation)."""
    del radius  # point contact: the map needs no geometry
    k, d = float(block["point_contact_stiffness"]), float(block_damping(block))
    return make_params(mass, k, d, k, d)


def block_damping(block: dict) -> np.ndarray:
    """Drake's own damping of a block: each geometry's ``hunt_crossley_dissipation`` (s/m), arrays too."""
    return np.asarray(block["hunt_crossley_dissipation"], dtype=float)


def law_damping(p: np.ndarray, approach_speed: float) -> float:
    """Hunt-Crossley's alpha = d v_minus of the pair's dissipation d in ``p``."""
    return pair_values(p)[1] * approach_speed
