"""Issue 43's stack and box in PyBullet's engine loop, with the robot's base floating.

Each answer is measured in raw PyBullet (``pybullet_scenes``: fresh worlds, free falls from a
random height, e_N read off the sampled gap), not on the loop's phases.
"""

import numpy as np
import pytest
from pybullet_scenes import BOX, STACK, G, raw_drops, resting_height
from raw_reading import start_rate

from contactalpha.mechanism.engine_loop import solve_damping
from contactalpha.mechanism.pybullet_floating import GROUND
from contactalpha.mechanism.pybullet_loop import PybulletLoop

SPEED = 1.0
STEP = 1e-3
STIFFNESS = 1e4


def test_pybullet_loop_delivers_the_stack(pybullet, tmp_path):
    """The 0.5 kg sphere lands at 1 m/s on the 1 kg one resting on the floor; the pair's values on
    the upper sphere's link (PyBullet's values act on every contact of a link: on the lower one
    they would soften its floor support too, and e_N stays below 0.14 for any damping)."""
    urdf = tmp_path / "stack.urdf"
    urdf.write_text(STACK)
    z = resting_height(pybullet, urdf, STEP)
    qpos, qvel = [1, 0, 0, 0, 0, 0, z, 0.0], [0, 0, 0, 0, 0, 0, -SPEED]
    loop = PybulletLoop(urdf, ("low", "top"), qpos, qvel, timestep=STEP, base="floating", set_on=("top",))
    target = 0.3
    ans = solve_damping(loop, target, (STIFFNESS, 10.0))
    loop.close()
    assert ans.status == "ok" and abs(ans.delivered.mean - target) <= 1.2e-4

    def place(pb, c, body, tau):
        pb.resetBasePositionAndOrientation(body, [0, 0, z], [0, 0, 0, 1], physicsClientId=c)
        pb.resetJointState(
            body, 0, SPEED * tau - 0.5 * G * tau * tau, start_rate(SPEED, tau, STEP), physicsClientId=c
        )

    values = {("robot", 1): ans.solref}
    mean, stderr = raw_drops(pybullet, urdf, STEP, 256, place, values, (("robot", -1), ("robot", 1)))
    assert abs(mean - target) <= 2e-3, (mean, stderr)


HALF = 0.05  # the cube's half edge


def _box_pose(tilt):
    """Drake's floating qpos of the cube tilted by ``tilt`` about x, its lowest edge on the floor."""
    z = HALF * (np.cos(tilt) + np.sin(tilt))
    return [np.cos(tilt / 2), np.sin(tilt / 2), 0, 0, 0, 0, z]


def test_pybullet_loop_delivers_the_flat_box(pybullet, tmp_path):
    """A cube landing flat: PyBullet's manifold has its four bottom corners, each with the pair's
    values: one contact mode, tuned and measured as the box."""
    urdf = tmp_path / "box.urdf"
    urdf.write_text(BOX)
    qvel = [0, 0, 0, 0, 0, -SPEED]
    loop = PybulletLoop(urdf, (GROUND, "box"), _box_pose(0.0), qvel, timestep=STEP, base="floating")
    assert "touches at 4 points" in loop.landing(STIFFNESS / 2, 1.0)
    target = 0.6
    ans = solve_damping(loop, target, (STIFFNESS, 1.0))
    loop.close()
    assert ans.status == "ok" and abs(ans.delivered.mean - target) <= 1.2e-4
    k, c = ans.solref

    def place(pb, cl, body, tau):
        z = HALF + SPEED * tau - 0.5 * G * tau * tau
        pb.resetBasePositionAndOrientation(body, [0, 0, z], [0, 0, 0, 1], physicsClientId=cl)
        pb.resetBaseVelocity(body, [0, 0, start_rate(SPEED, tau, STEP)], [0, 0, 0], physicsClientId=cl)

    pair = (("floor", -1), ("robot", -1))
    values = {("floor", -1): (k, c), ("robot", -1): (k, c)}
    mean, stderr = raw_drops(pybullet, urdf, STEP, 256, place, values, pair)
    assert abs(mean - target) <= 2e-3, (mean, stderr)
    # Four points with (k, c) each are not exactly one with (4k, 4c) in PyBullet: a sphere of the
    # cube's mass with four times each link's values lands about 0.013 lower; the loop tunes the
    # box itself.
    ball = tmp_path / "ball.urdf"
    ball.write_text(BOX.replace('<box size="0.1 0.1 0.1"/>', f'<sphere radius="{HALF}"/>'))
    four = {("floor", -1): (4 * k, 4 * c), ("robot", -1): (4 * k, 4 * c)}
    one, _ = raw_drops(pybullet, ball, STEP, 16, place, four, pair)
    assert 5e-3 < target - one < 3e-2, one


@pytest.mark.parametrize("degrees", [5.0])
def test_pybullet_loop_refuses_a_tilted_box(pybullet, tmp_path, degrees):
    """Tilted, the far edge's corners lie 2 HALF sin(tilt) above the near edge's (closed form):
    beyond 0.2 of the maximum compression the landing rocks, and the loop says so."""
    urdf = tmp_path / "box.urdf"
    urdf.write_text(BOX)
    tilt = np.radians(degrees)
    loop = PybulletLoop(urdf, (GROUND, "box"), _box_pose(tilt), [0, 0, 0, 0, 0, -SPEED], timestep=STEP,
                        base="floating")  # fmt: skip
    heights = loop.heights()
    assert heights[-1] - heights[0] == pytest.approx(2 * HALF * np.sin(tilt), rel=1e-6)
    with pytest.raises(ValueError, match="rocking"):
        loop.landing(STIFFNESS / 2, 1.0)
    loop.close()
