"""Many worlds of one drop in MJX, each with its own mass, load, speed, step and contact parameters.

The model is the MuJoCo adapter's drop (``adapters.mujoco_soft``: a sphere on a vertical slide
joint above a plane, ``condim = 1``), with gravity 0 and the whole load from the joint's motor,
so that any acceleration ``a >= 0`` is one control value.  Per world, the batched ``mjx.Model``
carries ``geom_solref`` and ``geom_solimp`` (both geoms: MuJoCo takes the minimum of two direct
solrefs and the mean of the solimps, the values themselves for equal ones), ``body_mass`` with
the contact's inverse weight ``body_invweight0`` (MuJoCo's regulariser reads it; it scales as
1/m for this body) and ``opt.timestep``; ``jax.vmap`` maps over exactly these fields
(``in_axes``: None elsewhere).  Each world starts a given fraction of a step before touchdown
(its phase; 0 by default, ``adapters.stepped.touchdown_state``), and its e_N is read by
``adapters.stepped.measure_steps``.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import TYPE_CHECKING, Any, cast

import jax
import jax.numpy as jnp
import numpy as np

from contactalpha.adapters.mujoco_soft import MuJoCoSettings, drop_xml
from contactalpha.adapters.stepped import measure_steps, touchdown_state

if TYPE_CHECKING:
    import mujoco
    from jax.typing import ArrayLike
    from mujoco import mjx

# Radius of the sphere, m (the law does not depend on it).
RADIUS = 0.05


def base_model(impedance: float, integrator: str = "Euler", mass: float = 1.0) -> mujoco.MjModel:
    """The MuJoCo model of one drop (gravity 0; ``mass`` kg), to be batched per world."""
    import mujoco

    scene = SimpleNamespace(gravity=0.0, radius=RADIUS, mass=float(mass))
    settings = MuJoCoSettings(timestep=1e-3, impedance=impedance, integrator=integrator)
    return mujoco.MjModel.from_xml_string(drop_xml(scene, settings))


def batched_model(
    model: mujoco.MjModel, mass: np.ndarray, solref: np.ndarray, solimp: np.ndarray, timestep: ArrayLike
) -> tuple[mjx.Model, Any]:
    """``(mjx.Model with a leading world axis on the per-world fields, in_axes for jax.vmap)``."""
    from mujoco import mjx

    n = len(mass)
    ball = model.body("ball").id
    mx = mjx.put_model(model)
    body_mass = np.tile(model.body_mass, (n, 1))
    body_mass[:, ball] = mass
    invweight = np.tile(model.body_invweight0, (n, 1, 1))
    invweight[:, ball, :] *= model.body_mass[ball] / np.asarray(mass)[:, None]
    fields = {
        "geom_solref": np.repeat(np.asarray(solref)[:, None, :], model.ngeom, axis=1),
        "geom_solimp": np.repeat(np.asarray(solimp)[:, None, :], model.ngeom, axis=1),
        "body_mass": body_mass,
        "body_invweight0": invweight,
        "opt.timestep": np.asarray(timestep, dtype=float),
    }
    batched = mx.tree_replace({k: jnp.asarray(v) for k, v in fields.items()})
    in_axes = jax.tree_util.tree_map(lambda _: None, mx).tree_replace({k: 0 for k in fields})
    return batched, in_axes


def rollout(
    model: mujoco.MjModel,
    mass: np.ndarray,
    accel: np.ndarray,
    approach_speed: np.ndarray,
    solref: np.ndarray,
    solimp: np.ndarray,
    timestep: ArrayLike,
    nstep: int,
    phase: ArrayLike = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Heights ``z`` (m above touchdown) and upward speeds ``v`` of every world, shape (n, nstep + 1).

    ``phase`` (per world or one for all, in [0, 1)): the fraction of a step before touchdown at
    which each world starts (``adapters.stepped.touchdown_state``).
    """
    from mujoco import mjx

    batched, in_axes = batched_model(model, mass, solref, solimp, timestep)
    phase = np.broadcast_to(np.asarray(phase, dtype=float), np.shape(mass))
    start = np.array(
        [
            touchdown_state(v, a, h, f)
            for v, a, h, f in zip(approach_speed, accel, cast(Any, timestep), phase, strict=True)
        ]
    )
    data = mjx.make_data(mjx.put_model(model))
    push = -np.asarray(mass) * np.asarray(accel)

    def one(m, z0, v0, f):
        d = data.replace(
            qpos=data.qpos.at[0].set(z0), qvel=data.qvel.at[0].set(v0), ctrl=data.ctrl.at[0].set(f)
        )

        def step(d, _):
            d = mjx.step(m, d)
            return d, (d.qpos[0], d.qvel[0])

        _, (z, v) = jax.lax.scan(step, d, None, length=nstep)
        return jnp.concatenate([z0[None], z]), jnp.concatenate([v0[None], v])

    run = jax.jit(jax.vmap(one, in_axes=(in_axes, 0, 0, 0)))
    z, v = run(batched, jnp.asarray(start[:, 0]), jnp.asarray(start[:, 1]), jnp.asarray(push))
    return np.asarray(z), np.asarray(v)


def delivered_e_n(
    z: np.ndarray, v: np.ndarray, accel: np.ndarray, timestep: np.ndarray, approach_speed: np.ndarray
) -> np.ndarray:
    """e_N of each world's run (``adapters.stepped.measure_steps``)."""
    return np.array(
        [measure_steps(z[i], v[i], accel[i], timestep[i], approach_speed[i]).e_n for i in range(len(accel))]
    )
