"""Issue 43's box in Drake's engine loop: a flat box on its corners, a tilted one, a box on a box.

Drake's point contact gives a pair of geometries one point, its deepest: a box's four corners
are four small spheres, and the pair names the box's body.  The loop's answer is measured in raw
Drake (a plant built here from the SDF with the answer written in, the box let fall from a random
height, the gap read from the box's pose in closed form), not on the loop's phases.
"""

import math

import numpy as np
import pytest
from raw_reading import G, done, flight_e, start_rate

from contactalpha.mechanism.drake_loop import DrakeLoop
from contactalpha.mechanism.engine_loop import solve_damping

HALF = 0.05  # the cube's half edge
R = 0.005  # the corner spheres' radius
STEP = 1e-3
SPEED = 1.0
CORNERS = ((-1, -1), (-1, 1), (1, -1), (1, 1))
MATERIAL = """<drake:proximity_properties><drake:point_contact_stiffness>{k!r}</drake:point_contact_stiffness>
      <drake:hunt_crossley_dissipation>{d!r}</drake:hunt_crossley_dissipation></drake:proximity_properties>"""


def _sdf(k=1e4, d=0.0, shape="corners"):
    """The cube (1 kg) over a welded floor box (its top at z = 0), each geometry with ``k`` and ``d``."""
    m = MATERIAL.format(k=k, d=d)
    if shape == "corners":
        cols = "".join(
            f'<collision name="c{i}"><pose>{sx * HALF} {sy * HALF} {R - HALF} 0 0 0</pose>'
            f"<geometry><sphere><radius>{R}</radius></sphere></geometry>{m}</collision>"
            for i, (sx, sy) in enumerate(CORNERS)
        )
    elif shape == "box":
        cols = (
            f'<collision name="cube"><geometry><box><size>0.1 0.1 0.1</size></box></geometry>{m}</collision>'
        )
    else:  # one sphere, its bottom where the corners' are
        cols = (f'<collision name="ball"><pose>0 0 {R - HALF} 0 0 0</pose>'
                f"<geometry><sphere><radius>{R}</radius></sphere></geometry>{m}</collision>")  # fmt: skip
    return f"""<?xml version="1.0"?>
<sdf version="1.7" xmlns:drake="http://drake.mit.edu"><model name="m">
  <link name="floor"><collision name="floor"><pose>0 0 -0.1 0 0 0</pose>
    <geometry><box><size>2 2 0.2</size></box></geometry>{m}</collision></link>
  <joint name="weld" type="fixed"><parent>world</parent><child>floor</child></joint>
  <link name="box"><inertial><mass>1</mass><inertia><ixx>0.00166667</ixx><iyy>0.00166667</iyy>
    <izz>0.00166667</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>{cols}</link>
</model></sdf>"""


def _pose(tilt):
    """Drake's qpos of the cube tilted by ``tilt`` about x, its lowest corners on the floor."""
    z = HALF * (math.cos(tilt) + math.sin(tilt))
    return [math.cos(tilt / 2), math.sin(tilt / 2), 0, 0, 0, 0, z]


def _raw(path, n, seed=13, points=CORNERS):
    """Raw Drake: the cube let fall flat from 3 to 4 steps above touchdown (the phases an even grid
    shifted by one uniform draw, none of them the loop's midpoints); e_N from the lowest
    point's height (the box's pose, closed form), read in free flight (``raw_reading``)."""
    import pydrake.all as dk

    builder = dk.DiagramBuilder()
    plant, _ = dk.AddMultibodyPlantSceneGraph(builder, STEP)
    plant.set_contact_model(dk.ContactModel.kPoint)
    plant.set_discrete_contact_approximation(dk.DiscreteContactApproximation.kLagged)
    dk.Parser(plant).AddModels(str(path))
    plant.Finalize()
    diagram = builder.Build()
    box = plant.GetBodyByName("box")
    local = np.array([[sx * HALF, sy * HALF, -HALF] for sx, sy in points])  # the points' bottoms
    shift = np.random.default_rng(seed).random()
    out = []
    for i in range(n):
        sim = dk.Simulator(diagram)
        ctx = plant.GetMyMutableContextFromRoot(sim.get_mutable_context())
        tau = (3.0 + (i + shift) / n) * STEP
        z = HALF + SPEED * tau - 0.5 * G * tau * tau
        plant.SetFreeBodyPose(ctx, box, dk.RigidTransform([0, 0, z]))
        velocity = dk.SpatialVelocity(np.zeros(3), [0, 0, start_rate(SPEED, tau, STEP)])
        plant.SetFreeBodySpatialVelocity(ctx, box, velocity)
        sim.Initialize()
        gaps = []
        for j in range(1, 3000):
            X = plant.EvalBodyPoseInWorld(ctx, box)
            gaps.append(float(min((X.rotation().matrix() @ p + X.translation())[2] for p in local)))
            if done(gaps):
                break
            sim.AdvanceTo(j * STEP)
        out.append(flight_e(gaps, STEP))
    return float(np.mean(out)), float(np.std(out, ddof=1) / math.sqrt(n))


def test_drake_loop_delivers_the_flat_box(pydrake, tmp_path):
    """Flat on its four corner spheres: one contact mode; each corner's pair has k/2 and d, so the
    landing's stiffness is the corners' sum and d is each corner's: one sphere with four times
    each geometry's stiffness and the same d lands the same."""
    src = tmp_path / "box.sdf"
    src.write_text(_sdf())
    loop = DrakeLoop(src, ("floor", "box"), _pose(0.0), [0, 0, 0, 0, 0, -SPEED], timestep=STEP)
    assert "touches at 4 points" in loop.landing(5e3, 1.0)
    target = 0.6
    ans = solve_damping(loop, target, (1e4, 1.0))
    assert ans.status == "ok" and abs(ans.delivered.mean - target) <= 1.2e-4
    k, d = ans.solref
    tuned = tmp_path / "tuned.sdf"
    tuned.write_text(_sdf(k, d))
    mean, stderr = _raw(tuned, 256)
    assert abs(mean - target) <= 2e-3, (mean, stderr)
    ball = tmp_path / "ball.sdf"
    ball.write_text(_sdf(4 * k, d, shape="ball"))
    one, one_err = _raw(ball, 32, points=((0, 0),))
    assert abs(one - target) <= 2e-3, (one, one_err)


def test_drake_loop_refuses_a_box_on_a_box(pydrake, tmp_path):
    """A box geometry on the floor box: Drake's point contact has one point for the pair."""
    src = tmp_path / "box.sdf"
    src.write_text(_sdf(shape="box"))
    loop = DrakeLoop(src, ("floor", "cube"), _pose(0.0), [0, 0, 0, 0, 0, -SPEED], timestep=STEP)
    with pytest.raises(ValueError, match="one contact point, its deepest"):
        loop.landing(5e3, 1.0)


def test_drake_loop_refuses_the_tilted_box(pydrake, tmp_path):
    """Tilted by 5°, the far corners lie 2 HALF sin(tilt) (less the spheres' turn) above the near
    ones: beyond 0.2 of the maximum compression, refused as rocking."""
    src = tmp_path / "box.sdf"
    src.write_text(_sdf())
    tilt = math.radians(5.0)
    loop = DrakeLoop(src, ("floor", "box"), _pose(tilt), [0, 0, 0, 0, 0, -SPEED], timestep=STEP)
    heights = loop.heights()
    # A sphere's lowest point is its centre less R: the centres sit R up the box's own z axis.
    spread = 2 * HALF * math.sin(tilt) - 0.0  # both edges' spheres turn alike: no R term in the spread
    assert heights[-1] - heights[0] == pytest.approx(spread, rel=5e-3)
    with pytest.raises(ValueError, match="rocking"):
        loop.landing(5e3, 1.0)
