"""The batched engines' parameters as JAX arrays, keyed by engine as ``contact_parameters`` keys them.

The engine records (``adapters.registry``) name these blocks; ``BLOCKS`` and ``blocks_of`` are
derived from them.  The five here run MuJoCo's soft contact (law ``mujoco_soft``): ``delta'' =
a - max(0, d a + b delta' + s delta)`` per unit mass, with ``s = k / m`` and ``b = 2 zeta sqrt(s)``
(``adapters.mujoco_soft.per_unit_mass``; docs/engines/batched.md).

- ``mujoco``, ``mjx``, ``mujoco_warp``: direct mode ``solref = (-s, -b)`` and ``solimp = (d, d, ...)``
  per world (MJX: a batched ``Model.geom_solref``; MuJoCo Warp: ``geom_solref`` with a world axis),
  and the (timeconst, dampratio) form where refsafe keeps it (``adapters.mujoco_soft.timeconst_form``).
- ``genesis``: only the (timeconst, dampratio) form exists there (``sol_params``); where it does not
  (timeconst below 2 steps) the entries are NaN and ``needs_direct`` is True.
- ``newton``: per-shape force-space ``ke``, ``kd`` for its MuJoCo solver, which turns them into
  ``solref = (timeconst, dampratio)`` with the gain factor ``(1 - d) / m``: ``s = (1 - d) ke / m``,
  ``b = (1 - d) kd / m``, so ``ke = k / (1 - d)`` and ``kd = b m / (1 - d)``; as a timeconst form
  it exists only where refsafe keeps it (``needs_direct`` elsewhere; ``mjc_solref`` is the direct
  pair for its raw solref mode).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import jax.numpy as jnp

from contactalpha.adapters.mujoco_soft import (
    IMPEDANCE,
    SOLIMP_TAIL,
    TIMESTEP,
    direct_mode,
    per_unit_mass,
    timeconst_form,
)
from contactalpha.adapters.registry import batched_blocks

if TYPE_CHECKING:
    import jax
    from jax.typing import ArrayLike


@dataclass(frozen=True)
class EngineScene:
    """Per-world arrays: ``mass`` (kg), ``stiffness`` (N/m), ``timestep`` (s) and the impedance ``d``."""

    mass: object
    stiffness: object
    timestep: object = TIMESTEP
    impedance: float = IMPEDANCE


def mujoco_block(zeta: ArrayLike, scene: EngineScene) -> dict[str, jax.Array]:
    """MuJoCo's, MJX's and MuJoCo Warp's block: direct-mode ``solref``/``solimp`` rows, the timeconst form."""
    s, omega, b = per_unit_mass(zeta, scene.stiffness, scene.mass, xp=jnp)
    solref, solimp = direct_mode(s, b, scene.impedance)
    tc, dr = timeconst_form(zeta, omega, scene.timestep, xp=jnp)
    solimp = jnp.broadcast_to(jnp.asarray(solimp), (*jnp.shape(b), len(solimp)))
    return {
        "stiffness": s,
        "damping": b,
        "solref": jnp.stack(jnp.broadcast_arrays(*solref), axis=-1),
        "solimp": solimp,
        "timeconst": tc,
        "dampratio": dr,
    }


def genesis_block(zeta: ArrayLike, scene: EngineScene) -> dict[str, jax.Array]:
    """Genesis's ``sol_params`` (the timeconst form only; ``needs_direct`` where it does not exist)."""
    m = mujoco_block(zeta, scene)
    d = jnp.full(jnp.shape(m["timeconst"]), scene.impedance)
    tail = [jnp.full(jnp.shape(d), x) for x in SOLIMP_TAIL]
    return {
        "sol_params": jnp.stack([m["timeconst"], m["dampratio"], d, d, *tail], axis=-1),
        "needs_direct": jnp.isnan(m["timeconst"]),
    }


def newton_block(zeta: ArrayLike, scene: EngineScene) -> dict[str, jax.Array]:
    """Newton's per-shape ``ke``, ``kd`` for its MuJoCo solver, and the direct pair of its raw mode."""
    m = mujoco_block(zeta, scene)
    gain = (1.0 - scene.impedance) / cast(Any, scene.mass)
    return {
        "shape_material_ke": m["stiffness"] / gain,
        "shape_material_kd": m["damping"] / gain,
        "needs_direct": jnp.isnan(m["timeconst"]),
        "mjc_solref": m["solref"],
        "solimp": m["solimp"],
    }


def blocks_of(law: str) -> dict:
    """``{batched engine: block(zeta, EngineScene)}`` of the engine records whose law is ``law``."""
    return {name: block for name, (of, block) in batched_blocks().items() if of == law}


# The law MuJoCo's soft contact's blocks run, and engine name -> its block of ``zeta`` (the law's
# damping ratio) and an ``EngineScene`` (from the engine records).
LAW = "mujoco_soft"
BLOCKS = blocks_of(LAW)


def engine_blocks(zeta: ArrayLike, scene: EngineScene, law: str = LAW) -> dict[str, dict[str, jax.Array]]:
    """Every batched engine's parameters of ``law`` for its damping ``zeta`` (arrays broadcast)."""
    return {name: block(zeta, scene) for name, block in blocks_of(law).items()}
