"""One scene, the continuous law: the damping for the target, its impact, the engines' blocks.

Two paths, by the law: Hunt-Crossley (n = 3/2, the default) takes alpha from the shipped table
inside its domain and from ``engine.solver`` outside it, at the paper's xi (Eq. 10); every other
law of the family takes its damping from its own inverse (``laws.maps``).  Both integrate the one
impact for its restitutions and end state, and give the e_N the same physical damping delivers at
half and at twice the approach speed (``SPEED_FACTORS``).  Inputs arrive checked
(``front_door``).
"""

import math
from typing import Any

import numpy as np

from contactalpha.adapters.registry import adapter, engine_parameters
from contactalpha.engine import driver
from contactalpha.engine.scaling import influence_factor_unchecked, length_scale
from contactalpha.engine.solver import solve_alpha
from contactalpha.engine.table import EPS_MIN, XI_MAX, alpha_tabulated
from contactalpha.laws import maps
from contactalpha.laws.domain import target_name
from contactalpha.laws.law import ContactLaw

from .block_scene import BlockScene
from .reach import UnreachableTarget, eps_zero_without_load
from .result import ContactParameters

# Approach speeds, as factors of the given one, at which the fixed physical damping is checked.
SPEED_FACTORS = (0.5, 2.0)
# Where the law's inverse fails, a load factor this close to 1, or a target this small, is named as
# the cause: the load outweighs the approach, or the target is next to capture.
XI_NEAR_ONE = 1.0 - 1e-6
TARGET_SMALL = 1e-3


def engine_blocks(law: ContactLaw, damping: Any, scene: BlockScene, engine: str | None = None) -> dict:
    """``engine``'s block for the law's ``damping`` in ``scene``, or every engine's of ``law`` (None)."""
    if engine is None:
        return engine_parameters(law, damping, scene)
    return {engine: adapter(engine).parameters(damping, scene)}


def hunt_crossley_parameters(
    law: ContactLaw,
    value: float,
    restitution: str,
    mass: float,
    stiffness: float,
    approach_speed: float,
    accel: float,
    radius: float | None,
    engine: str | None = None,
) -> ContactParameters:
    """``ContactParameters`` of one Hunt-Crossley scene (n = 3/2) for checked SI inputs."""
    xi = influence_factor_unchecked(mass, stiffness, approach_speed, accel)
    if restitution == "energetic" and value == 0.0 and xi == 0.0:
        raise eps_zero_without_load()
    alpha, source = _alpha(value, xi, restitution)
    r = driver.impact_unchecked(alpha, xi)
    if r.status != "ok":
        raise RuntimeError(f"impact at alpha = {alpha!r}, xi = {xi!r} failed: {r.status}")
    scene = BlockScene(mass, stiffness, approach_speed, radius)
    e_n_half, e_n_twice = (
        _hunt_crossley_e_n(alpha, mass, stiffness, approach_speed, accel, f) for f in SPEED_FACTORS
    )
    return driver.frozen_instance(
        ContactParameters,
        law=law.name,
        xi=xi,
        damping_name=law.damping,
        damping=alpha,
        physical_damping=law.physical_damping_unchecked(alpha, mass, stiffness, approach_speed),
        physical_unit=law.physical_unit,
        eps=r.eps,
        e_n=r.e_n,
        end_state=r.state,
        ok=True,
        reason="",
        accel=accel,
        delta_star=float(length_scale(mass, stiffness, approach_speed)),
        source=source,
        engines=engine_blocks(law, alpha, scene, engine),
        e_n_half_speed=e_n_half,
        e_n_twice_speed=e_n_twice,
        engine=None,
        stepped=None,
    )


def _alpha(value, xi, restitution):
    """``(alpha, source)``: the shipped table inside its domain, the solver outside it."""
    if EPS_MIN <= value <= 1.0 and xi <= XI_MAX:
        return alpha_tabulated(value, xi, restitution=restitution), "table"
    sol = solve_alpha(value, xi, restitution=restitution)
    if not sol.ok:
        where = f"{target_name(restitution)} = {value!r}, xi = {xi!r}"
        raise RuntimeError(f"exact alpha not found at {where}: {sol.status}")
    return sol.alpha, "solver"


def _hunt_crossley_e_n(alpha, mass, stiffness, speed, accel, factor):
    """Newton's e_N of an impact at ``factor`` times ``speed`` with the same damping ``mu = alpha k / v``."""
    try:
        xi = influence_factor_unchecked(mass, stiffness, speed * factor, accel)
    except ValueError:  # the load's xi rounds to 1 at that speed: no impact to speak of
        return math.nan
    r = driver.impact_unchecked(alpha * factor, xi)
    return float(r.e_n) if r.status == "ok" else math.nan


def law_parameters(
    law: ContactLaw,
    value: float,
    restitution: str,
    mass: float,
    stiffness: float,
    approach_speed: float,
    accel: float,
    radius: float | None = None,
    engine: str | None = None,
) -> ContactParameters:
    """``ContactParameters`` of one scene of another law of the family for checked SI inputs.

    ``stiffness`` is the law's physical one (N/m for n = 1, N/m^1.5 for n = 3/2); the engines'
    blocks (``adapters.registry.engine_parameters``) convert it to their own units.
    """
    xi = float(law.scene_load_factor_unchecked(mass, stiffness, approach_speed, accel))
    if value == 0.0:
        raise ValueError(
            f"{'eps' if restitution == 'energetic' else 'e_N'} = 0.0 is outside the valid range (0.0, 1.0] "
            f"of law {law.name!r}"
        )
    sol = maps.damping_for_unchecked(law, value, xi, restitution)
    if not sol.ok:
        raise unresolved(law, value, restitution, xi, approach_speed, accel, sol.status)
    p = float(sol.damping)
    scene = BlockScene(mass, stiffness, approach_speed, radius)
    e_n_half, e_n_twice = (
        float(fixed_damping_e_n(law, p, mass, stiffness, approach_speed, accel, f)) for f in SPEED_FACTORS
    )
    return ContactParameters(
        law=law.name,
        xi=xi,
        damping_name=law.damping,
        damping=p,
        physical_damping=float(law.physical_damping_unchecked(p, mass, stiffness, approach_speed)),
        physical_unit=law.physical_unit,
        eps=float(sol.eps),
        e_n=float(sol.e_n),
        end_state=str(sol.state),
        ok=True,
        reason="",
        accel=accel,
        delta_star=float(law.length_scale_unchecked(mass, stiffness, approach_speed)),
        source="solver",
        engines=engine_blocks(law, p, scene, engine),
        e_n_half_speed=e_n_half,
        e_n_twice_speed=e_n_twice,
    )


def unresolved(
    law: ContactLaw,
    value: float,
    restitution: str,
    xi: float,
    approach_speed: float,
    accel: float,
    status: str,
) -> UnreachableTarget:
    """``UnreachableTarget`` for a scene the law's inverse does not resolve: what the user can change."""
    name = target_name(restitution)
    where = f"no {law.damping} of law {law.name!r} gives {name} = {value!r} at xi = {xi!r} ({status})"
    hints = []
    if xi >= XI_NEAR_ONE:
        hints.append(
            f"the load factor is within {1.0 - xi:.2g} of 1: the load (accel = {accel!r} m/s^2) "
            f"outweighs the approach (approach_speed = {approach_speed!r} m/s); give a faster approach "
            "or a smaller load"
        )
    if value < TARGET_SMALL:
        hints.append(
            f"{name} = {value!r} is next to capture (no rebound), where the restitution falls steeply "
            f"with the damping; give {name} >= {TARGET_SMALL:g}, or model the contact as capture"
        )
    if not hints:
        hints.append("the scene is at the edge of what the law resolves; give a target or a load farther "
                     "from it")  # fmt: skip
    return UnreachableTarget(f"{where}: {'; '.join(hints)}")


def fixed_damping_e_n(
    law: ContactLaw,
    p: Any,
    mass: Any,
    stiffness: Any,
    approach_speed: Any,
    accel: Any,
    factor: float,
    load_factor: Any = None,
) -> float | np.ndarray:
    """Newton's e_N at ``factor`` times the approach speed with the same physical damping as ``p``.

    The physical damping is ``p m^a k^b v^c`` (``ContactLaw.damping_unit``), so at the speed
    ``factor v`` the law's damping is ``p factor^-c``; the load factor is the scene's at that
    speed (``load_factor(mass, stiffness, speed, accel)`` if given, else the law's).  NaN where the
    load's xi rounds to 1 there or the impact fails; arrays go through.
    """
    speed = np.asarray(approach_speed, dtype=float) * factor
    with np.errstate(all="ignore"):
        if load_factor is None:
            A = law.load_unchecked(mass, stiffness, speed, accel)
            xi = np.asarray(law.load_factor_unchecked(A), dtype=float)
        else:
            xi = np.asarray(load_factor(mass, stiffness, speed, accel), dtype=float)
    p_f = np.asarray(p, dtype=float) * factor ** -law.damping_unit[3]
    good = np.isfinite(p_f) & (xi < 1.0)
    r = maps.impact_unchecked(law, np.where(good, p_f, 0.0), np.where(good, xi, 0.0))
    e_n = np.where(good & (np.asarray(r.status) == "ok"), r.e_n, np.nan)
    return float(e_n) if e_n.ndim == 0 else e_n
