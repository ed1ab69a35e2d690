"""Genesis's ``sol_params`` from the JAX front door, checked in MuJoCo, whose law Genesis runs.

Genesis is not installed here (docs/engines/batched.md: its install cost); it takes MuJoCo's
(timeconst, dampratio) form only.  Handed to MuJoCo as a positive ``solref`` with ``solimp`` =
``sol_params[2:]``, that form must step exactly as the direct pair does where the front door gives
it, and where it says ``needs_direct`` MuJoCo's refsafe must change the contact.
"""

import numpy as np
import pytest

from contactalpha.adapters.stepped import touchdown_state

pytestmark = pytest.mark.integration

STEP = 0.002  # MuJoCo's and Genesis's default step, s


def _run(mass, accel, speed, solref, solimp, nstep=150):
    import mujoco

    from contactalpha.xla.mjx_drop import base_model

    m = base_model(float(solimp[0]), mass=mass)
    m.opt.timestep = STEP
    m.geom_solref[:] = solref
    m.geom_solimp[:] = solimp
    d = mujoco.MjData(m)
    d.qpos[0], d.qvel[0] = touchdown_state(speed, accel, STEP, 0.0)
    d.ctrl[0] = -mass * accel
    z = [d.qpos[0]]
    for _ in range(nstep):
        mujoco.mj_step(m, d)
        z.append(d.qpos[0])
    return np.array(z)


def test_genesis_sol_params_step_as_mujocos_direct_pair(jax, mujoco):
    from contactalpha.xla.front import contact_parameters

    mass = np.array([0.5, 1.5, 1.0])
    stiffness = np.array([5e3, 2e4, 1e6]) * mass  # N/m; the last too stiff for the timeconst form
    speed, accel, target = np.array([0.5, 1.5, 1.0]), np.array([9.81, 3.0, 9.81]), np.array([0.6, 0.3, 0.5])
    out = contact_parameters(mass, stiffness, speed, accel, target, law="mujoco_soft", timestep=STEP)
    genesis, direct = out["engines"]["genesis"], out["engines"]["mujoco"]
    params = np.asarray(genesis["sol_params"])
    assert np.asarray(genesis["needs_direct"]).tolist() == [False, False, True]
    for i in range(2):
        z_direct = _run(mass[i], accel[i], speed[i], np.asarray(direct["solref"])[i], params[i, 2:])
        z_genesis = _run(mass[i], accel[i], speed[i], params[i, :2], params[i, 2:])
        assert z_direct.min() < 0.0  # the run holds the contact
        np.testing.assert_allclose(z_genesis, z_direct, rtol=0, atol=1e-9 * np.abs(z_direct).max())
    assert np.isnan(params[2, :2]).all()
    # Its timeconst 1/(zeta omega) is under two steps: MuJoCo's refsafe raises it, another contact.
    zeta, omega = float(np.asarray(out["damping"])[2]), np.sqrt(stiffness[2] / mass[2])
    assert 1.0 / (zeta * omega) < 2.0 * STEP
    solimp = np.asarray(direct["solimp"])[2]
    z_direct = _run(mass[2], accel[2], speed[2], np.asarray(direct["solref"])[2], solimp)
    z_timeconst = _run(mass[2], accel[2], speed[2], [1.0 / (zeta * omega), zeta], solimp)
    assert np.abs(z_timeconst - z_direct).max() > 1e-3 * np.abs(z_direct).max()
