"""Scenes of issue 43 as URDF files for PyBullet's floating base, and raw PyBullet drops of them.

The raw drops are written here on PyBullet alone: the robot let fall freely from a few steps
above touchdown (its touchdown at a random point of a step), e_N read off the pair's gap in free
flight (``raw_reading``).
"""

import math

import numpy as np
from raw_reading import G, done, flight_e

# A 1 kg sphere (the floating base) and a 0.5 kg sphere above it on a vertical slide: the head-on
# stack of two free spheres (by symmetry neither turns nor moves sideways).  The upper sphere
# hangs from a carrier link (half its mass, no collision) so that the two spheres are not parent
# and child, which PyBullet's self-collision skips.
STACK = """<robot name="stack">
  <link name="low">
    <inertial><mass value="1.0"/>
      <inertia ixx="0.004" iyy="0.004" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision name="low"><geometry><sphere radius="0.1"/></geometry></collision>
  </link>
  <link name="carrier">
    <inertial><mass value="0.25"/>
      <inertia ixx="0.00025" iyy="0.00025" izz="0.00025" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="top">
    <inertial><mass value="0.25"/>
      <inertia ixx="0.00025" iyy="0.00025" izz="0.00025" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision name="top"><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
  <joint name="slide" type="prismatic"><parent link="low"/><child link="carrier"/><origin xyz="0 0 0.15"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="0" velocity="100"/></joint>
  <joint name="carry" type="fixed"><parent link="carrier"/><child link="top"/></joint>
</robot>
"""
# A free 0.1 m cube of 1 kg.
BOX = """<robot name="box">
  <link name="box">
    <inertial><mass value="1.0"/>
      <inertia ixx="0.00166667" iyy="0.00166667" izz="0.00166667" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision name="box"><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
</robot>
"""


def world(pb, urdf, h):
    """``(client, robot, floor)``: the URDF floating over a static box floor (its top at z = 0)."""
    c = pb.connect(pb.DIRECT)
    pb.setGravity(0, 0, -G, physicsClientId=c)
    pb.setTimeStep(h, physicsClientId=c)
    flags = pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_INERTIA_FROM_FILE
    body = pb.loadURDF(str(urdf), [0, 0, 1.0], useFixedBase=False, flags=flags, physicsClientId=c)
    shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[2, 2, 0.1], physicsClientId=c)
    floor = pb.createMultiBody(0, shape, -1, [0, 0, -0.1], physicsClientId=c)
    for j in range(pb.getNumJoints(body, physicsClientId=c)):
        pb.setJointMotorControl2(body, j, pb.VELOCITY_CONTROL, force=0.0, physicsClientId=c)
    return c, body, floor


def resting_height(pb, urdf, h):
    """The lower sphere's height at rest on the floor (PyBullet's own contact), the upper held up."""
    c, body, _ = world(pb, urdf, h)
    pb.resetBasePositionAndOrientation(body, [0, 0, 0.1], [0, 0, 0, 1], physicsClientId=c)
    for _ in range(int(2.0 / h)):
        pb.resetJointState(body, 0, 0.5, 0.0, physicsClientId=c)
        pb.stepSimulation(physicsClientId=c)
    z = pb.getBasePositionAndOrientation(body, physicsClientId=c)[0][2]
    speed = np.linalg.norm(pb.getBaseVelocity(body, physicsClientId=c)[0])
    pb.disconnect(c)
    assert speed < 1e-9
    return z


def raw_drops(pb, urdf, h, n, place, values, pair, seed=11, steps=4000):
    """e_N of ``n`` raw drops: ``place(pb, client, body, tau)`` sets the state ``tau`` before touchdown.

    ``values``: {(body or "floor", link): (contactStiffness, contactDamping)}; ``pair``: ((who, link),
    (who, link)) with who "robot" or "floor".  tau is 3 to 4 steps: the touchdown phases an even
    grid shifted by one uniform draw (none of them the loop's midpoints).
    """
    shift = np.random.default_rng(seed).random()
    out = []
    for i in range(n):
        c, body, floor = world(pb, urdf, h)
        ids = {"robot": body, "floor": floor}
        for (who, link), (k, d) in values.items():
            pb.changeDynamics(ids[who], link, contactStiffness=k, contactDamping=d, physicsClientId=c)
        place(pb, c, body, (3.0 + (i + shift) / n) * h)
        (a, la), (b, lb) = pair
        gaps = []
        for _ in range(steps):
            pts = pb.getClosestPoints(ids[a], ids[b], 1.0, la, lb, physicsClientId=c)
            gaps.append(min(p[8] for p in pts))
            if done(gaps):
                break
            pb.stepSimulation(physicsClientId=c)
        pb.disconnect(c)
        out.append(flight_e(gaps, h))
    out = np.array(out)
    return float(out.mean()), float(out.std(ddof=1) / math.sqrt(n))
