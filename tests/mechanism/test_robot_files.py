"""Robot files as they ship (``robot_files``, ``touch``): unnamed collisions, no floor, .stl meshes,
a pose apart from touch, a joint outside its limits.

The model is a pendulum URDF (a 0.5 m arm of 1 kg, uniform, on a hinge about y at the origin)
whose tip sphere's ``<collision>`` has no name.  Expected values are closed forms: the tip's
effective mass I / L^2, the tip's height -L sin(theta), the touching angle.
"""

import math

import pytest

from contactalpha.mechanism import read_contact
from contactalpha.mechanism.robot_files import collision_name, engine_for, prepared_urdf
from contactalpha.mechanism.touch import first_touch, joint_limit_problems

L, R, MASS = 0.5, 0.02, 1.0
I_HINGE = MASS * L * L / 3.0  # a uniform rod about its end
URDF = """<robot name="pendulum">
  <link name="base"/>
  <link name="arm">
    <inertial><origin xyz="0.25 0 0"/><mass value="1.0"/>
      <inertia ixx="0.001" iyy="0.0208333333333" izz="0.0208333333333" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.02"/></geometry></collision>
  </link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="100" velocity="100"/></joint>
  {mesh}
</robot>
"""
TIP = collision_name("arm", 0)
GROUND_PAIR = ("ground", TIP)


@pytest.fixture
def pendulum(tmp_path):
    path = tmp_path / "pendulum.urdf"
    path.write_text(URDF.format(mesh=""))
    return path


def _tip_gap(theta):
    """The tip sphere's height above z = 0 less its radius: -L sin(theta) - R."""
    return -L * math.sin(theta) - R


@pytest.mark.parametrize("reader", ["mujoco", "drake"])
def test_an_unnamed_collision_is_named_by_its_link_and_the_ground_is_added(pendulum, reader, mujoco, pydrake):
    named = prepared_urdf(pendulum, ground=True)
    theta = -0.3
    c = read_contact(named, GROUND_PAIR, reader=reader, qpos=[theta], speed=1.0)
    assert c.gap == pytest.approx(_tip_gap(theta), abs=1e-9)
    # The tip's effective mass along the vertical normal: I / (L cos(theta))^2.
    assert c.effective_mass == pytest.approx(I_HINGE / (L * math.cos(theta)) ** 2, rel=1e-6)


def test_without_preparing_the_unnamed_collision_cannot_be_addressed(pendulum, mujoco):
    with pytest.raises(ValueError, match="arm/collision0"):
        read_contact(pendulum, ("arm/collision0", "arm/collision0"), reader="mujoco", qpos=[0.0], speed=1.0)


def test_a_pose_apart_is_moved_to_first_touch_along_the_approach(pendulum, mujoco):
    named = prepared_urdf(pendulum, ground=True)

    def read(q):
        return read_contact(named, GROUND_PAIR, reader="mujoco", qpos=q, qvel=[2.0])

    apart = read([-0.3])
    assert apart.gap > 0.1
    touched, note = first_touch(read, apart)
    # The touching angle: -L sin(theta) = R.
    assert touched.qpos[0] == pytest.approx(-math.asin(R / L), abs=1e-7)
    assert abs(touched.gap) <= 1e-6
    assert "moved to first touch" in note


@pytest.mark.parametrize("reader", ["mujoco", "drake"])
def test_a_joint_outside_its_limits_is_named(pendulum, reader, mujoco, pydrake):
    named = prepared_urdf(pendulum, ground=True)
    inside = read_contact(named, GROUND_PAIR, reader=reader, qpos=[-0.5], speed=1.0)
    outside = read_contact(named, GROUND_PAIR, reader=reader, qpos=[-1.2], speed=1.0)
    assert joint_limit_problems(inside) == []
    (line,) = joint_limit_problems(outside)
    assert "'hinge'" in line and "-1.2" in line


def test_the_engine_for_a_urdf_with_stl_meshes_is_one_that_reads_them(tmp_path, pydrake, mujoco):
    path = tmp_path / "arm.urdf"
    path.write_text(URDF.format(mesh='<link name="shell"><collision><geometry><mesh filename="shell.stl"/>'
                                '</geometry></collision></link>'))  # fmt: skip
    engine, why = engine_for(path)
    assert engine == "mujoco" and "drake reads no .stl" in why
    plain = tmp_path / "plain.urdf"
    plain.write_text(URDF.format(mesh=""))
    assert engine_for(plain)[0] == "drake"
