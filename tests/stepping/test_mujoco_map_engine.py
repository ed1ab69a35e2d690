"""MuJoCo's own mj_step against the map, step by step and drop by drop (integration)."""

import math

import numpy as np
import pytest

from contactalpha.adapters.mujoco_soft import MuJoCoSettings, drop_xml
from contactalpha.adapters.stepped import measure_steps
from contactalpha.stepping.delivered import at_phases
from contactalpha.stepping.drop import touchdown_state
from contactalpha.stepping.registry import stepper

mujoco = pytest.importorskip("mujoco")
pytestmark = pytest.mark.integration

H = 0.002
G = 9.81
# (mass kg, stiffness N/m, zeta, speed m/s, push N): 10 scenes over the ranges.
SCENES = [
    (0.5, 2e4, 0.2, 0.5, 0.0),
    (20.0, 1e5, 0.05, 3.0, 100.0),
    (0.02, 500.0, 0.6, 0.05, 0.1),
    (0.1, 3e3, 0.1, 1.0, 0.0),
    (2.0, 5e4, 0.3, 0.2, 20.0),
    (5.0, 2e5, 0.02, 2.0, 50.0),
    (0.05, 1e3, 0.4, 0.3, 0.5),
    (1.0, 1e4, 0.15, 0.1, 5.0),
    (10.0, 4e5, 0.08, 1.5, 100.0),
    (0.2, 8e3, 0.25, 0.7, 2.0),
]


class _Scene:
    def __init__(self, mass):
        self.mass, self.gravity, self.radius = mass, G, 0.05


def _engine(mass, integrator):
    settings = MuJoCoSettings(timestep=H, integrator=integrator)
    model = mujoco.MjModel.from_xml_string(drop_xml(_Scene(mass), settings))
    return model, mujoco.MjData(model)


def _params(mass, k, zeta):
    omega2 = k / mass
    return omega2, 2.0 * zeta * math.sqrt(omega2)


def _run(model, data, z0, w0, push, n):
    mujoco.mj_resetData(model, data)
    data.qpos[0], data.qvel[0], data.ctrl[0] = z0, w0, -push
    z, w = [z0], [w0]
    for _ in range(n):
        mujoco.mj_step(model, data)
        z.append(float(data.qpos[0]))
        w.append(float(data.qvel[0]))
    return np.array(z), np.array(w)


@pytest.mark.parametrize("integrator", ["Euler", "implicitfast"])
@pytest.mark.parametrize("scene", SCENES)
def test_a_whole_drop_follows_mujoco_step_by_step(scene, integrator):
    from contactalpha.stepping.drop import trajectory
    from contactalpha.stepping.kernels import MUJOCO

    mass, k, zeta, v, push = scene
    stiffness, damping = _params(mass, k, zeta)
    model, data = _engine(mass, integrator)
    model.geom_solref[:] = (-stiffness, -damping)
    accel = G + push / mass
    p = stepper("mujoco").pack(stiffness=stiffness, damping=damping, impedance=MuJoCoSettings().impedance)
    n = int(2.5 * math.pi / math.sqrt(stiffness) / H) + 10  # through the contact and beyond
    for phase in (0.0, 0.31, 0.77):
        z0, w0 = touchdown_state(v, accel, H, phase)
        z_mj, w_mj = _run(model, data, z0, w0, push, n)
        z, w = trajectory(MUJOCO, p, H, phase, v, accel, n)
        assert np.max(np.abs(z - z_mj)) <= 1e-9 * np.max(np.abs(z_mj))
        assert np.max(np.abs(w - w_mj)) <= 1e-9 * np.max(np.abs(w_mj))


@pytest.mark.parametrize("integrator", ["Euler", "implicitfast"])
@pytest.mark.parametrize("scene", [SCENES[i] for i in (0, 1, 3, 4, 9)])
def test_e_n_at_64_phases_is_mujocos(scene, integrator):
    mass, k, zeta, v, push = scene
    stiffness, damping = _params(mass, k, zeta)
    model, data = _engine(mass, integrator)
    model.geom_solref[:] = (-stiffness, -damping)
    accel = G + push / mass
    p = stepper("mujoco").pack(stiffness=stiffness, damping=damping, impedance=MuJoCoSettings().impedance)
    phases = np.arange(64) / 64
    n = int(3.0 * 2.0 * math.pi / math.sqrt(stiffness) / H) + 4
    measured = []
    for phase in phases:
        z0, w0 = touchdown_state(v, accel, H, phase)
        z, w = _run(model, data, z0, w0, push, n)
        measured.append(measure_steps(z, w, accel, H, v).e_n)  # the adapters' own reading
    predicted = at_phases("mujoco", p, H, phases, v, accel)["e_n"]
    assert np.allclose(predicted, measured, rtol=1e-9, atol=1e-12)
    assert np.ptp(predicted) > 1e-3  # the phase matters at 2 ms: the test sees it


def test_the_adapters_reading_takes_the_first_impact_not_a_deeper_later_one():
    """A high-e_N drop bounces again inside MuJoCo's window; e_N is the first impact's (the map's)."""
    from contactalpha.stepping.drop import run_drop, trajectory
    from contactalpha.stepping.kernels import MUJOCO

    p = stepper("mujoco").pack(stiffness=2.5e4, damping=10.4, impedance=0.9)
    phase, v, a = 34 / 128, 0.1, 9.81
    z, w = trajectory(MUJOCO, p, H, phase, v, a, 60)  # three contact periods: two impacts
    assert np.argmin(z) > 20  # the deepest point is the second impact's
    e_map = run_drop(MUJOCO, p, H, phase, v, a, 10_000)[0]
    assert measure_steps(z, w, a, H, v).e_n == pytest.approx(e_map, rel=1e-12)


def test_a_batch_at_the_step_is_what_mujoco_delivers():
    """Rows of a batch at 2 ms, dropped in MuJoCo at 128 phases: MuJoCo's e_N per phase is the map's,
    so the exact mean of the batch's parameters (the target within 1e-6, by the drop-by-drop
    quadrature) is MuJoCo's."""
    from contactalpha import contact_parameters
    from contactalpha.stepping.delivered import over_phase

    rng = np.random.default_rng(21)
    n = 6
    m = np.exp(rng.uniform(np.log(0.1), np.log(5.0), n))
    k = m * (math.pi / (rng.uniform(15.0, 40.0, n) * H)) ** 2
    v = rng.uniform(0.5, 2.0, n)
    e = rng.uniform(0.3, 0.9, n)
    cp = contact_parameters(
        mass=m, stiffness=k, approach_speed=v, accel=G, e_N=e, engine="mujoco", timestep=H
    )
    rows = [i for i in range(n) if cp.stepped.status[i] == "ok"][:3]
    assert len(rows) == 3
    phases = np.arange(128) / 128
    for i in rows:
        stiffness, damping = -cp.block["solref"][i]  # a row per scene
        model, data = _engine(float(m[i]), "Euler")
        model.geom_solref[:] = (-stiffness, -damping)
        p = stepper("mujoco").pack(stiffness=stiffness, damping=damping, impedance=MuJoCoSettings().impedance)
        steps = int(3.0 * 2.0 * math.pi / math.sqrt(stiffness) / H) + 4
        measured = []
        for phase in phases:
            z0, w0 = touchdown_state(float(v[i]), G, H, phase)
            z, w = _run(model, data, z0, w0, 0.0, steps)
            measured.append(measure_steps(z, w, G, H, v[i]).e_n)
        assert np.allclose(at_phases("mujoco", p, H, phases, v[i], G)["e_n"], measured, rtol=1e-9, atol=1e-12)
        assert abs(over_phase("mujoco", p, H, v[i], G).mean - e[i]) <= 1e-6
        assert cp.stepped.minimum[i] <= np.mean(measured) <= cp.stepped.maximum[i]


def _armature_drop(mass, armature, stiffness, damping, impedance):
    """A sphere on a vertical slide joint with ``armature``: diagApprox (1/m) is not A (1/(m + arm))."""
    xml = f"""
<mujoco>
  <option timestep="{H!r}" gravity="0 0 -{G!r}"/>
  <worldbody>
    <geom type="plane" size="1 1 0.1" condim="1" solref="{-stiffness!r} {-damping!r}"
          solimp="{impedance!r} {impedance!r} 0.001 0.5 2"/>
    <body pos="0 0 0.05">
      <joint type="slide" axis="0 0 1" armature="{armature!r}"/>
      <geom type="sphere" size="0.05" mass="{mass!r}" condim="1" solref="{-stiffness!r} {-damping!r}"
            solimp="{impedance!r} {impedance!r} 0.001 0.5 2"/>
    </body>
  </worldbody>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def _run_unforced(model, data, z0, w0, n):
    mujoco.mj_resetData(model, data)
    data.qpos[0], data.qvel[0] = z0, w0
    z, w = [z0], [w0]
    for _ in range(n):
        mujoco.mj_step(model, data)
        z.append(float(data.qpos[0]))
        w.append(float(data.qvel[0]))
    return np.array(z), np.array(w)


def test_a_contact_whose_diag_approx_is_not_its_inverse_mass_follows_mujoco():
    # Every scene above is a free body (diag ratio 1): the ratio's place in the soft row is unseen
    # there.  With armature the contact's true inverse mass is 1/(m + arm) while MuJoCo's
    # diagApprox is the body's 1/m: the ratio r = diagApprox (m + arm) is 1.6 here.
    from contactalpha.stepping.drop import trajectory
    from contactalpha.stepping.kernels import MUJOCO

    mass, armature, stiffness, damping, d, v = 0.5, 0.3, 2e4, 30.0, 0.9, 0.5
    model = _armature_drop(mass, armature, stiffness, damping, d)
    data = mujoco.MjData(model)
    data.qpos[0] = -1e-3  # in contact: read the row MuJoCo builds
    mujoco.mj_forward(model, data)
    A = float(data.efc_J[0] ** 2 / data.M[0])  # J M^-1 J^T of the one row and one dof
    ratio = float(data.efc_diagA[0]) / A
    assert A == pytest.approx(1.0 / (mass + armature), rel=1e-12) and ratio == pytest.approx(1.6, rel=1e-12)
    accel = G * mass / (mass + armature)  # gravity acts on the mass, the armature only resists
    p = stepper("mujoco").pack(stiffness=stiffness, damping=damping, impedance=d, diag_ratio=ratio)
    n = int(2.5 * math.pi / math.sqrt(stiffness) / H) + 10
    for phase in (0.0, 0.31, 0.77):
        z0, w0 = touchdown_state(v, accel, H, phase)
        z_mj, w_mj = _run_unforced(model, data, z0, w0, n)
        z, w = trajectory(MUJOCO, p, H, phase, v, accel, n)
        assert np.max(np.abs(z - z_mj)) <= 1e-9 * np.max(np.abs(z_mj))
        assert np.max(np.abs(w - w_mj)) <= 1e-9 * np.max(np.abs(w_mj))
    free_body = stepper("mujoco").pack(stiffness=stiffness, damping=damping, impedance=d)
    z, w = trajectory(MUJOCO, free_body, H, 0.31, v, accel, n)
    assert np.max(np.abs(w - _run_unforced(model, data, *touchdown_state(v, accel, H, 0.31), n)[1])) > 1e-3
