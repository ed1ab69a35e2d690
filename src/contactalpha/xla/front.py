"""The JAX front door: target restitutions of many scenes -> the law's damping and the engines' parameters.

``contact_parameters`` is ``parameters.batch.batched_parameters`` as a pure function of arrays: it
accepts ``jax.jit``, ``jax.vmap`` and ``jax.grad`` (the law and the restitution are static).
The law's damping comes from its shipped table on the device (``tables.py``), or, for a law whose
impacts have a closed form (MuJoCo's soft contact at any impedance, the spring-dashpot), from
``inverse.py``.  Nothing raises inside a trace: a scene outside the domain (a target below the
table's 0.01, a load factor above 0.99, a non-positive mass) gets NaN and ``ok = False``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import jax.numpy as jnp

from contactalpha.laws import get_law

from . import engines, scaling
from .inverse import law_damping

if TYPE_CHECKING:
    from jax.typing import ArrayLike


def contact_parameters(
    mass: ArrayLike,
    stiffness: ArrayLike,
    approach_speed: ArrayLike,
    accel: ArrayLike,
    target: ArrayLike,
    *,
    restitution: str = "kinematic",
    law: str = "hunt_crossley",
    impedance: float | None = None,
    timestep: ArrayLike = engines.TIMESTEP,
) -> dict[str, Any]:
    """The law's damping and every batched engine's parameters for arrays of scenes (broadcast).

    Parameters
    ----------
    mass, stiffness, approach_speed : array_like
        kg, the law's stiffness (N/m^1.5 for n = 3/2, N/m for n = 1), m/s.
    accel : array_like
        Acceleration of the load pressing the bodies together, m/s^2 (>= 0).
    target : array_like
        Target restitution in [0.01, 1].
    restitution : {"kinematic", "energetic"}
        Newton's e_N or Stronge's eps (static).
    law : str
        A law of ``contactalpha.laws`` (static).
    impedance : float, optional
        MuJoCo's constant impedance d for ``mujoco_soft`` (static; default the law's 0.9).
    timestep : array_like
        The engines' step, s: where the (timeconst, dampratio) form exists (``engines.py``).

    Returns
    -------
    dict
        ``xi`` (load factor), ``damping`` (the law's dimensionless damping), ``physical_damping``
        (the law's engine damping, ``ContactLaw.physical_damping``), ``ok`` and, for a law whose
        engine records have batched blocks (MuJoCo's: ``mujoco``, ``mjx``, ``mujoco_warp``,
        ``newton``, ``genesis``), ``engines`` keyed by batched engine (``engines.blocks_of``).
    """
    chosen = get_law(law) if impedance is None else get_law(law, impedance=impedance)
    m, k, v, a, e = jnp.broadcast_arrays(
        *(jnp.asarray(x, dtype=float) for x in (mass, stiffness, approach_speed, accel, target))
    )
    valid = (m > 0.0) & (k > 0.0) & (v > 0.0) & (a >= 0.0) & jnp.isfinite(m + k + v + a)
    xi = scaling.load_factor(chosen, jnp.where(valid, scaling.scaled_load(chosen, m, k, v, a), jnp.nan))
    p = law_damping(chosen, e, xi, restitution)
    ok = valid & jnp.isfinite(p)
    p = jnp.where(ok, p, jnp.nan)
    factor, pm, pk, pv = chosen.damping_unit
    out = {"xi": xi, "damping": p, "ok": ok, "physical_damping": p * factor * m**pm * k**pk * v**pv}
    if engines.blocks_of(chosen.name):  # the engine records' batched blocks of this law
        scene = engines.EngineScene(m, k, timestep, chosen.impedance)
        out["engines"] = engines.engine_blocks(p, scene, chosen.name)
    return out
