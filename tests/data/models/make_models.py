# ruff: noqa: E501  (model text: one XML element a line)
"""Write the four mechanism test models, in MJCF (MuJoCo) and SDF (Drake), at first touch.

The leg also in URDF, which both MuJoCo and Drake read.

Run from the repository root: ``python tests/data/models/make_models.py``.  The numbers here are
the ones ``tests/mechanism/hand.py`` derives its values from; each model's default configuration
(``qpos0``, the SDF's poses) puts its pair exactly at first touch.
"""

import math
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
G = 9.81

# Pendulum: hinge at height 1 on y; arm mass, COM at the tip, inertia about the COM; tip sphere r.
PEND = dict(L=0.5, m=0.5, Iyy=0.002, r=0.05)
# Capsule: free body, axis tilted by beta about y; radius, half length, mass, inertia (I1, I1, I3).
CAPS = dict(r=0.03, hl=0.1, m=1.0, I1=0.01, I3=0.002, beta=0.4)
# Leg: hip on a vertical slider; thigh and shank (COM at mid-length), foot sphere at the shank's end.
LEG = dict(M0=2.0, I0=0.01, l1=0.4, m1=1.0, I1=0.015, l2=0.4, m2=0.8, I2=0.01, r=0.03, q1=0.5, q2=-0.9)
# Box: free body, half sizes, mass, principal inertia, roll-pitch-yaw (fixed axes X, Y, Z).
BOX = dict(half=(0.05, 0.08, 0.03), m=0.7, inertia=(0.0018, 0.0008, 0.002), rpy=(0.3, -0.2, 0.5))


def rpy_matrix(r, p, y):
    """R = Rz(y) Ry(p) Rx(r): SDF's pose convention."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def quat(R):
    """(w, x, y, z) of a rotation matrix."""
    w = math.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2.0
    return (w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w))


def box_corners(half):
    return np.array(
        [[sx * half[0], sy * half[1], sz * half[2]] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    )


def box_height():
    R = rpy_matrix(*BOX["rpy"])
    return -min((R @ c)[2] for c in box_corners(BOX["half"]))


def leg_height():
    p = LEG
    return p["l1"] * math.cos(p["q1"]) + p["l2"] * math.cos(p["q1"] + p["q2"]) + p["r"]


def f(x):
    return repr(float(x))


def v(*xs):
    return " ".join(f(x) for x in xs)


OPTION = '<compiler angle="radian"/>\n  <option timestep="1e-05" gravity="0 0 -9.81" integrator="Euler"/>'


def mjcf():
    p = PEND
    yield (
        "pendulum",
        f"""<mujoco model="pendulum_wall">
  {OPTION}
  <worldbody>
    <geom name="wall" type="plane" size="1 1 0.1" pos="{v(-p["r"], 0, 1 - p["L"])}" zaxis="1 0 0" condim="1"/>
    <body name="arm" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <inertial pos="{v(0, 0, -p["L"])}" mass="{f(p["m"])}" diaginertia="{v(p["Iyy"], p["Iyy"], p["Iyy"])}"/>
      <geom name="tip" type="sphere" size="{f(p["r"])}" pos="{v(0, 0, -p["L"])}" condim="1"/>
    </body>
  </worldbody>
</mujoco>
""",
    )
    c = CAPS
    z0 = c["hl"] * math.cos(c["beta"]) + c["r"]
    q = quat(rpy_matrix(0.0, c["beta"], 0.0))
    yield (
        "capsule",
        f"""<mujoco model="capsule_end">
  {OPTION}
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" condim="1"/>
    <body name="capsule" pos="{v(0, 0, z0)}" quat="{v(*q)}">
      <freejoint name="free"/>
      <inertial pos="0 0 0" mass="{f(c["m"])}" diaginertia="{v(c["I1"], c["I1"], c["I3"])}"/>
      <geom name="capsule" type="capsule" size="{v(c["r"], c["hl"])}" condim="1"/>
    </body>
  </worldbody>
</mujoco>
""",
    )
    g = LEG
    yield (
        "leg",
        f"""<mujoco model="two_link_leg">
  {OPTION}
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" condim="1"/>
    <body name="hip" pos="{v(0, 0, leg_height())}">
      <joint name="slide" type="slide" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="{f(g["M0"])}" diaginertia="{v(g["I0"], g["I0"], g["I0"])}"/>
      <body name="thigh" euler="{v(0, g["q1"], 0)}">
        <joint name="hip" type="hinge" axis="0 1 0" ref="0"/>
        <inertial pos="{v(0, 0, -g["l1"] / 2)}" mass="{f(g["m1"])}" diaginertia="{v(g["I1"], g["I1"], g["I1"])}"/>
        <body name="shank" pos="{v(0, 0, -g["l1"])}" euler="{v(0, g["q2"], 0)}">
          <joint name="knee" type="hinge" axis="0 1 0"/>
          <inertial pos="{v(0, 0, -g["l2"] / 2)}" mass="{f(g["m2"])}" diaginertia="{v(g["I2"], g["I2"], g["I2"])}"/>
          <geom name="foot" type="sphere" size="{f(g["r"])}" pos="{v(0, 0, -g["l2"])}" condim="1"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
""",
    )
    b = BOX
    q = quat(rpy_matrix(*b["rpy"]))
    yield (
        "box",
        f"""<mujoco model="box_corner">
  {OPTION}
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" condim="1"/>
    <body name="box" pos="{v(0, 0, box_height())}" quat="{v(*q)}">
      <freejoint name="free"/>
      <inertial pos="0 0 0" mass="{f(b["m"])}" diaginertia="{v(*b["inertia"])}"/>
      <geom name="box" type="box" size="{v(*b["half"])}" condim="1"/>
    </body>
  </worldbody>
</mujoco>
""",
    )


def _inertial(m, ixx, iyy, izz, pose="0 0 0 0 0 0"):
    return (
        f"<inertial><pose>{pose}</pose><mass>{f(m)}</mass><inertia><ixx>{f(ixx)}</ixx><iyy>{f(iyy)}</iyy>"
        f"<izz>{f(izz)}</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>"
    )


def _sdf(name, ground, body):
    return f"""<?xml version="1.0"?>
<sdf version="1.9" xmlns:drake="http://drake.mit.edu">
  <model name="{name}">
    <link name="ground">
      {ground}
    </link>
    <joint name="ground_weld" type="fixed"><parent>world</parent><child>ground</child></joint>
{body}
  </model>
</sdf>
"""


# No friction, as condim 1 in the MJCF files: the normal law alone.
FRICTIONLESS = (
    "<drake:proximity_properties><drake:mu_dynamic>0</drake:mu_dynamic>"
    "<drake:mu_static>0</drake:mu_static></drake:proximity_properties>"
)
FLOOR = (
    '<collision name="floor"><pose>0 0 -0.5 0 0 0</pose>'
    f"<geometry><box><size>4 4 1</size></box></geometry>{FRICTIONLESS}</collision>"
)


def sdf():
    """The four models in SDF; a joint's parent carries no collision geometry (Drake filters
    collisions between bodies a joint connects)."""
    p = PEND
    wall = (
        f'<collision name="wall"><pose>{v(-p["r"] - 0.5, 0, 1 - p["L"], 0, 0, 0)}</pose>'
        f"<geometry><box><size>1 4 4</size></box></geometry>{FRICTIONLESS}</collision>"
    )
    yield (
        "pendulum",
        _sdf(
            "pendulum_wall",
            wall,
            f"""    <link name="arm">
      <pose>0 0 1 0 0 0</pose>
      {_inertial(p["m"], p["Iyy"], p["Iyy"], p["Iyy"], v(0, 0, -p["L"], 0, 0, 0))}
      <collision name="tip"><pose>{v(0, 0, -p["L"], 0, 0, 0)}</pose>
        <geometry><sphere><radius>{f(p["r"])}</radius></sphere></geometry>{FRICTIONLESS}</collision>
    </link>
    <link name="pivot"><pose>0 0 1 0 0 0</pose>{_inertial(1.0, 1e-3, 1e-3, 1e-3)}</link>
    <joint name="pivot_weld" type="fixed"><parent>world</parent><child>pivot</child></joint>
    <joint name="hinge" type="revolute"><parent>pivot</parent><child>arm</child>
      <axis><xyz>0 1 0</xyz><limit><lower>-1e10</lower><upper>1e10</upper></limit></axis></joint>""",
        ),
    )
    c = CAPS
    z0 = c["hl"] * math.cos(c["beta"]) + c["r"]
    yield (
        "capsule",
        _sdf(
            "capsule_end",
            FLOOR,
            f"""    <link name="capsule">
      <pose>{v(0, 0, z0, 0, c["beta"], 0)}</pose>
      {_inertial(c["m"], c["I1"], c["I1"], c["I3"])}
      <collision name="capsule">
        <geometry><capsule><radius>{f(c["r"])}</radius><length>{f(2 * c["hl"])}</length></capsule></geometry>
        {FRICTIONLESS}</collision>
    </link>""",
        ),
    )
    g = LEG
    h = leg_height()
    yield (
        "leg",
        _sdf(
            "two_link_leg",
            FLOOR,
            f"""    <link name="hip">
      <pose>{v(0, 0, h, 0, 0, 0)}</pose>
      {_inertial(g["M0"], g["I0"], g["I0"], g["I0"])}
    </link>
    <joint name="slide" type="prismatic"><parent>ground</parent><child>hip</child>
      <axis><xyz>0 0 1</xyz><limit><lower>-1e10</lower><upper>1e10</upper></limit></axis></joint>
    <link name="thigh">
      <pose>{v(0, 0, h, 0, g["q1"], 0)}</pose>
      {_inertial(g["m1"], g["I1"], g["I1"], g["I1"], v(0, 0, -g["l1"] / 2, 0, 0, 0))}
    </link>
    <joint name="hip_joint" type="revolute"><parent>hip</parent><child>thigh</child>
      <axis><xyz>0 1 0</xyz><limit><lower>-1e10</lower><upper>1e10</upper></limit></axis></joint>
    <link name="shank">
      <pose>{v(-g["l1"] * math.sin(g["q1"]), 0, h - g["l1"] * math.cos(g["q1"]), 0, g["q1"] + g["q2"], 0)}</pose>
      {_inertial(g["m2"], g["I2"], g["I2"], g["I2"], v(0, 0, -g["l2"] / 2, 0, 0, 0))}
      <collision name="foot"><pose>{v(0, 0, -g["l2"], 0, 0, 0)}</pose>
        <geometry><sphere><radius>{f(g["r"])}</radius></sphere></geometry>{FRICTIONLESS}</collision>
    </link>
    <joint name="knee" type="revolute"><parent>thigh</parent><child>shank</child>
      <axis><xyz>0 1 0</xyz><limit><lower>-1e10</lower><upper>1e10</upper></limit></axis></joint>""",
        ),
    )
    b = BOX
    yield (
        "box",
        _sdf(
            "box_corner",
            FLOOR,
            f"""    <link name="box">
      <pose>{v(0, 0, box_height(), *b["rpy"])}</pose>
      {_inertial(b["m"], *b["inertia"])}
      <collision name="box"><geometry><box><size>{v(*(2 * x for x in b["half"]))}</size></box></geometry>{FRICTIONLESS}</collision>
    </link>""",
        ),
    )


def _urdf_inertial(m, inertia, z):
    return (
        f'<inertial><origin xyz="0 0 {f(z)}"/><mass value="{f(m)}"/><inertia ixx="{f(inertia)}" '
        f'iyy="{f(inertia)}" izz="{f(inertia)}" ixy="0" ixz="0" iyz="0"/></inertial>'
    )


def urdf():
    """The leg in URDF (MuJoCo and Drake both read it): a floor box on a link welded to the world."""
    g = LEG
    yield (
        "leg",
        f"""<?xml version="1.0"?>
<robot name="two_link_leg">
  <link name="world"/>
  <link name="ground">
    <collision name="floor"><origin xyz="0 0 -0.5"/><geometry><box size="4 4 1"/></geometry></collision>
  </link>
  <joint name="ground_weld" type="fixed"><parent link="world"/><child link="ground"/></joint>
  <link name="hip">{_urdf_inertial(g["M0"], g["I0"], 0.0)}</link>
  <joint name="slide" type="prismatic"><parent link="world"/><child link="hip"/>
    <origin xyz="0 0 {f(leg_height())}"/><axis xyz="0 0 1"/><limit lower="-10" upper="10" effort="0" velocity="100"/></joint>
  <link name="thigh">{_urdf_inertial(g["m1"], g["I1"], -g["l1"] / 2)}</link>
  <joint name="hip_joint" type="continuous"><parent link="hip"/><child link="thigh"/>
    <origin rpy="0 {f(g["q1"])} 0"/><axis xyz="0 1 0"/></joint>
  <link name="shank">{_urdf_inertial(g["m2"], g["I2"], -g["l2"] / 2)}
    <collision name="foot"><origin xyz="0 0 {f(-g["l2"])}"/><geometry><sphere radius="{f(g["r"])}"/></geometry></collision>
  </link>
  <joint name="knee" type="continuous"><parent link="thigh"/><child link="shank"/>
    <origin xyz="0 0 {f(-g["l1"])}" rpy="0 {f(g["q2"])} 0"/><axis xyz="0 1 0"/></joint>
</robot>
""",
    )


if __name__ == "__main__":
    for name, text in mjcf():
        (HERE / f"{name}.xml").write_text(text)
    for name, text in sdf():
        (HERE / f"{name}.sdf").write_text(text)
    for name, text in urdf():
        (HERE / f"{name}.urdf").write_text(text)
