"""The engine's step for a mechanism's contact: the step issue's maps at the contact's m_eff and load.

Every engine's discrete map (``stepping``) is a body of mass ``m`` on a plane, pressed by a
constant acceleration.  Along a mechanism's contact normal the engines solve the same row with
``m = m_eff = 1 / (J M^-1 J^T)`` and the free normal acceleration as the load:

- **MuJoCo** builds the row with ``diagA`` in its regulariser (``mujoco_row``): the map's
  ``diag_ratio = diagA m_eff`` slot carries it;
- **Drake's discrete plant** (SAP or TAMSI) solves ``M (v' - v*) = J^T gamma`` with the exact
  ``M``: along the normal ``m_eff (w' - w*) = gamma`` with ``w = J v``, the map's momentum balance;
- **PyBullet's** multibody solver sets the row's ``jacDiagABInv`` from ``J M^-1 J^T`` computed
  by the articulated-body algorithm (``btMultiBodyConstraintSolver::setupMultiBodyContactConstraint``
  with ``calcAccelerationDeltasMultiDof``): exact too.  A link loaded from a URDF carries a
  ``btCompoundShape``, whose child is tested against the other shape only when their bounding
  boxes overlap, so the manifold holds a point only once the pair penetrates: the map's contact
  breaking threshold is 0 (``COMPOUND_BREAKING``), not a free sphere's ``0.02 sqrt(3) r``.

What the maps leave out is the mechanism moving during the contact: ``J``, ``m_eff`` and the
load change with the configuration, and the gap is not exactly ``z + h w'`` when the contact point
moves on an arc.  ``tune(check=True)`` drops the tuned model in the engine and says how much
``m_eff`` moved.
"""

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from contactalpha.stepping import drake_map, pybullet_map
from contactalpha.stepping.delivered import PhaseStats, over_phase
from contactalpha.stepping.inverse import StepInverse, damping_for
from contactalpha.stepping.registry import stepper

from .contact import MechanismContact

# PyBullet's contact breaking threshold (m) for a pair of URDF links: compound shapes report a
# contact point only once their children's bounding boxes overlap (measured in PyBullet 3.2.7:
# no manifold point at a gap of 1e-7 m, one at -1e-7 m; tests/mechanism).
COMPOUND_BREAKING = 0.0


@dataclass(frozen=True)
class DiscreteAnswer:
    """An engine's step for a mechanism's contact.

    ``continuous`` (``PhaseStats`` of the continuous answer at the step), ``inverse``
    (``stepping.inverse.StepInverse``: the engine's damping whose phase mean is the target),
    ``timestep`` s, ``engine``, ``p`` the map's parameters of the continuous answer, and
    ``diag_ratio`` (MuJoCo: diagA m_eff, the map's mechanism slot; NaN for the others).
    """

    continuous: PhaseStats
    inverse: StepInverse
    timestep: float
    engine: str = "mujoco"
    p: np.ndarray | None = None
    diag_ratio: float = math.nan


def step_answer(
    engine: str,
    p: np.ndarray,
    contact: MechanismContact,
    target: float,
    timestep: float,
    diag_ratio: float = math.nan,
) -> DiscreteAnswer:
    """``DiscreteAnswer`` of ``engine``'s map with parameters ``p`` at the contact's speed and load.

    The caller has checked that the contact presses (``contact.accel > 0``).
    """
    v, a = contact.approach_speed, contact.accel
    stats = over_phase(engine, p, timestep, v, a)
    inverse = damping_for(engine, p, timestep, v, a, target)
    return DiscreteAnswer(stats, inverse, float(timestep), engine, p, diag_ratio)


def drake_p(block: dict, contact: MechanismContact) -> np.ndarray:
    """Drake's map parameters: each geometry's stiffness and dissipation of ``block``, mass m_eff."""
    from_block = stepper("drake").from_block
    assert from_block is not None  # every registered stepper has one
    return from_block(block, contact.effective_mass, None)


def pybullet_p(block: dict, contact: MechanismContact, breaking: float = COMPOUND_BREAKING) -> np.ndarray:
    """PyBullet's map parameters: each body's values of ``block``, mass m_eff, threshold ``breaking``."""
    k, c = float(block["contactStiffness"]), float(block["contactDamping"])
    p = pybullet_map.make_params(contact.effective_mass, k, c, k, c, 0.0)
    p[pybullet_map.BREAKING] = breaking
    return p


# Drake's discrete contact approximations the map reproduces.
DRAKE_APPROXIMATIONS = drake_map.APPROXIMATIONS


@dataclass(frozen=True)
class EngineStep:
    """How ``tune`` steps an engine other than MuJoCo.

    ``parameters``: (block, contact) -> the map's ``p``; ``default_step``: s, when none is given
    (None: a continuous plant, no step); ``damping``: the block's per-body damping key; ``note``:
    what the map covers.
    """

    parameters: Callable[[dict, MechanismContact], np.ndarray]
    default_step: float | None
    damping: str
    note: str


ENGINE_STEPS = {
    "drake": EngineStep(
        drake_p, None, "hunt_crossley_dissipation",
        f"Drake's step map: point contact with the discrete approximations {DRAKE_APPROXIMATIONS} "
        "(not sap, which ignores hunt_crossley_dissipation)",
    ),
    "pybullet": EngineStep(
        pybullet_p, pybullet_map.TIMESTEP, "contactDamping",
        "PyBullet's step map: a URDF's links (contact only once they penetrate), frictionless, "
        "no link damping, joint motors off",
    ),
}  # fmt: skip
