"""The one list of steppers: each engine's discrete map with its capabilities.

The phase mean, the inverse, the step a tolerance needs, the front door and the command line
iterate ``STEPPERS``.  The built-in maps are their module, their line in ``kernels.MAPS`` and one
entry here; an engine outside this folder registers its map with ``kernels.register_map`` (a
fresh kernel code) and its ``Stepper`` is added here by ``register`` (``adapters.registry`` does
it for the step map of every engine record).
"""

import threading
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
    code : its kernel code in ``kernels.MAPS``.
    integrators : the engine's integrators the map reproduces.
    timestep : the engine's default step, s.
    slots : names of ``p``'s slots, in order (the map module's int constants).
    damping_slots : the slots of the engine's own damping parameter (what the inverse solves for;
        all of them take the same value, e.g. both bodies' values of a pair).
    stiffness_slots : the slots of its stiffness (an unreachable target's remedy); may be empty.
    defaults : slot values used when a caller gives none (name -> value).
    contact_time : ``p -> s``, the contact's time scale (sizes step limits and step searches).
    drop : the interface's ``drop_<engine>(p, h, phase, v_in, accel, max_steps)``; its e_N and
        status agree with the generic ``drop.run_drop`` on the same map (tests/stepping).
    source : where the map was read from (files and functions of the engine's source).
    from_block : ``(block, mass, radius) -> p`` from the engine's block of ``contact_parameters``
        (``adapters``' ``parameters``), or None where the front door does not step this engine.
    law_damping : ``(p, approach_speed) -> the law's dimensionless damping`` that the adapter's
        ``parameters`` turn back into the engine's block, or None likewise.
    block_damping : ``block -> the engine's own damping parameter`` (arrays go through), or None.
    step_setting : the name of the step in the engine adapter's settings.
    needs_radius : the map reads the sphere's radius (``from_block`` refuses None).
    read_at : where a drop's approach and rebound are read (``kernels.surface``), in words.
    """

    name: str
    code: int
    integrators: tuple
    timestep: float
    slots: tuple
    damping_slots: tuple
    stiffness_slots: tuple
    defaults: dict
    contact_time: Callable
    drop: Callable
    source: str
    from_block: Callable | None = None
    law_damping: Callable | None = None
    block_damping: Callable | None = None
    step_setting: str = "timestep"
    needs_radius: bool = False
    read_at: str = "the contact surface"

    @property
    def affine(self) -> bool:
        """Whether the map is piecewise affine (``kernels.AFFINE``).

        Then phase means are exact and batches run at formula speed.
        """
        return self.code in kernels.AFFINE

    def pack(self, **values: float) -> np.ndarray:
        """``p`` from slot names (``defaults`` fill the rest); ValueError naming a missing or unknown slot."""
        unknown = sorted(set(values) - set(self.slots))
        if unknown:
            raise ValueError(f"{self.name}: unknown parameter(s) {unknown}; the slots are {self.slots}")
        merged = {**self.defaults, **values}
        missing = [s for s in self.slots if s not in merged]
        if missing:
            raise ValueError(f"{self.name}: parameter(s) {missing} are required; the slots are {self.slots}")
        return np.array([float(merged[s]) for s in self.slots])

    def unpack(self, p: np.ndarray) -> dict[str, float]:
        """Slot name -> value of ``p``."""
        return {s: float(v) for s, v in zip(self.slots, p, strict=True)}


STEPPERS: tuple[Stepper, ...] = (
    Stepper(
        name="mujoco",
        code=kernels.MUJOCO,
        integrators=mujoco_map.INTEGRATORS,
        timestep=mujoco_map.TIMESTEP,
        slots=mujoco_map.SLOT_NAMES,
        damping_slots=(mujoco_map.DAMPING,),
        stiffness_slots=(mujoco_map.STIFFNESS,),
        defaults={"diag_ratio": 1.0},
        contact_time=mujoco_map.contact_time,
        drop=drop_mujoco,
        from_block=mujoco_map.from_block,
        law_damping=mujoco_map.law_damping,
        block_damping=mujoco_map.block_damping,
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
        damping_slots=(pybullet_map.DAMPING_BALL, pybullet_map.DAMPING_GROUND),
        stiffness_slots=(pybullet_map.STIFFNESS_BALL, pybullet_map.STIFFNESS_GROUND),
        defaults={"slop": pybullet_map.LINEAR_SLOP},
        contact_time=pybullet_map.contact_time,
        drop=drop_pybullet,
        from_block=pybullet_map.from_block,
        law_damping=pybullet_map.law_damping,
        block_damping=pybullet_map.block_damping,
        needs_radius=True,
        read_at="the geometric surface (Bullet's solver surface lies the 1e-5 m linear slop below it)",
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
        damping_slots=(drake_map.DISSIPATION_BALL, drake_map.DISSIPATION_GROUND),
        stiffness_slots=(drake_map.STIFFNESS_BALL, drake_map.STIFFNESS_GROUND),
        defaults={},
        contact_time=drake_map.contact_time,
        drop=drop_drake,
        from_block=drake_map.from_block,
        law_damping=drake_map.law_damping,
        block_damping=drake_map.block_damping,
        step_setting="time_step",
        source="drake multibody/plant: discrete_update_manager.cc "
        "(AppendDiscreteContactPairsForPointContact), "
        "multibody_plant.h (CombinePointContactParameters), tamsi_solver.cc, sap_driver.cc; "
        "multibody/contact_solvers/sap: sap_hunt_crossley_constraint.cc (CalcDiscreteHuntCrossleyImpulse)",
    ),
)
STEPPER_NAMES: tuple[str, ...] = tuple(s.name for s in STEPPERS)
_REGISTER_LOCK = threading.Lock()


def map_problem(s: Stepper) -> str | None:
    """Why ``s``'s kernel code does not run its own map (``kernels.MAPS``), or None when it does."""
    m = kernels.MAPS.get(s.code) if isinstance(s.code, int) else None
    if m is None:
        return (
            f"kernel code {s.code!r} of {s.name!r} is not a registered step map: register the engine's step "
            "with stepping.kernels.register_map and give its code"
        )
    if m.name != s.name:
        return f"kernel code {s.code!r} is {m.name!r}'s step map, not {s.name!r}'s"
    return None


def register(s: Stepper) -> Stepper:
    """Add ``s`` to ``STEPPERS`` (the same stepper again: nothing); ``s`` back.

    ValueError when its code does not run its own map (``map_problem``) or another stepper has
    its name.
    """
    global STEPPERS, STEPPER_NAMES
    if not isinstance(s, Stepper):
        raise ValueError(f"{s!r} is not a stepping.registry.Stepper")
    problem = map_problem(s)
    if problem:
        raise ValueError(f"stepper {s.name!r}: {problem}")
    with _REGISTER_LOCK:
        for old in STEPPERS:
            if old.name == s.name:
                if old is s:
                    return s
                raise ValueError(f"stepper {s.name!r} is registered already (kernel code {old.code})")
        STEPPERS = (*STEPPERS, s)
        STEPPER_NAMES = tuple(x.name for x in STEPPERS)
    return s


def stepper(name: str) -> Stepper:
    """The registered stepper called ``name``; ValueError naming the valid choices otherwise."""
    for s in STEPPERS:
        if s.name == name:
            return s
    raise ValueError(f"engine = {name!r} has no step map; the valid choices are {STEPPER_NAMES}")
