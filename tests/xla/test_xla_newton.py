"""Newton on this CPU: per-shape ke/kd from the JAX front door give each world its target.

Newton's MuJoCo solver (``SolverMuJoCo``, MuJoCo Warp underneath, float32 on Warp's CPU backend)
with its own collision pipeline and every shape in ``SOLREF_MODE_FORCE_SPACE``: per contact it
turns the shapes' ``shape_material_ke``/``kd`` into ``solref = (timeconst, dampratio)`` with the
gain ``(1 - d)/m`` (``xla.engines``).  Each world is a free sphere above one shared plane, with its
own mass, speed, load (the world's gravity) and target; ``condim = 1`` (frictionless: the
law's contact) and ``solimp = (d, d, ...)`` on every shape.  All worlds step with one dt.
"""

import numpy as np
import pytest

from contactalpha.adapters.stepped import measure_steps, touchdown_state

pytestmark = pytest.mark.integration

RADIUS = 0.05
# float32 velocities: a free-flight step is -a h to about 1e-7 of the speed.
FREE_RTOL_F32 = 1e-6


def _worlds(n, seed):
    rng = np.random.default_rng(seed)
    mass = rng.uniform(0.1, 2.0, n)
    return {
        "mass": mass,
        "stiffness": mass * rng.uniform(1e4, 2e4, n),  # N/m: 1e4-2e4 per unit mass, one dt fits all
        "approach_speed": rng.uniform(0.3, 2.0, n),
        "accel": rng.uniform(0.5, 20.0, n),
        "target": rng.uniform(0.2, 0.9, n),
    }


def _newton_drop(newton, s, ke, kd, d, h, nstep):
    """Heights above touchdown and upward speeds of every world, shape (n, nstep + 1)."""
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
    model = builder.finalize(device="cpu")
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


def _mujoco_drop(s, i, solref, d, h, nstep):
    """MuJoCo's own run of world ``i`` (the adapter's drop) with the direct solref, float64."""
    import mujoco

    from contactalpha.xla.mjx_drop import base_model

    m = base_model(d, mass=s["mass"][i])
    m.opt.timestep = h
    m.geom_solref[:] = solref
    data = mujoco.MjData(m)
    data.qpos[0], data.qvel[0] = touchdown_state(s["approach_speed"][i], s["accel"][i], h, 0.0)
    data.ctrl[0] = -s["mass"][i] * s["accel"][i]
    z, w = [data.qpos[0]], [data.qvel[0]]
    for _ in range(nstep):
        mujoco.mj_step(m, data)
        z.append(data.qpos[0])
        w.append(data.qvel[0])
    return measure_steps(np.array(z), np.array(w), s["accel"][i], h, s["approach_speed"][i]).e_n


def test_newton_per_shape_ke_kd_deliver_each_worlds_target(jax, mujoco, newton):
    from contactalpha.xla.front import contact_parameters

    s = _worlds(6, 4)
    out = contact_parameters(**s, law="mujoco_soft")
    assert np.asarray(out["ok"]).all()
    block = out["engines"]["newton"]
    ke, kd = np.asarray(block["shape_material_ke"]), np.asarray(block["shape_material_kd"])
    d = float(np.asarray(block["solimp"])[0, 0])
    omega = np.sqrt(s["stiffness"] / s["mass"])
    h = 2.0 * np.pi / omega.max() / 4000  # at least 4,000 steps per undamped period in every world
    nstep = int(0.8 * 2.0 * np.pi / omega.min() / h)
    z, w = _newton_drop(newton, s, ke, kd, d, h, nstep)
    v, a = s["approach_speed"], s["accel"]
    got = np.array([measure_steps(z[i], w[i], a[i], h, v[i], FREE_RTOL_F32).e_n for i in range(6)])
    solref = np.asarray(out["engines"]["mujoco"]["solref"])
    mujoco_e = np.array([_mujoco_drop(s, i, solref[i], d, h, nstep) for i in range(6)])
    np.testing.assert_allclose(got, mujoco_e, atol=1e-4)  # Newton steps like MuJoCo (float32)
    np.testing.assert_allclose(got, s["target"], atol=1e-3)
