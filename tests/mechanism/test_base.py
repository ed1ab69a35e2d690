"""One URDF, one mechanism: a URDF's root link is fixed in Drake as in MuJoCo (issue 43's Kuka).

The file has no ``world`` link: MuJoCo (and PyBullet, as the package loads it) fix its root
link, Drake's parser left it floating, so the whole robot, floor included, fell freely in Drake
and the pressing load read near zero.
"""

import pytest

from contactalpha.mechanism import read_contact

URDF = """<robot name="arm">
  <link name="base"><inertial><mass value="5"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision name="floor"><origin xyz="0.5 0 -0.55"/><geometry><box size="2 2 0.1"/></geometry>
    </collision></link>
  <link name="arm"><inertial><origin xyz="0.25 0 0"/><mass value="1.5"/>
    <inertia ixx="0.001" iyy="0.03" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision name="tip"><origin xyz="0.5 0 0"/><geometry><sphere radius="0.03"/></geometry>
    </collision></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="100" velocity="10"/></joint>
</robot>
"""


@pytest.fixture
def arm(tmp_path):
    path = tmp_path / "arm.urdf"
    # the tip's bottom (z = -0.03) 2 cm above the floor's top (z = -0.05): touch after a small turn
    path.write_text(URDF.replace('xyz="0.5 0 -0.55"', 'xyz="0.5 0 -0.1"'))
    return path


def test_drake_fixes_a_urdf_root_as_mujoco_does(arm, mujoco, pydrake):
    import math

    angle = math.asin(0.02 / 0.5)  # the tip down onto the floor
    # MuJoCo's hinge axis is y: a positive turn lowers the tip at x = 0.5
    mj = read_contact(arm, ("floor", "tip"), reader="mujoco", qpos=[angle], speed=0.5)
    dk = read_contact(arm, ("floor", "tip"), reader="drake", qpos=[angle], speed=0.5)
    assert abs(mj.gap) < 1e-6 and abs(dk.gap) < 1e-6
    assert dk.effective_mass == pytest.approx(mj.effective_mass, rel=1e-6)
    assert dk.accel == pytest.approx(mj.accel, rel=1e-6)
    assert dk.accel > 5.0  # gravity presses the arm down: not a free fall of the whole robot
    assert "welded to the world" in dk.engine_row["base"]
    floating = read_contact(arm, ("floor", "tip"), reader="drake", qpos=[1, 0, 0, 0, 0, 0, 0, angle],
                            speed=0.5, base="floating")  # fmt: skip
    assert abs(floating.accel) < 0.5  # Drake's own default: everything falls together
