"""The stepping adapters' defaults are the engines' own, read from the engines (issue 34, planted bugs).

A default time step or impedance changed by mistake gives every engine block and every refinement
another engine than the one users run; nothing else in the default run would notice.
"""

import math

import pytest

from contactalpha.adapters import drake_point, mujoco_soft, pybullet_kv
from contactalpha.adapters.contract import DropScene


def test_mujocos_default_step_and_impedance_are_mujocos():
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom size="1"/></worldbody></mujoco>')
    settings = mujoco_soft.ADAPTER.settings
    assert settings.timestep == model.opt.timestep == 0.002
    assert settings.impedance == model.geom_solimp[0][0] == 0.9
    assert mujoco_soft.ADAPTER.law.impedance == model.geom_solimp[0][0]
    assert mujoco_soft.SOLIMP_TAIL == tuple(model.geom_solimp[0][2:])


def test_pybullets_default_step_is_pybullets():
    pb = pytest.importorskip("pybullet")
    client = pb.connect(pb.DIRECT)
    try:
        step = pb.getPhysicsEngineParameters(physicsClientId=client)["fixedTimeStep"]
    finally:
        pb.disconnect(client)
    assert pybullet_kv.ADAPTER.settings.timestep == step == 1.0 / 240.0


def test_drakes_default_step_is_drakes():
    plant = pytest.importorskip("pydrake.multibody.plant")
    assert drake_point.ADAPTER.settings.time_step == plant.MultibodyPlantConfig().time_step == 1e-3


@pytest.mark.parametrize("factor", [1.5, 1.99, 2.01, 3.0])
def test_mujocos_timeconst_form_exists_only_from_twice_the_step(factor):
    # MuJoCo clamps a solref time constant below 2 timestep up to 2 timestep (its "refsafe" rule),
    # so (timeconst, dampratio) cannot represent a faster contact: it must be NaN there.
    h = mujoco_soft.ADAPTER.settings.timestep
    omega = 100.0
    zeta = 1.0 / (factor * h * omega)  # timeconst 1 / (zeta omega) = factor * h
    scene = DropScene(1.0, omega * omega, 0.5, 9.81, 0.0, 0.05)
    out = mujoco_soft.ADAPTER.parameters(zeta, scene)
    if factor >= 2.0:
        assert out["timeconst"] == pytest.approx(factor * h, rel=1e-12) and out["dampratio"] == zeta
    else:
        assert math.isnan(out["timeconst"]) and math.isnan(out["dampratio"])
    assert out["solref"] == (-omega * omega, pytest.approx(-2.0 * zeta * omega, rel=1e-15))
