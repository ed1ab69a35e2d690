"""PyBullet's engine loop: a URDF's contact solved on PyBullet's own drops of the whole model.

The design is ``engine_loop``'s (MuJoCo): the contact's e_N is the pair's signed gap's rate where
it first comes back through zero over its closing rate at touchdown; the drops start ``phase`` of
a step before touchdown at the midpoint phases; the mean's error estimate and the secant are
``engine_loop.PhaseSampler`` and ``engine_loop.solve_damping``.  The parameters are each link's
``contactStiffness`` and ``contactDamping`` (``changeDynamics``; PyBullet's pair then has the
stiffness k = k1 k2 / (k1 + k2) and the damping c1 + c2, as the script ``tune`` writes sets them).

The model is loaded once, as PyBullet users load a URDF with ``tune``'s script (``loadURDF`` with
``URDF_USE_SELF_COLLISION | URDF_USE_INERTIA_FROM_FILE``, the base fixed or floating, the joints'
default velocity motors off), and keeps everything else of PyBullet's: the joints' damping of the file,
the links' velocity damping (0.04 by default), the pair's friction (the file's, else PyBullet's
0.5) and every other contact.  Each drop restores the state saved after loading
(``restoreState``, which also clears the contact cache) and sets the touchdown state.

**A floating base** (``base="floating"``) starts each drop ``phase`` of a step before touchdown
with the accelerations PyBullet itself gives the robot ``PROBE_STEPS`` steps before touchdown
(one step from there: gravity, the links' damping and every other contact, such as a resting
support's, acting): a stack's lower sphere resting on the floor stays at rest.

**Per link.** A link's ``contactStiffness`` and ``contactDamping`` act on every contact of the
link (the floor's too): PyBullet combines a pair's as k1 k2 / (k1 + k2) and c1 + c2, where a
link without its own values has PyBullet's rigid contact (stiffness without limit, damping 0.1).
A pair landing on several points (a box flat on its face: PyBullet's manifold has its four
corners) gets the values at each point, so the landing's stiffness and damping are the points'
sum: four times the pair's.

Importing this module does not need PyBullet.
"""

import math
from collections.abc import Sequence
from pathlib import Path

from numpy.typing import ArrayLike

from . import pybullet_floating as floating
from .engine_loop import DropLoop
from .mujoco_model import HEIGHT_LOOK
from .pybullet_model import (
    collision_links,
    free_qacc,
    in_pybullet_order,
    inverse_mass,
    link_indices,
    movable_joints,
    push_forces,
    pybullet_module,
    set_joint_state,
    touchdown_rate,
)
from .touch import landing_note

# The longest drop, s: a drop that touched and has not come back by then is captured (e_N = 0).
DURATION = 1.0
# A URDF's base: fixed (as MuJoCo loads it and Drake's reader does by default), or floating
# (``useFixedBase=False``; ``pybullet_floating``: Drake's coordinates, a floor ``GROUND`` added).
BASES = ("fixed", "floating")
# Steps before touchdown at which a floating robot's accelerations are read (``_probe_acc``).
PROBE_STEPS = 10.0
# Height (m) a floating robot is lifted to between drops, away from every contact (``_flush``).
FAR = 100.0


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
    base : "fixed" or "floating" (``BASES``).  Floating: the URDF loaded with ``useFixedBase=False``
        (the whole robot falls), ``qpos`` and ``qvel`` in Drake's coordinates of the same file
        (``pybullet_floating``), a static floor ``GROUND`` added (the pair may name it); the
        effective mass's change over the contact is not read (NaN).
    set_on : the pair's geometries whose links get ``(k, c)`` (default both, as ``tune``'s script
        sets them).  A link's values act on every contact of that link: on a stack, set them on
        the upper sphere only, and the lower sphere's floor support keeps PyBullet's own contact.
    """

    engine = "PyBullet"
    damping_name = "contactDamping (each link)"

    def __init__(
        self, urdf: str | Path, pair: Sequence[str], qpos: ArrayLike, qvel: ArrayLike, *, timestep: float,
        joint_names: Sequence[str] | None = None, forces: dict | None = None, speed: float | None = None,
        base: str = "fixed", set_on: Sequence[str] | None = None,
    ) -> None:  # fmt: skip
        if base not in BASES:
            raise ValueError(f"base = {base!r} is outside the valid choices {BASES}")
        pb = self.pb = pybullet_module()
        self.client = c = pb.connect(pb.DIRECT)
        self.pair: tuple[str, str] = (str(pair[0]), str(pair[1]))
        self.timestep = h = float(timestep)
        self.floating = base == "floating"
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=c)
        pb.setTimeStep(h, physicsClientId=c)
        flags = pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_INERTIA_FROM_FILE
        self.body = pb.loadURDF(str(urdf), useFixedBase=not self.floating, flags=flags, physicsClientId=c)
        self.parts = self._pair_parts(urdf)
        self.links = tuple(link for body, link in self.parts if body == self.body)
        on = self.pair if set_on is None else tuple(str(g) for g in set_on)
        if not on or any(g not in self.pair for g in on):
            raise ValueError(f"set_on = {set_on!r}: name one or both of the pair's geometries {self.pair}")
        self.set_on = tuple(part for name, part in zip(self.pair, self.parts, strict=True) if name in on)
        self.joints, names = movable_joints(self.body, c)
        pb.setJointMotorControlArray(self.body, self.joints, pb.VELOCITY_CONTROL,
                                     forces=[0.0] * len(self.joints), physicsClientId=c)  # fmt: skip
        forces = dict(forces or {})
        self.pushes = dict(zip(link_indices(self.body, list(forces), c), forces.values(), strict=True))
        if self.floating:
            bq, jq, bv, jv = floating.split(qpos, qvel)
            jq, jv = (in_pybullet_order(x, joint_names, names) for x in (jq, jv))
            self.state0 = floating.base_state(pb, self.body, bq, bv, jq, jv, c)
            self.speed = float(self._rate() if speed is None else speed)
            self.accs: dict = {}
        else:
            self.q0, self.v0 = (in_pybullet_order(x, joint_names, names) for x in (qpos, qvel))
            self.speed = float(touchdown_rate(pb, self.body, self.links, self.joints, self.q0, self.v0, c)
                               if speed is None else speed)  # fmt: skip
            set_joint_state(pb, self.body, self.joints, self.q0, self.v0, c)
            self.qacc = free_qacc(pb, self.body, self.q0, self.v0, c, self.pushes)
        self.saved = pb.saveState(physicsClientId=c)
        self.drops = 0

    def _pair_parts(self, urdf):
        """``((body, link), (body, link))`` of the pair; ``GROUND`` is the floor a floating robot meets."""
        pb, c = self.pb, self.client
        if not self.floating:
            links = link_indices(self.body, collision_links(urdf, self.pair), c)
            return tuple((self.body, link) for link in links)
        floor = floating.add_ground(pb, c)
        own = [name for name in self.pair if name != floating.GROUND]
        mine = iter(link_indices(self.body, collision_links(urdf, own), c) if own else ())
        return tuple((floor, -1) if name == floating.GROUND else (self.body, next(mine))
                     for name in self.pair)  # fmt: skip

    def _flush(self):
        """Empty PyBullet's contact manifolds, then restore the saved state.

        ``restoreState`` keeps a box's corner points and their impulses: the next drop's solver
        would start warm from the last drop's (a flat box's e_N moved by 0.013).
        """
        pb, c = self.pb, self.client
        away = [0.0, 0.0, FAR]
        pb.resetBasePositionAndOrientation(self.body, away, [0.0, 0.0, 0.0, 1.0], physicsClientId=c)
        pb.performCollisionDetection(physicsClientId=c)
        pb.restoreState(self.saved, physicsClientId=c)

    def _gap(self):
        (b1, l1), (b2, l2) = self.parts
        pts = self.pb.getClosestPoints(b1, b2, 1.0, l1, l2, physicsClientId=self.client)
        return min(p[8] for p in pts) if pts else math.inf

    def _rate(self, dt=1e-7):
        """The pair's closing rate at the floating start, by a central difference along its velocity."""
        gaps = []
        still = floating.Rates(0.0 * self.state0.v, 0.0 * self.state0.w, 0.0 * self.state0.qd)
        for sign in (1.0, -1.0):
            moved = floating.shifted(self.state0, still, sign * dt, 0.0)
            floating.put(self.pb, self.body, self.joints, moved, self.client)
            gaps.append(self._gap())
        return -(gaps[0] - gaps[1]) / (2.0 * dt)

    def _probe_acc(self, params):
        """The floating robot's accelerations with ``params``: one PyBullet step ``PROBE_STEPS`` before.

        The state is moved back rigidly along its velocity by ``PROBE_STEPS`` steps (the pair
        apart) and stepped once: every other contact of the model acts, as a resting support's.
        """
        key = tuple(float(x) for x in params)
        if key in self.accs:
            return self.accs[key]
        pb, c, h = self.pb, self.client, self.timestep
        self._set(params)
        still = floating.Rates(0.0 * self.state0.v, 0.0 * self.state0.w, 0.0 * self.state0.qd)
        start = floating.shifted(self.state0, still, -PROBE_STEPS * h, 0.0)
        pb.restoreState(self.saved, physicsClientId=c)
        floating.put(pb, self.body, self.joints, start, c)
        before = floating.read(pb, self.body, self.joints, c)
        push_forces(pb, self.body, self.pushes, c)
        pb.stepSimulation(physicsClientId=c)
        after = floating.read(pb, self.body, self.joints, c)
        acc = floating.Rates((after.v - before.v) / h, (after.w - before.w) / h, (after.qd - before.qd) / h)
        self.accs[key] = acc
        return acc

    def heights(self) -> list[float]:
        """Heights (m) over the floor of the pair's points within ``HEIGHT_LOOK`` of the lowest, at the start.

        A floating robot's pair with the floor ``GROUND``: the corners of the other link's box
        collision shapes (a flat box: its four bottom corners); another pair, a link without a
        box, or a fixed base: the pair's closest point only.
        """
        pb, c = self.pb, self.client
        if not self.floating:
            set_joint_state(pb, self.body, self.joints, self.q0, self.v0, c)
            return [self._gap()]
        pb.restoreState(self.saved, physicsClientId=c)
        floating.put(pb, self.body, self.joints, self.state0, c)
        out = []
        if floating.GROUND in self.pair:
            body, link = self.parts[1 - self.pair.index(floating.GROUND)]
            out = floating.box_corner_heights(pb, body, link, c)
        out = out or [self._gap()]
        low = min(out)
        return sorted(h for h in out if h - low <= HEIGHT_LOOK)

    def landing(self, stiffness: float, effective_mass: float) -> str:
        """``touch.landing_note`` on the pair's points (``heights``): one contact mode, or ValueError.

        The maximum compression is ``speed`` sqrt(``effective_mass`` / ``stiffness``), the pair's.
        """
        delta = float(self.speed) * math.sqrt(float(effective_mass) / float(stiffness))
        return landing_note(self.heights(), delta)

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
        had = [float(pb.getDynamicsInfo(body, link, physicsClientId=c)[1]) for body, link in self.parts]
        for body, link in self.parts:
            pb.changeDynamics(body, link, lateralFriction=0.0, physicsClientId=c)
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
        for body, link in self.set_on:
            self.pb.changeDynamics(body, link, contactStiffness=k, contactDamping=c,
                                   physicsClientId=self.client)  # fmt: skip

    def drop(self, params, phase: float, mass: bool = False) -> tuple[float, float]:
        """``(e_N, relative change of m_eff over the contact)`` of one drop (the change NaN without ``mass``).

        NaN e_N: never touched; 0: touched and not back within ``DURATION``.
        """
        pb, c, h = self.pb, self.client, self.timestep
        acc = self._probe_acc(params) if self.floating else None
        self._set(params)
        pb.restoreState(self.saved, physicsClientId=c)
        if self.floating:
            self._flush()
        tc = float(phase) * h
        if acc is not None:
            start = floating.shifted(self.state0, acc, -tc, -(tc + 0.5 * h))
            floating.put(pb, self.body, self.joints, start, c)
        else:
            q = self.q0 - tc * self.v0 + 0.5 * tc * tc * self.qacc
            set_joint_state(pb, self.body, self.joints, q, self.v0 - (tc + 0.5 * h) * self.qacc, c)
        gaps, inv = [], []
        for _ in range(int(math.ceil(DURATION / h))):
            gaps.append(self._gap())
            if mass and gaps[-1] < 0.0 and not self.floating:
                inv.append(inverse_mass(pb, self.body, self.links, self.joints, c))
            if len(gaps) > 3 and gaps[-1] > 0.0 and gaps[-2] >= 0.0 and min(gaps) < 0.0:
                break
            push_forces(pb, self.body, self.pushes, c)
            pb.stepSimulation(physicsClientId=c)
        return self.read_drop(gaps, inv, h)
