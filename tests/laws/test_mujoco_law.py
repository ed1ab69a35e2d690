"""MuJoCo's soft contact, measured in MuJoCo: the mujoco_soft law's static penetration and rebound."""

import os

import numpy as np
import pytest

from contactalpha.laws import get_law

if os.environ.get("CI") == "true":
    import mujoco  # under CI a missing engine fails
else:
    mujoco = pytest.importorskip("mujoco")

pytestmark = pytest.mark.integration

G = 9.81
RADIUS = 0.1


def _model(stiffness, damping, d, dt):
    """A unit-mass sphere on a plane, frictionless (condim 1), direct-mode solref, constant impedance d."""
    xml = f"""
<mujoco>
  <option timestep="{dt!r}" gravity="0 0 {-G}"/>
  <default><geom condim="1" solref="{-stiffness!r} {-damping!r}" solimp="{d!r} {d!r} 0.001 0.5 2"/></default>
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body pos="0 0 {RADIUS}"><freejoint/><geom type="sphere" size="{RADIUS}" mass="1"/></body>
  </worldbody>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def _rest_penetration(stiffness, d, dt=1e-4, seconds=5.0):
    m = _model(stiffness, 2.0 * float(np.sqrt(stiffness)), d, dt)
    data = mujoco.MjData(m)
    for _ in range(int(seconds / dt)):
        mujoco.mj_step(m, data)
    return RADIUS - data.qpos[2]


def _rebound(stiffness, damping, d, speed, dt):
    """Newton's e_N of a drop that touches the plane at ``speed``: the speed where the sphere leaves it."""
    m = _model(stiffness, damping, d, dt)
    data = mujoco.MjData(m)
    data.qvel[2] = -speed
    z0, v0 = data.qpos[2], data.qvel[2]
    for _ in range(int(1.0 / dt)):
        mujoco.mj_step(m, data)
        z, v = data.qpos[2], data.qvel[2]
        if z >= RADIUS > z0:
            return (v0 + (RADIUS - z0) / (z - z0) * (v - v0)) / speed
        z0, v0 = z, v
    return 0.0


@pytest.mark.parametrize("d", [0.5, 0.9, 0.99])
def test_resting_penetration_is_one_minus_d_of_the_load(d):
    stiffness = 1e4
    assert _rest_penetration(stiffness, d) == pytest.approx((1.0 - d) * G / stiffness, rel=1e-6)


@pytest.mark.parametrize(
    ("stiffness", "damping", "d", "speed"),
    [(1e4, 20.0, 0.9, 0.5), (1e4, 60.0, 0.5, 0.3), (4e4, 40.0, 0.99, 0.2)],
)
def test_rebound_matches_the_mujoco_soft_law(stiffness, damping, d, speed):
    law = get_law("mujoco_soft", impedance=d)
    omega = np.sqrt(stiffness)
    zeta = law.damping_from_physical(damping, 1.0, stiffness, speed)
    assert zeta == pytest.approx(damping / (2.0 * omega), rel=1e-15)
    predicted = law.impact(zeta, law.load_factor(G / (omega * speed))).e_n
    # MuJoCo's rebound moves with the timestep to first order: extrapolate dt -> 0 from 1e-5 and 1e-6.
    coarse, fine = (_rebound(stiffness, damping, d, speed, dt) for dt in (1e-5, 1e-6))
    assert abs(fine - predicted) < 1e-4
    assert abs(fine - (coarse - fine) / 9.0 - predicted) < 2e-6
    # The plain spring-dashpot carrying (1 - d) of the load is a different law, distinguishable here.
    kv = get_law("kelvin_voigt")
    plain = kv.impact(zeta, kv.load_factor((1.0 - d) * G / (omega * speed))).e_n
    assert abs(plain - predicted) > 1e-3
