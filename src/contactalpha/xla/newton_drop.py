"""Many worlds of one drop in Newton (its MuJoCo solver), each with its own mass, load, speed and ke/kd.

Newton's ``SolverMuJoCo`` (MuJoCo Warp underneath; float32 on Warp's CPU backend) with Newton's
own collision pipeline and every shape in ``SOLREF_MODE_FORCE_SPACE``: per contact it turns the
shapes' ``shape_material_ke``/``kd`` into ``solref = (timeconst, dampratio)`` with the gain
``(1 - d)/m`` (``xla.engines``).  Each world is a free sphere above one shared plane, with its own
mass, speed and load (the world's gravity); ``condim = 1`` (frictionless: the law's contact) and
``solimp = (d, d, ...)`` on every shape; the plane's ``geom_solmix`` is 0, so that each contact
takes the sphere's ke/kd.  All worlds step with one dt, and start a step before touchdown at
phase 0 (``adapters.stepped.touchdown_state``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from contactalpha.adapters.stepped import touchdown_state

# Radius of the sphere, m (the law does not depend on it).
RADIUS = 0.05
# float32 velocities: a free-flight step is -a h to about 1e-7 of the speed
# (``adapters.stepped.measure_steps``' ``free_rtol``).
FREE_RTOL_F32 = 1e-6


def rollout(
    s: Mapping[str, np.ndarray], ke: np.ndarray, kd: np.ndarray, d: float, h: float, nstep: int
) -> tuple[np.ndarray, np.ndarray]:
    """Heights above touchdown and upward speeds of every world, shape (n, nstep + 1).

    ``s``: per-world ``mass`` (kg), ``approach_speed`` (m/s), ``accel`` (m/s^2); ``ke`` (N/m),
    ``kd`` (N s/m) per world; ``d`` the impedance; ``h`` the step (s).
    """
    import newton
    import warp as wp
    from newton.solvers import SolverMuJoCo

    n = len(s["mass"])
    builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    SolverMuJoCo.register_custom_attributes(builder)
    start = [touchdown_state(s["approach_speed"][i], s["accel"][i], h, 0.0) for i in range(n)]
    for i in range(n):
        builder.begin_world(gravity=(0.0, 0.0, -float(s["accel"][i])))
        m = float(s["mass"][i])
        body = builder.add_body(
            xform=wp.transform((0.0, 0.0, RADIUS + start[i][0]), wp.quat_identity()),
            mass=m,
            inertia=wp.mat33(np.eye(3) * 0.4 * m * RADIUS**2),
        )
        cfg = newton.ModelBuilder.ShapeConfig(ke=float(ke[i]), kd=float(kd[i]), density=0.0, mu=0.0)
        builder.add_shape_sphere(body, radius=RADIUS, cfg=cfg)
        builder.end_world()
    builder.add_ground_plane(cfg=newton.ModelBuilder.ShapeConfig(ke=1.0, kd=1.0, mu=0.0))
    model: Any = builder.finalize(device="cpu")  # SolverMuJoCo adds model.mujoco at run time
    shapes = model.shape_count
    model.mujoco.condim.assign(np.ones(shapes, dtype=np.int32))
    model.mujoco.geom_solimp.assign(np.tile([d, d, 0.001, 0.5, 2.0], (shapes, 1)).astype(np.float32))
    model.mujoco.solref_mode.assign(np.zeros(shapes, dtype=np.int32))  # SOLREF_MODE_FORCE_SPACE
    solmix = np.ones(shapes, dtype=np.float32)
    solmix[-1] = 0.0  # the plane: each contact takes the sphere's ke/kd
    model.mujoco.geom_solmix.assign(solmix)
    state, nxt, control = model.state(), model.state(), model.control()
    qd = state.joint_qd.numpy().reshape(n, 6).copy()
    qd[:, 2] = [w for _, w in start]
    state.joint_qd.assign(qd.reshape(-1))
    solver = SolverMuJoCo(model, use_mujoco_contacts=False)
    pipeline = newton.CollisionPipeline(model)
    contacts = pipeline.contacts()
    z, w = [np.array([z0 for z0, _ in start])], [qd[:, 2].copy()]
    for _ in range(nstep):
        pipeline.collide(state, contacts)
        solver.step(state, nxt, control, contacts, h)
        state, nxt = nxt, state
        z.append(state.joint_q.numpy().reshape(n, 7)[:, 2].copy() - RADIUS)
        w.append(state.joint_qd.numpy().reshape(n, 6)[:, 2].copy())
    return np.array(z, dtype=float).T, np.array(w, dtype=float).T
