"""MJX with per-world contact parameters: it steps like MuJoCo, and each world delivers its target."""

import numpy as np
import pytest

pytestmark = pytest.mark.integration


def _scenes(n, seed):
    rng = np.random.default_rng(seed)
    return {
        "mass": rng.uniform(0.1, 2.0, n),
        "stiffness": 10.0 ** rng.uniform(3.0, 5.0, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 30.0, n),
        "target": rng.uniform(0.1, 0.9, n),
    }


def test_mjx_steps_like_mujoco(jax, mjx):
    """Per-world fields batched in MJX give MuJoCo's own trajectories at the default 2 ms step."""
    import mujoco

    from contactalpha.adapters.stepped import touchdown_state
    from contactalpha.xla import mjx_drop

    s = _scenes(3, 1)
    omega2 = s["stiffness"] / s["mass"]
    solref = np.stack([-omega2, -2.0 * 0.3 * np.sqrt(omega2)], axis=-1)
    solimp = np.tile([0.9, 0.9, 0.001, 0.5, 2.0], (3, 1))
    h = np.full(3, 0.002)
    model = mjx_drop.base_model(0.9)
    z, v = mjx_drop.rollout(model, s["mass"], s["accel"], s["approach_speed"], solref, solimp, h, 120)
    for i in range(3):
        # MuJoCo's own model of this world: compiled at its mass (inverse weights from the compiler).
        m = mjx_drop.base_model(0.9, mass=s["mass"][i])
        m.opt.timestep = h[i]
        m.geom_solref[:] = solref[i]
        m.geom_solimp[:] = solimp[i]
        d = mujoco.MjData(m)
        d.qpos[0], d.qvel[0] = touchdown_state(s["approach_speed"][i], s["accel"][i], h[i], 0.0)
        d.ctrl[0] = -s["mass"][i] * s["accel"][i]
        zs, vs = [d.qpos[0]], [d.qvel[0]]
        for _ in range(120):
            mujoco.mj_step(m, d)
            zs.append(d.qpos[0])
            vs.append(d.qvel[0])
        assert min(zs) < 0.0  # the run holds a contact
        np.testing.assert_allclose(z[i], zs, rtol=0, atol=1e-12 * max(abs(np.array(zs))))
        np.testing.assert_allclose(v[i], vs, rtol=0, atol=1e-12 * max(abs(np.array(vs))))


def test_every_world_delivers_its_target(jax, mjx):
    """A small batch (benchmarks/study_mjx_batch.py runs 1,024): each world within 1e-3 of its target."""
    from contactalpha.xla import mjx_drop
    from contactalpha.xla.front import contact_parameters

    s = _scenes(6, 2)
    out = contact_parameters(**s, law="mujoco_soft")
    ok = np.asarray(out["ok"])
    assert ok.all()
    blocks = out["engines"]["mjx"]
    per_period = 4000
    h = 2.0 * np.pi / np.sqrt(s["stiffness"] / s["mass"]) / per_period
    z, v = mjx_drop.rollout(
        mjx_drop.base_model(0.9), s["mass"], s["accel"], s["approach_speed"],
        np.asarray(blocks["solref"]), np.asarray(blocks["solimp"]), h, int(1.5 * per_period),
    )  # fmt: skip
    got = mjx_drop.delivered_e_n(z, v, s["accel"], h, s["approach_speed"])
    np.testing.assert_allclose(got, s["target"], atol=1e-3)
