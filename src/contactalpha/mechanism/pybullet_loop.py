"""PyBullet's engine loop: a URDF's contact solved on PyBullet's own drops of the whole model.

The design is ``engine_loop``'s (MuJoCo): the contact's e_N is the pair's signed gap's rate where
it first comes back through zero over its closing rate at touchdown; the drops start ``phase`` of
a step before touchdown at the midpoint phases; the mean's error estimate and the secant are
``engine_loop.PhaseSampler`` and ``engine_loop.solve_damping``.  The parameters are each link's
``contactStiffness`` and ``contactDamping`` (``changeDynamics``; PyBullet's pair then has the
stiffness k = k1 k2 / (k1 + k2) and the damping c1 + c2, as the script ``tune`` writes sets them).

The model is loaded once, as PyBullet users load a URDF with ``tune``'s script (``loadURDF`` with
``URDF_USE_SELF_COLLISION | URDF_USE_INERTIA_FROM_FILE``, the base fixed, the joints' default
velocity motors off), and keeps everything else of PyBullet's: the joints' damping of the file,
the links' velocity damping (0.04 by default), the pair's friction (the file's, else PyBullet's
0.5) and every other contact.  Each drop restores the state saved after loading
(``restoreState``, which also clears the contact cache) and sets the touchdown state.

Importing this module does not need PyBullet.
"""

import math
from collections.abc import Sequence
from pathlib import Path

from numpy.typing import ArrayLike

from .engine_loop import DropLoop
from .pybullet_model import (
    collision_links,
    free_qacc,
    in_pybullet_order,
    inverse_mass,
    link_indices,
    movable_joints,
    pair_gap,
    push_forces,
    pybullet_module,
    set_joint_state,
    touchdown_rate,
)

# The longest drop, s: a drop that touched and has not come back by then is captured (e_N = 0).
DURATION = 1.0
# PyBullet loads a URDF's base fixed here (as MuJoCo does and Drake's reader does by default).
BASES = ("fixed",)


class PybulletLoop(DropLoop):
    """A URDF loaded once in PyBullet, dropped at many phases with any pair ``(k, c)`` per link.

    Parameters
    ----------
    urdf : path of the URDF.
    pair : (geometry 1, geometry 2): ``<collision>`` names (``pybullet_model.collision_links``).
    qpos, qvel : touchdown configuration and joint velocities of the movable joints, ordered by
        ``joint_names`` (default PyBullet's order).
    timestep : PyBullet's step, s.
    joint_names : the joints ``qpos`` and ``qvel`` are ordered by.
    forces : {link: (fx, fy, fz)} constant forces at links' centres of mass, N, world axes.
    speed : the approach speed e_N is relative to, m/s (default: the gap's rate at touchdown).
    base : "fixed" (``BASES``).
    """

    engine = "PyBullet"
    damping_name = "contactDamping (each link)"

    def __init__(
        self, urdf: str | Path, pair: Sequence[str], qpos: ArrayLike, qvel: ArrayLike, *, timestep: float,
        joint_names: Sequence[str] | None = None, forces: dict | None = None, speed: float | None = None,
        base: str = "fixed",
    ) -> None:  # fmt: skip
        if base not in BASES:
            raise ValueError(
                f"base = {base!r}: PyBullet's engine loop drops a URDF with its base fixed {BASES}; "
                "a floating URDF robot is tuned in MuJoCo (an MJCF with a <freejoint>) or Drake"
            )
        pb = self.pb = pybullet_module()
        self.client = c = pb.connect(pb.DIRECT)
        self.pair: tuple[str, str] = (str(pair[0]), str(pair[1]))
        self.timestep = h = float(timestep)
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=c)
        pb.setTimeStep(h, physicsClientId=c)
        flags = pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_INERTIA_FROM_FILE
        self.body = pb.loadURDF(str(urdf), useFixedBase=True, flags=flags, physicsClientId=c)
        self.links = link_indices(self.body, collision_links(urdf, self.pair), c)
        self.joints, names = movable_joints(self.body, c)
        pb.setJointMotorControlArray(self.body, self.joints, pb.VELOCITY_CONTROL,
                                     forces=[0.0] * len(self.joints), physicsClientId=c)  # fmt: skip
        self.q0, self.v0 = (in_pybullet_order(x, joint_names, names) for x in (qpos, qvel))
        forces = dict(forces or {})
        self.pushes = dict(zip(link_indices(self.body, list(forces), c), forces.values(), strict=True))
        self.speed = float(touchdown_rate(pb, self.body, self.links, self.joints, self.q0, self.v0, c)
                           if speed is None else speed)  # fmt: skip
        set_joint_state(pb, self.body, self.joints, self.q0, self.v0, c)
        self.qacc = free_qacc(pb, self.body, self.q0, self.v0, c, self.pushes)
        self.saved = pb.saveState(physicsClientId=c)
        self.drops = 0

    def close(self) -> None:
        """Disconnect PyBullet's client."""
        if self.client is not None:
            self.pb.disconnect(self.client)
            self.client = None

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - PyBullet may be gone at interpreter exit
            pass

    def switch_off_friction(self) -> str:
        """Make the pair frictionless; what it had ("" where it had none)."""
        pb, c = self.pb, self.client
        had = [float(pb.getDynamicsInfo(self.body, link, physicsClientId=c)[1]) for link in self.links]
        for link in self.links:
            pb.changeDynamics(self.body, link, lateralFriction=0.0, physicsClientId=c)
        self.saved = pb.saveState(physicsClientId=c)
        return f"lateralFriction {max(had):g}" if max(had) > 0.0 else ""

    def switch_off_damping(self) -> str:
        """Zero every joint's damping and every link's velocity damping; what there was.

        PyBullet does not report a link's velocity damping: its default (0.04) is named.
        """
        pb, c = self.pb, self.client
        joints = [float(pb.getJointInfo(self.body, j, physicsClientId=c)[6]) for j in self.joints]
        for k in range(-1, pb.getNumJoints(self.body, physicsClientId=c)):
            pb.changeDynamics(self.body, k, linearDamping=0.0, angularDamping=0.0, jointDamping=0.0,
                              physicsClientId=c)  # fmt: skip
        self.saved = pb.saveState(physicsClientId=c)
        parts = []
        if max(joints, default=0.0) > 0.0:
            parts.append(f"{sum(x > 0 for x in joints)} joints' damping up to {max(joints):g}")
        parts.append("the links' velocity damping (PyBullet's, 0.04 by default)")
        return ", ".join(parts)

    def _set(self, params):
        k, c = (float(x) for x in params)
        for link in self.links:
            self.pb.changeDynamics(self.body, link, contactStiffness=k, contactDamping=c,
                                   physicsClientId=self.client)  # fmt: skip

    def drop(self, params, phase: float, mass: bool = False) -> tuple[float, float]:
        """``(e_N, relative change of m_eff over the contact)`` of one drop (the change NaN without ``mass``).

        NaN e_N: never touched; 0: touched and not back within ``DURATION``.
        """
        pb, c, h = self.pb, self.client, self.timestep
        self._set(params)
        pb.restoreState(self.saved, physicsClientId=c)
        tc = float(phase) * h
        q = self.q0 - tc * self.v0 + 0.5 * tc * tc * self.qacc
        set_joint_state(pb, self.body, self.joints, q, self.v0 - (tc + 0.5 * h) * self.qacc, c)
        gaps, inv = [], []
        for _ in range(int(math.ceil(DURATION / h))):
            gaps.append(pair_gap(pb, self.body, self.links, c))
            if mass and gaps[-1] < 0.0:
                inv.append(inverse_mass(pb, self.body, self.links, self.joints, c))
            if len(gaps) > 3 and gaps[-1] > 0.0 and gaps[-2] >= 0.0 and min(gaps) < 0.0:
                break
            push_forces(pb, self.body, self.pushes, c)
            pb.stepSimulation(physicsClientId=c)
        return self.read_drop(gaps, inv, h)
