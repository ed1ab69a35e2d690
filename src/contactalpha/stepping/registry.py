"""The one list of steppers: each engine's discrete map with its capabilities.

The phase mean, the inverse, the step a tolerance needs, the front door and the command line
iterate ``STEPPERS``; adding an engine's map is its module, its branch in ``kernels.step_map``
and one entry here.
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import drake_map, kernels, mujoco_map, pybullet_map
from .drop import drop_drake, drop_mujoco, drop_pybullet


@dataclass(frozen=True)
class Stepper:
    """One engine's step map and what it can do.

    Attributes
    ----------
    name : the engine's key (as in ``adapters.registry``).
    code : its kernel code in ``kernels.step_map``.
    integrators : the engine's integrators the map reproduces.
    timestep : the engine's default step, s.
    slots : names of ``p``'s slots, in order (the map module's int constants).
    damping_slot : the slot of the engine's own damping parameter (what the inverse solves for).
    stiffness_slot : the slot of its stiffness (an unreachable target's remedy), or None.
    defaults : slot values used when a caller gives none (name -> value).
    contact_time : ``p -> s``, the contact's time scale (sizes step limits and step searches).
    drop : the interface's ``drop_<engine>(p, h, phase, v_in, accel, max_steps)``; its e_N and
        status agree with the generic ``drop.run_drop`` on the same map (tests/stepping).
    source : where the map was read from (files and functions of the engine's source).
    """

    name: str
    code: int
    integrators: tuple
    timestep: float
    slots: tuple
    damping_slot: int
    stiffness_slot: int | None
    defaults: dict
    contact_time: Callable
    drop: Callable
    source: str

    def pack(self, **values):
        """``p`` from slot names (``defaults`` fill the rest); ValueError naming a missing or unknown slot."""
        unknown = sorted(set(values) - set(self.slots))
        if unknown:
            raise ValueError(f"{self.name}: unknown parameter(s) {unknown}; the slots are {self.slots}")
        merged = {**self.defaults, **values}
        missing = [s for s in self.slots if s not in merged]
        if missing:
            raise ValueError(f"{self.name}: parameter(s) {missing} are required; the slots are {self.slots}")
        return np.array([float(merged[s]) for s in self.slots])

    def unpack(self, p):
        """Slot name -> value of ``p``."""
        return {s: float(v) for s, v in zip(self.slots, p, strict=True)}


STEPPERS = (
    Stepper(
        name="mujoco",
        code=kernels.MUJOCO,
        integrators=mujoco_map.INTEGRATORS,
        timestep=mujoco_map.TIMESTEP,
        slots=mujoco_map.SLOT_NAMES,
        damping_slot=mujoco_map.DAMPING,
        stiffness_slot=mujoco_map.STIFFNESS,
        defaults={"diag_ratio": 1.0},
        contact_time=mujoco_map.contact_time,
        drop=drop_mujoco,
        source="MuJoCo src/engine: engine_core_constraint.c (mj_diagApprox, getimpedance, "
        "mj_makeImpedance, mj_referenceConstraint), engine_collision_driver.c (con->exclude), "
        "engine_forward.c (mj_EulerSkip, mj_implicitSkip, mj_advance)",
    ),
    Stepper(
        name="pybullet",
        code=kernels.PYBULLET,
        integrators=pybullet_map.INTEGRATORS,
        timestep=pybullet_map.TIMESTEP,
        slots=pybullet_map.SLOT_NAMES,
        damping_slot=pybullet_map.DAMPING_BALL,
        stiffness_slot=pybullet_map.STIFFNESS_BALL,
        defaults=pybullet_map.defaults(),
        contact_time=pybullet_map.contact_time,
        drop=drop_pybullet,
        source="bullet3 src/BulletDynamics/Featherstone: btMultiBodyConstraintSolver.cpp "
        "(setupMultiBodyContactConstraint, resolveSingleConstraintRowGeneric), btMultiBodyDynamicsWorld.cpp "
        "(solveConstraints, integrateMultiBodyTransforms); src/BulletCollision/CollisionDispatch: "
        "btConvexPlaneCollisionAlgorithm.cpp, btManifoldResult.cpp (calculateCombinedContactStiffness, "
        "calculateCombinedContactDamping), btCollisionDispatcher.cpp (getNewManifold); "
        "examples/SharedMemory/PhysicsServerCommandProcessor.cpp (m_linearSlop)",
    ),
    Stepper(
        name="drake",
        code=kernels.DRAKE,
        integrators=drake_map.APPROXIMATIONS,
        timestep=drake_map.TIMESTEP,
        slots=drake_map.SLOT_NAMES,
        damping_slot=drake_map.DISSIPATION_BALL,
        stiffness_slot=drake_map.STIFFNESS_BALL,
        defaults={},
        contact_time=drake_map.contact_time,
        drop=drop_drake,
        source="drake multibody/plant: discrete_update_manager.cc (AppendDiscreteContactPairsForPointContact), "
        "multibody_plant.h (CombinePointContactParameters), tamsi_solver.cc, sap_driver.cc; "
        "multibody/contact_solvers/sap: sap_hunt_crossley_constraint.cc (CalcDiscreteHuntCrossleyImpulse)",
    ),
)
STEPPER_NAMES = tuple(s.name for s in STEPPERS)


def stepper(name):
    """The registered stepper called ``name``; ValueError naming the valid choices otherwise."""
    for s in STEPPERS:
        if s.name == name:
            return s
    raise ValueError(f"engine = {name!r} has no step map; the valid choices are {STEPPER_NAMES}")
