"""A URDF robot with a floating base in PyBullet: its state in Drake's coordinates, moved in time.

PyBullet loads a URDF with ``useFixedBase=False`` as a free base link (six degrees of freedom)
and its joints.  The coordinates here are those Drake's reader gives the same file with
``base="floating"`` (``drake_model.BASES``): ``qpos`` = the base link's orientation (quaternion
w, x, y, z) and origin (x, y, z), then the joints; ``qvel`` = its angular velocity and its
origin's velocity (world axes), then the joints' rates.  PyBullet's base state is that of the base
link's centre of mass (its inertial frame): ``base_state`` converts.

``FloatingState`` is one such state as PyBullet holds it; ``shifted`` moves it along a velocity
and an acceleration (second order; the orientation by the rotation vector), as the engine loop
moves a drop's start back by a fraction of a step.

Importing this module does not need PyBullet.
"""

from dataclasses import dataclass

import numpy as np

# The floor a floating robot falls on (a URDF with a free base has no fixed floor of its own):
# a static box, its top at z = 0, PyBullet's default material; the pair names it ``GROUND``.
GROUND = "ground"
GROUND_HALF = (5.0, 5.0, 0.05)
# Base coordinates ahead of the joints in ``qpos`` (quaternion and origin) and ``qvel``.
BASE_Q, BASE_V = 7, 6


@dataclass(frozen=True)
class FloatingState:
    """A floating robot's state as PyBullet holds it.

    The base's centre of mass ``p``, orientation ``quat`` (PyBullet's x, y, z, w), its linear and
    angular velocities ``v`` and ``w`` (world axes), and the joints' positions ``q`` and rates ``qd``.
    """

    p: np.ndarray
    quat: np.ndarray
    v: np.ndarray
    w: np.ndarray
    q: np.ndarray
    qd: np.ndarray


def add_ground(pb, client) -> int:
    """The static floor ``GROUND``: a box body, its top at z = 0."""
    shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(GROUND_HALF), physicsClientId=client)
    return pb.createMultiBody(0.0, shape, -1, [0.0, 0.0, -GROUND_HALF[2]], physicsClientId=client)


def split(qpos, qvel):
    """``(base qpos, joints' qpos, base qvel, joints' qvel)`` of Drake's floating coordinates."""
    q, v = np.asarray(qpos, dtype=float).ravel(), np.asarray(qvel, dtype=float).ravel()
    if q.size < BASE_Q or v.size < BASE_V or q.size - BASE_Q != v.size - BASE_V:
        raise ValueError(
            f"a floating base's qpos has 7 + n values (quaternion w x y z, origin x y z, n joints) and "
            f"its qvel 6 + n (angular, linear, the joints); got {q.size} and {v.size}"
        )
    return q[:BASE_Q], q[BASE_Q:], v[:BASE_V], v[BASE_V:]


def base_state(pb, body, base_q, base_v, joints_q, joints_v, client) -> FloatingState:
    """``FloatingState`` of Drake's base coordinates: the link origin moved to the centre of mass."""
    info = pb.getDynamicsInfo(body, -1, physicsClientId=client)
    local_p, local_orn = info[3], info[4]
    w_, x_, y_, z_ = (float(a) for a in base_q[:4])
    norm = np.sqrt(w_ * w_ + x_ * x_ + y_ * y_ + z_ * z_)
    if not norm > 0.0:
        raise ValueError(f"qpos[0:4] = {list(base_q[:4])}: the base's quaternion must not be zero")
    origin = [float(a) for a in base_q[4:7]]
    orn = [x_ / norm, y_ / norm, z_ / norm, w_ / norm]
    p, quat = pb.multiplyTransforms(origin, orn, local_p, local_orn)
    w = np.asarray(base_v[:3], dtype=float)
    v = np.asarray(base_v[3:6], dtype=float) + np.cross(w, np.asarray(p) - np.asarray(origin))
    return FloatingState(np.asarray(p), np.asarray(quat), v, w, np.asarray(joints_q), np.asarray(joints_v))


def put(pb, body, joints, s: FloatingState, client) -> None:
    """Reset ``body`` (a floating base) to the state ``s``."""
    pb.resetBasePositionAndOrientation(body, list(s.p), list(s.quat), physicsClientId=client)
    pb.resetBaseVelocity(body, list(s.v), list(s.w), physicsClientId=client)
    for j, qj, vj in zip(joints, s.q, s.qd, strict=True):
        pb.resetJointState(body, j, float(qj), float(vj), physicsClientId=client)


def read(pb, body, joints, client) -> FloatingState:
    """``body``'s current state."""
    p, quat = pb.getBasePositionAndOrientation(body, physicsClientId=client)
    v, w = pb.getBaseVelocity(body, physicsClientId=client)
    states = pb.getJointStates(body, joints, physicsClientId=client) if joints else []
    return FloatingState(np.asarray(p), np.asarray(quat), np.asarray(v), np.asarray(w),
                         np.array([s[0] for s in states]), np.array([s[1] for s in states]))  # fmt: skip


@dataclass(frozen=True)
class Rates:
    """The rates of a ``FloatingState``: linear, angular and joint (velocities or accelerations)."""

    v: np.ndarray
    w: np.ndarray
    qd: np.ndarray


def velocity(s: FloatingState) -> Rates:
    """The state's velocities."""
    return Rates(s.v, s.w, s.qd)


def _rotated(quat, rotvec):
    """``quat`` (x, y, z, w) turned by the world rotation vector ``rotvec``."""
    angle = float(np.linalg.norm(rotvec))
    if angle == 0.0:
        return np.asarray(quat)
    axis = np.asarray(rotvec) / angle
    r = np.array([*(np.sin(angle / 2) * axis), np.cos(angle / 2)])
    x1, y1, z1, w1 = r
    x2, y2, z2, w2 = quat
    return np.array([
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2, w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2, w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
    ])  # fmt: skip


def shifted(s: FloatingState, acc: Rates, dt: float, dv: float) -> FloatingState:
    """``s`` moved by ``dt`` along its velocity and ``acc`` (second order); velocities moved by ``dv``."""

    def move(x, xd, xdd):
        return np.asarray(x) + dt * np.asarray(xd) + 0.5 * dt * dt * np.asarray(xdd)

    return FloatingState(
        move(s.p, s.v, acc.v), _rotated(s.quat, dt * s.w + 0.5 * dt * dt * acc.w), s.v + dv * acc.v,
        s.w + dv * acc.w, move(s.q, s.qd, acc.qd), s.qd + dv * acc.qd,
    )  # fmt: skip


def box_corner_heights(pb, body, link, client) -> list[float]:
    """The world heights (z, m; the floor's top is 0) of the corners of ``link``'s box shapes."""
    if link < 0:
        frame = pb.getBasePositionAndOrientation(body, physicsClientId=client)
    else:
        frame = pb.getLinkState(body, link, computeForwardKinematics=1, physicsClientId=client)[:2]
    out = []
    for shape in pb.getCollisionShapeData(body, link, physicsClientId=client):
        if shape[2] != pb.GEOM_BOX:
            continue
        half = 0.5 * np.asarray(shape[3])
        pos, orn = pb.multiplyTransforms(frame[0], frame[1], shape[5], shape[6])
        R = np.array(pb.getMatrixFromQuaternion(orn)).reshape(3, 3)
        for sx in (-1, 1):
            for sy in (-1, 1):
                for sz in (-1, 1):
                    out.append(float((np.asarray(pos) + R @ (half * [sx, sy, sz]))[2]))
    return out
