"""A pair landing on several points (``touch.landing_check``): one contact mode, or refused.

A free 0.1 m cube of 1 kg over MuJoCo's floor: flat, its four bottom corners touch at once (one
contact mode); tilted about x by a few degrees, two corners lie L sin(tilt) above the other two
(the closed form the test checks the reader's heights against), within a few maximum compressions:
the landing rocks and ``tune`` refuses it with the reason.
"""

import math

import pytest

from contactalpha.mechanism import read_contact, tune
from contactalpha.mechanism.touch import LANDING_SPREAD, landing_check, max_compression

HALF = 0.05
BOX = """<mujoco><option timestep="0.0005"/>
  <worldbody><geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="cube"><freejoint/><geom name="cube" type="box" size="{h} {h} {h}" mass="1"/></body>
  </worldbody></mujoco>"""
STIFFNESS = 1e4


def _pose(tilt):
    """qpos of the cube tilted by ``tilt`` about x with its lowest edge at z = 0."""
    z = HALF * (math.cos(tilt) + math.sin(tilt))
    return [0.0, 0.0, z, math.cos(tilt / 2), math.sin(tilt / 2), 0.0, 0.0]


@pytest.fixture
def cube(tmp_path):
    path = tmp_path / "cube.xml"
    path.write_text(BOX.format(h=HALF))
    return path


def test_a_flat_box_is_one_contact_mode(cube, mujoco):
    c = read_contact(cube, ("floor", "cube"), reader="mujoco", qpos=_pose(0.0), speed=1.0)
    assert c.engine_row["pair_heights"] == pytest.approx([0.0] * 4, abs=1e-12)
    assert "touches at 4 points" in landing_check(c, STIFFNESS)


@pytest.mark.parametrize("degrees", [2.0, 5.0])
def test_a_tilted_box_that_would_rock_is_refused(cube, mujoco, degrees):
    tilt = math.radians(degrees)
    c = read_contact(cube, ("floor", "cube"), reader="mujoco", qpos=_pose(tilt), speed=1.0)
    spread = 2 * HALF * math.sin(tilt)  # the far edge's corners above the near edge's
    assert c.engine_row["pair_heights"][-1] == pytest.approx(spread, rel=1e-9)
    assert spread > LANDING_SPREAD * max_compression(c, STIFFNESS)
    with pytest.raises(ValueError, match="rocking"):
        tune(cube, ("floor", "cube"), 0.6, qpos=_pose(tilt), speed=1.0, engine="mujoco", stiffness=STIFFNESS)
