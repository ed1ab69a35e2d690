"""MuJoCo Warp on this CPU: per-world geom_solref (a world axis) gives each world MuJoCo's own drop."""

import numpy as np
import pytest

from contactalpha.adapters.stepped import measure_steps, touchdown_state

pytestmark = pytest.mark.integration


def test_per_world_solref_steps_like_mujoco(mujoco, mujoco_warp):
    import warp as wp

    from contactalpha.xla.mjx_drop import base_model

    mjw = mujoco_warp

    s, b = np.array([2e4, 1e5]), np.array([60.0, 200.0])  # per unit mass: 1/s^2, 1/s
    v, a, h = 0.8, 9.81, 5e-5
    z0, w0 = touchdown_state(v, a, h, 0.0)
    nstep = int(1.5 * 2 * np.pi / np.sqrt(s.min()) / h)
    m = base_model(0.9)
    m.opt.timestep = h
    d = mujoco.MjData(m)
    d.qpos[0], d.qvel[0], d.ctrl[0] = z0, w0, -a
    with wp.ScopedDevice("cpu"):
        mw, dw = mjw.put_model(m), mjw.put_data(m, d, nworld=2)
        mw.geom_solref = wp.array(np.repeat(np.stack([-s, -b], -1)[:, None, :], m.ngeom, 1), dtype=wp.vec2)
        z, w = [], []
        for _ in range(nstep):
            mjw.step(mw, dw)
            z.append(dw.qpos.numpy()[:, 0].copy())
            w.append(dw.qvel.numpy()[:, 0].copy())
    z, w = np.array(z).T, np.array(w).T
    for i in range(2):
        mm = base_model(0.9)
        mm.opt.timestep = h
        mm.geom_solref[:] = (-s[i], -b[i])
        dd = mujoco.MjData(mm)
        dd.qpos[0], dd.qvel[0], dd.ctrl[0] = z0, w0, -a
        zr, wr = [], []
        for _ in range(nstep):
            mujoco.mj_step(mm, dd)
            zr.append(dd.qpos[0])
            wr.append(dd.qvel[0])
        e_warp = measure_steps(np.r_[z0, z[i]], np.r_[w0, w[i]], a, h, v).e_n
        e_mujoco = measure_steps(np.r_[z0, zr], np.r_[w0, wr], a, h, v).e_n
        assert 0.2 < e_mujoco < 0.9
        # MuJoCo Warp computes in float32.
        assert e_warp == pytest.approx(e_mujoco, abs=1e-4)


def test_phase_mean_answer_at_2ms_steps_like_the_map(mujoco, mujoco_warp):
    """The stepped answer at MuJoCo's 2 ms step, one world per touchdown phase: the map's e_N."""
    import warp as wp

    from contactalpha.parameters.front_door import contact_parameters
    from contactalpha.stepping.delivered import at_phases
    from contactalpha.stepping.registry import stepper
    from contactalpha.xla.mjx_drop import base_model

    mjw = mujoco_warp
    mass, k, v, a, target, h = 0.5, 1e4, 0.5, 9.81, 0.5, 0.002
    scene = {"mass": mass, "stiffness": k, "approach_speed": v, "accel": a, "e_N": target}
    cp = contact_parameters(**scene, engine="mujoco", timestep=h)
    block = cp.engines["mujoco"]
    phases = (np.arange(32) + 0.5) / 32
    start = np.array([touchdown_state(v, a, h, f) for f in phases])
    m = base_model(float(block["solimp"][0]), mass=mass)
    m.opt.timestep = h
    m.geom_solref[:] = block["solref"]
    m.geom_solimp[:] = block["solimp"]
    nstep = int(3.0 * 2.0 * np.pi / np.sqrt(k / mass) / h) + 4
    with wp.ScopedDevice("cpu"):
        mw, dw = mjw.put_model(m), mjw.put_data(m, mujoco.MjData(m), nworld=len(phases))
        dw.qpos.assign(start[:, :1].astype(np.float32))
        dw.qvel.assign(start[:, 1:].astype(np.float32))
        dw.ctrl.assign(np.full((len(phases), 1), -mass * a, dtype=np.float32))
        z, w = [start[:, 0]], [start[:, 1]]
        for _ in range(nstep):
            mjw.step(mw, dw)
            z.append(dw.qpos.numpy()[:, 0].copy())
            w.append(dw.qvel.numpy()[:, 0].copy())
    z, w = np.array(z, dtype=float).T, np.array(w, dtype=float).T
    got = np.array([measure_steps(z[i], w[i], a, h, v, free_rtol=1e-6).e_n for i in range(len(phases))])
    p = stepper("mujoco").from_block(block, mass, None)
    mapped = at_phases("mujoco", p, h, phases, v, a)["e_n"]
    assert np.ptp(mapped) > 0.05  # the phase matters at 2 ms
    np.testing.assert_allclose(got, mapped, atol=1e-4)  # float32
    assert abs(got.mean() - target) <= 1e-3
