"""MuJoCo's pyramidal cone: the normal force's equivalent row of the 2 (condim - 1) edges.

A free sphere dropped straight onto a plane (no tangential motion, tangent rows decoupled from
the normal): with the edges' R divided by their number (``mujoco_model.normal_rows``) the tuned
contact delivers what a frictionless one does.  Before, the edge's own diagA was taken for the
normal's and the sphere delivered 0.563 (mu 1) and 0.593 (mu 0.5) for a target of 0.6.
"""

import math

import pytest

from contactalpha.mechanism.tune import tune

XML = """<mujoco><option cone="{cone}" impratio="{impratio}" timestep="{h}" integrator="Euler"/>
<worldbody><geom name="floor" type="plane" size="1 1 0.1" condim="{condim}" friction="{mu} 0.005 0.0001"/>
<body name="ball" pos="0 0 0.05"><freejoint/>
<inertial pos="0 0 0" mass="0.5" diaginertia="0.0005 0.0005 0.0005"/>
<geom name="b" type="sphere" size="0.05" condim="{condim}" friction="{mu} 0.005 0.0001"/></body>
</worldbody></mujoco>"""
OMEGA = 1e4  # 1/s: k = m omega^2, 2000 steps per undamped contact


@pytest.mark.parametrize(
    ("cone", "condim", "mu", "impratio", "rows"),
    [("pyramidal", 3, 1.0, 1.0, 4), ("pyramidal", 3, 0.5, 1.0, 4), ("pyramidal", 3, 0.3, 2.0, 4),
     ("pyramidal", 4, 0.5, 1.0, 6), ("elliptic", 3, 0.5, 1.0, 1), ("pyramidal", 1, 1.0, 1.0, 1)],
)  # fmt: skip
def test_free_sphere_delivers_the_target_in_any_cone(mujoco, tmp_path, cone, condim, mu, impratio, rows):
    h = math.pi / OMEGA / 2000
    model = tmp_path / "ball.xml"
    model.write_text(XML.format(cone=cone, impratio=impratio, condim=condim, mu=mu, h=h))
    got = tune(model, ("floor", "b"), 0.6, qvel=(0, 0, -0.8, 0, 0, 0), stiffness=0.5 * OMEGA**2, check=True,
               discrete=False, output=tmp_path / "t.xml")  # fmt: skip
    row = got.contact.engine_row
    assert row["rows"] == rows
    # the edge's diagA is tran (1 + mu^2) rescaled to R's common value 2 mu^2 / impratio R_edge
    # (mj_makeImpedance), over the number of edges; tran = 1/m for a free sphere
    expect = 2.0 * mu**2 / impratio * (1 + mu**2) * 2.0 / rows if rows > 1 else 2.0
    assert row["diagA"] == pytest.approx(expect, rel=1e-12)
    assert got.delivered == pytest.approx(0.6, abs=3e-4)  # frictionless: 0.60013 at this step
