"""The impulse engines: each one's step map and what its restitution means (one record each).

The inverse (``inverse.restitution_for``), the front door (``parameters.impulse``) and the adapters
(``adapters.pybullet_impulse``, ``adapters.physx_sapien``) look an engine up here by its name.
"""

import math
from collections.abc import Callable
from dataclasses import dataclass

from . import bullet_map, kernels, physx_map


@dataclass(frozen=True)
class ImpulseEngine:
    """One impulse engine's map and conventions.

    Attributes
    ----------
    name : the registry key (as in ``adapters.registry``).
    code : its kernel code (``kernels.step_impulse``).
    timestep : its default step, s.
    threshold : its default velocity threshold, m/s.
    params : ``(pair restitution, radius m, threshold m/s) -> p`` for its map.
    per_body : each body's restitution for the pair's (its combining rule undone).
    combine : the combining rule, in words.
    source : where the map was read from.
    holds : whether a body landed with restitution 0 can be sent off again from rest by the map's
        coefficient (``schedule.Rebounder`` then holds each contact for the loaded contact's
        duration; else it releases each touchdown at once).
    """

    name: str
    code: int
    timestep: float
    threshold: float
    params: Callable
    per_body: Callable
    combine: str
    source: str
    holds: bool = True


ENGINES = {
    e.name: e
    for e in (
        ImpulseEngine(
            "pybullet_impulse", kernels.BULLET, bullet_map.DEFAULT_TIMESTEP, bullet_map.VELOCITY_THRESHOLD,
            lambda e, r, t: bullet_map.make_params(e, r, t), math.sqrt,
            "product (btManifoldResult::calculateCombinedRestitution)",
            "bullet3: btMultiBodyConstraintSolver::setupMultiBodyContactConstraint, "
            "btSequentialImpulseConstraintSolver::setupContactConstraint, restitutionCurve",
        ),
        ImpulseEngine(
            "physx", kernels.PHYSX, physx_map.DEFAULT_TIMESTEP, physx_map.BOUNCE_THRESHOLD,
            lambda e, r, t: physx_map.make_params(e, t), lambda pair: pair,
            "average (PxCombineMode::eAVERAGE, the default)",
            "PhysX 5: DyTGSContactPrep.cpp constructContactConstraintStep, solveDynamicContactsStep; "
            "DyTGSDynamics.cpp (10 position, 1 velocity iteration)",
        ),
    )
}  # fmt: skip


def impulse_engine(name: str) -> ImpulseEngine:
    """The record of impulse engine ``name``; ValueError naming the valid choices otherwise."""
    if name not in ENGINES:
        raise ValueError(f"engine = {name!r} is not an impulse engine; valid: {tuple(ENGINES)}")
    return ENGINES[name]
