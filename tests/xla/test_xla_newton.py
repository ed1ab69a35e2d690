"""Newton on this CPU: per-shape ke/kd from the JAX front door give each world its target.

Newton's MuJoCo solver with per-shape force-space ``ke``/``kd`` (``xla.newton_drop``): each world
within 1e-3 of its target at a small step, and within float32 of MuJoCo's own run of it.
"""

import numpy as np
import pytest

from contactalpha.adapters.stepped import measure_steps, touchdown_state

pytestmark = pytest.mark.integration


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
    from contactalpha.xla.newton_drop import FREE_RTOL_F32, rollout

    s = _worlds(6, 4)
    out = contact_parameters(**s, law="mujoco_soft")
    assert np.asarray(out["ok"]).all()
    block = out["engines"]["newton"]
    ke, kd = np.asarray(block["shape_material_ke"]), np.asarray(block["shape_material_kd"])
    d = float(np.asarray(block["solimp"])[0, 0])
    omega = np.sqrt(s["stiffness"] / s["mass"])
    h = 2.0 * np.pi / omega.max() / 4000  # at least 4,000 steps per undamped period in every world
    nstep = int(0.8 * 2.0 * np.pi / omega.min() / h)
    z, w = rollout(s, ke, kd, d, h, nstep)
    v, a = s["approach_speed"], s["accel"]
    got = np.array([measure_steps(z[i], w[i], a[i], h, v[i], FREE_RTOL_F32).e_n for i in range(6)])
    solref = np.asarray(out["engines"]["mujoco"]["solref"])
    mujoco_e = np.array([_mujoco_drop(s, i, solref[i], d, h, nstep) for i in range(6)])
    np.testing.assert_allclose(got, mujoco_e, atol=1e-4)  # Newton steps like MuJoCo (float32)
    np.testing.assert_allclose(got, s["target"], atol=1e-3)
