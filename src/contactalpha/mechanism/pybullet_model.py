"""A URDF mechanism dropped in PyBullet with tuned contact parameters: the engine's own e_N.

``pybullet_drop`` loads the URDF as PyBullet users do (``loadURDF`` with a fixed base; the inertias
of the file, ``URDF_USE_INERTIA_FROM_FILE``, since PyBullet otherwise recomputes them from the
collision shapes; self-collision on, so that two links of one model can touch), gives both links
of the pair their ``contactStiffness`` and ``contactDamping`` (``changeDynamics``, as the script
``tune`` writes does), sets the touchdown state and steps until the pair separates.  The gap is
``getClosestPoints``' signed distance at every step's start; the rebound speed is read from it as
for the other engines (``crossing.rebound_speed``).

PyBullet's links carry a velocity damping (``linearDamping`` and ``angularDamping``, 0.04 by
default) that the contact laws leave out: the drop sets both to 0 unless ``link_damping`` is kept.
Fixed-base models with one-degree-of-freedom joints only; constant forces at links' centres of
mass (``forces``) are applied before every step.

Importing this module does not need PyBullet.
"""

import math
import runpy
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from contactalpha.adapters.pybullet_kv import LOADER

from .contact import MechanismDrop
from .crossing import rebound_speed

# Joint types PyBullet reports for one-degree-of-freedom joints (JOINT_REVOLUTE, JOINT_PRISMATIC).
MOVABLE = (0, 1)


# The engine's one import guard and install hint (its record's loader).
pybullet_module = LOADER.load


def collision_links(urdf: str | Path, pair: Sequence[str]) -> tuple[str | None, ...]:
    """The URDF link names that carry the ``<collision name=...>`` geometries of ``pair``."""
    root = ET.parse(urdf).getroot()
    links = []
    for name in pair:
        owners = [link.get("name") for link in root.iter("link")
                  for col in link.findall("collision") if col.get("name") == name]  # fmt: skip
        if len(owners) != 1:
            raise ValueError(f"geometry {name!r}: {len(owners)} URDF links carry a <collision> of that name")
        links.append(owners[0])
    return tuple(links)


def link_indices(body: int, names: Sequence[str | None], client: int) -> tuple[int, ...]:
    """PyBullet's link index of each link name of ``body`` (-1 for the base)."""
    pb = pybullet_module()
    index = {pb.getBodyInfo(body, physicsClientId=client)[0].decode(): -1}
    for j in range(pb.getNumJoints(body, physicsClientId=client)):
        index[pb.getJointInfo(body, j, physicsClientId=client)[12].decode()] = j
    missing = [n for n in names if n not in index]
    if missing:
        raise ValueError(f"links {missing} are not in the PyBullet model (its links: {sorted(index)})")
    return tuple(index[n] for n in names)


def movable_joints(body: int, client: int) -> tuple[list[int], list[str]]:
    """``(indices, names)`` of ``body``'s joints with one degree of freedom, in PyBullet's order."""
    pb = pybullet_module()
    idx, names = [], []
    for j in range(pb.getNumJoints(body, physicsClientId=client)):
        info = pb.getJointInfo(body, j, physicsClientId=client)
        if info[2] in MOVABLE:
            idx.append(j)
            names.append(info[1].decode())
        elif info[2] != pb.JOINT_FIXED:
            raise ValueError(f"joint {info[1].decode()!r}: PyBullet drops here take 1-dof joints only")
    return idx, names


def set_joint_state(pb, body, joints, q, v, client):
    """Reset the ``joints`` of ``body`` to positions ``q`` and velocities ``v``."""
    for j, qj, vj in zip(joints, q, v, strict=True):
        pb.resetJointState(body, j, float(qj), float(vj), physicsClientId=client)


def pair_gap(pb, body, links, client):
    """The signed distance between the two ``links`` of ``body`` (inf beyond 1 m)."""
    pts = pb.getClosestPoints(body, body, 1.0, links[0], links[1], physicsClientId=client)
    return min(p[8] for p in pts) if pts else math.inf


def _point_jacobian(pb, body, link, point, q, client):
    """(3, n) translational Jacobian of the world ``point`` fixed to ``link`` (zero for the base)."""
    if link < 0:
        return np.zeros((3, len(q)))
    state = pb.getLinkState(body, link, computeForwardKinematics=1, physicsClientId=client)
    R = np.array(pb.getMatrixFromQuaternion(state[5])).reshape(3, 3)
    local = R.T @ (np.asarray(point) - np.asarray(state[4]))  # in the link's frame
    zero = [0.0] * len(q)
    lin, _ = pb.calculateJacobian(body, link, list(local), list(q), zero, zero, physicsClientId=client)
    return np.array(lin)


def inverse_mass(pb, body, links, joints, client):
    """``J M^-1 J^T`` of the gap row at the current state (PyBullet's mass matrix and Jacobians)."""
    q = [s[0] for s in pb.getJointStates(body, joints, physicsClientId=client)]
    pt = pb.getClosestPoints(body, body, 1.0, links[0], links[1], physicsClientId=client)[0]
    normal = -np.asarray(pt[7])  # contactNormalOnB points from geometry 2 to 1
    point = 0.5 * (np.asarray(pt[5]) + np.asarray(pt[6]))
    J = normal @ (_point_jacobian(pb, body, links[1], point, q, client)
                  - _point_jacobian(pb, body, links[0], point, q, client))  # fmt: skip
    M = np.array(pb.calculateMassMatrix(body, q, physicsClientId=client))
    return float(J @ np.linalg.solve(M, J))


def _com(pb, body, link, client):
    return np.asarray(pb.getLinkState(body, link, computeForwardKinematics=1, physicsClientId=client)[0])


def push_forces(pb, body, pushes, client):
    """The constant forces at the links' centres of mass, for the next step (PyBullet clears them)."""
    for link, force in pushes.items():
        pb.applyExternalForce(body, link, list(map(float, force)), list(_com(pb, body, link, client)),
                              pb.WORLD_FRAME, physicsClientId=client)  # fmt: skip


def free_qacc(pb, body, q, v, client, pushes):
    """Joint accelerations without contact: ``M^-1 (tau_gravity + J_com^T F - C v)`` from PyBullet."""
    M = np.array(pb.calculateMassMatrix(body, list(q), physicsClientId=client))
    tau = np.zeros(len(q))
    for link, force in pushes.items():
        tau += _point_jacobian(pb, body, link, _com(pb, body, link, client), q, client).T @ np.asarray(force)
    zero = [0.0] * len(q)
    bias = np.array(pb.calculateInverseDynamics(body, list(q), list(v), zero, physicsClientId=client))
    return np.linalg.solve(M, tau - bias)


def pybullet_drop(
    urdf: str | Path, pair: tuple[str, str], qpos: ArrayLike, qvel: ArrayLike, *, timestep: float,
    script: str | Path | None = None, stiffness: float | None = None, damping: float | None = None,
    phase: float = 0.0, duration: float = 1.0, link_damping: bool = False, friction: float | None = 0.0,
    speed: float | None = None, joint_names: Sequence[str] | None = None, forces: dict | None = None,
) -> MechanismDrop:  # fmt: skip
    """Drop the URDF's mechanism in PyBullet from the touchdown state; ``MechanismDrop``.

    Parameters
    ----------
    urdf : path of the URDF.
    pair : (geometry 1, geometry 2): ``<collision>`` names.
    qpos, qvel : touchdown configuration and joint velocities of the movable joints, in PyBullet's
        order (the URDF's; ``movable_joints``).
    timestep : PyBullet's step, s.
    script : the script ``tune`` wrote: its ``apply_to(body, client)`` sets the pair's values.
    stiffness, damping : instead of ``script``: each link's ``contactStiffness`` (N/m) and
        ``contactDamping`` (N s/m).
    phase : in [0, 1): the first step starts ``phase`` of a step before touchdown, on the free
        motion (a second-order expansion; the stored velocity is that of half a step earlier:
        semi-implicit Euler's positions then lie on the free motion, as in ``stepping.flight``).
    link_damping : keep PyBullet's link damping (default: set to 0).
    friction : the pair's ``lateralFriction`` (default 0: the frictionless contact the laws and
        maps describe; None keeps the model's, PyBullet's default 0.5).
    speed : the approach speed e_N is relative to, m/s (default: the gap's rate at touchdown, by
        differences).
    joint_names : the joints ``qpos`` and ``qvel`` are ordered by (default PyBullet's order).
    forces : {link: (fx, fy, fz)} constant forces at the links' centres of mass, N, world axes
        (``applyExternalForce`` before every step).
    """
    if (script is None) == (stiffness is None or damping is None):
        raise ValueError("give either script= (the tuned script) or both stiffness= and damping=")
    pb = pybullet_module()
    client = pb.connect(pb.DIRECT)
    try:
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=client)
        pb.setTimeStep(float(timestep), physicsClientId=client)
        flags = pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_INERTIA_FROM_FILE
        body = pb.loadURDF(str(urdf), useFixedBase=True, flags=flags, physicsClientId=client)
        links = link_indices(body, collision_links(urdf, pair), client)
        if script is not None:
            runpy.run_path(str(script))["apply_to"](body, client)
        for link in links:
            if script is None:
                assert stiffness is not None and damping is not None  # checked above
                pb.changeDynamics(body, link, contactStiffness=float(stiffness),
                                  contactDamping=float(damping), physicsClientId=client)  # fmt: skip
            if friction is not None:
                pb.changeDynamics(body, link, lateralFriction=float(friction), physicsClientId=client)
        if not link_damping:
            for link in range(-1, pb.getNumJoints(body, physicsClientId=client)):
                pb.changeDynamics(body, link, linearDamping=0.0, angularDamping=0.0, physicsClientId=client)
        joints, names = movable_joints(body, client)
        # PyBullet drives every joint by a velocity motor (target 0) unless told otherwise: free them.
        pb.setJointMotorControlArray(body, joints, pb.VELOCITY_CONTROL, forces=[0.0] * len(joints),
                                     physicsClientId=client)  # fmt: skip
        q0, v0 = (in_pybullet_order(x, joint_names, names) for x in (qpos, qvel))
        h = float(timestep)
        if speed is None:
            speed = touchdown_rate(pb, body, links, joints, q0, v0, client)
        pushes = dict(
            zip(link_indices(body, list(forces or {}), client), (forces or {}).values(), strict=True)
        )
        set_joint_state(pb, body, joints, q0, v0, client)
        qacc = free_qacc(pb, body, q0, v0, client, pushes)
        tc = float(phase) * h
        set_joint_state(
            pb, body, joints, q0 - tc * v0 + 0.5 * tc * tc * qacc, v0 - (tc + 0.5 * h) * qacc, client
        )
        gaps, inv_masses = [], []
        for _ in range(int(math.ceil(duration / h))):
            gaps.append(pair_gap(pb, body, links, client))
            if gaps[-1] < 0.0:
                inv_masses.append(inverse_mass(pb, body, links, joints, client))
            if len(gaps) > 3 and gaps[-1] > 0.0 and min(gaps) < 0.0 and gaps[-2] >= 0.0:
                break
            push_forces(pb, body, pushes, client)
            pb.stepSimulation(physicsClientId=client)
        exit_speed, t_exit = rebound_speed(np.arange(len(gaps)) * h, gaps)
        return MechanismDrop.of(exit_speed / float(speed), exit_speed, t_exit, inv_masses, h)
    finally:
        pb.disconnect(client)


def in_pybullet_order(values, given, names):
    """``values`` (ordered by the joint names ``given``, or PyBullet's) in PyBullet's joint order."""
    x = np.asarray(values, dtype=float).ravel()
    if x.size != len(names):
        raise ValueError(f"qpos and qvel need {len(names)} values (the movable joints {names}), got {x.size}")
    if given is None:
        return x
    given = list(given)
    if sorted(given) != sorted(names):
        raise ValueError(f"joint_names = {given} are not PyBullet's movable joints {names}")
    return np.array([x[given.index(n)] for n in names])


def touchdown_rate(pb, body, links, joints, q, v, client, dt=1e-7):
    """The gap's rate at ``(q, v)`` by a central difference along the joint velocity (m/s, > 0 closing)."""
    set_joint_state(pb, body, joints, q + dt * v, v, client)
    up = pair_gap(pb, body, links, client)
    set_joint_state(pb, body, joints, q - dt * v, v, client)
    down = pair_gap(pb, body, links, client)
    return -(up - down) / (2.0 * dt)
