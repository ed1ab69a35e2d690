"""A sphere dropped on a plane in PyBullet with Bullet's rigid contact: ``restitution`` and its threshold.

This is the contact most PyBullet users have: no ``contactStiffness``, a ``restitution`` on each
body (the pair's is their product) and ``restitutionVelocityThreshold`` (0.2 m/s).  Its step is
``impulse.bullet_map`` (read from Bullet's source, checked here step by step); the restitution
whose phase mean at the step is a loaded contact's e_N is ``impulse.inverse.restitution_for``.

``law`` is the loaded contact the answer stands for (Hunt-Crossley, n = 3/2, as the front door's
default): ``parameters(damping, scene)`` turns the law's damping at the scene's load into its e_N
and gives the restitution that delivers it at the step (with ``settings.threshold``); the front
door (``contact_parameters(..., engine="pybullet_impulse", timestep=h)``) also sets the threshold
from the law's critical speed.

**The drop.**  As ``adapters.pybullet_kv``'s: ``createMultiBody`` (a ``btMultiBody``; Bullet's
rigid-body path, ``settings.maximal``, steps the same map), no friction, no damping in flight,
``applyExternalForce(-F)`` before every step.  A drop is read as ``impulse.delivered`` reads the
map (``measure_impulse``).  Importing this module does not need PyBullet.
"""

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from contactalpha.adapters.contract import Samples
from contactalpha.adapters.measure import MeasuredImpact
from contactalpha.adapters.record import Engine
from contactalpha.adapters.stepped import FREE_STEP_RTOL, SteppingAdapter, float_or_array, touchdown_state
from contactalpha.engine.codes import END_STATES, NONSEPARATION, SEPARATION
from contactalpha.impulse import bullet_map
from contactalpha.impulse.delivered import CHATTER_STEPS, free_steps
from contactalpha.impulse.inverse import per_body, restitution_for
from contactalpha.impulse.schedule import Rebounder
from contactalpha.laws import get_law
from contactalpha.stepping.flight import rebound_speed

from .pybullet_kv import LOADER

_pybullet = LOADER.load


@dataclass(frozen=True)
class ImpulseSettings:
    """A PyBullet rigid-contact drop: ``timestep`` (s), ``phases``, ``threshold`` (m/s), ``steps``.

    ``steps``: steps a drop runs (touchdown, contact, the rebound's first free step);
    ``maximal``: ``useMaximalCoordinates`` (a ``btRigidBody`` instead of a ``btMultiBody``);
    ``extra_phases``: touchdown phases run after the ``phases`` midpoints (where the step map puts
    the range's ends, say).
    """

    timestep: float = bullet_map.DEFAULT_TIMESTEP
    phases: int = 64
    threshold: float = bullet_map.VELOCITY_THRESHOLD
    steps: int = 2 * CHATTER_STEPS
    maximal: bool = False
    tol: float = 1e-3
    extra_phases: tuple = ()


@dataclass
class _Drop:
    client: int
    ball: int
    states: list


def measure_impulse(z, w, accel, h, approach_speed, free_rtol=FREE_STEP_RTOL, z_atol=0.0):
    """The first impact in per-step states (``z`` height above the plane, m; ``w`` up, m/s).

    The rule of ``impulse.delivered.drop_impulse``: the first sample after the first step with an
    impulse (a step not free by ``delivered.free_steps``: its velocity changed by ``free_rtol`` of
    the scale, or its position by that of a step's travel or ``z_atol`` m, other than free flight)
    that moves up with a free step after it; e_N is its parabola's speed at the plane over the
    approach speed.  None: "nonseparation", e_N = 0.
    """
    z, w = np.asarray(z, dtype=float), np.asarray(w, dtype=float)
    tol = free_rtol * max(accel * h, approach_speed)
    free = free_steps(z, w, accel, h, tol, max(tol * h, z_atol))
    hit = np.flatnonzero(~free)
    t_max = int(np.argmin(z))
    if hit.size:
        after = np.flatnonzero(free[hit[0] + 1 :] & (w[hit[0] + 1 : -1] > 0.0))
        if after.size:
            j = hit[0] + 1 + int(after[0])
            out = rebound_speed(z[j], w[j], accel, h)
            return MeasuredImpact(
                math.nan, out / approach_speed, END_STATES[SEPARATION], approach_speed,
                0.0, t_max * h, j * h, -float(z.min()), 0.0, -out,
            )  # fmt: skip
    return MeasuredImpact(
        math.nan, 0.0, END_STATES[NONSEPARATION], approach_speed,
        0.0, t_max * h, (z.size - 1) * h, -float(z.min()), -float(z[-1]), 0.0,
    )  # fmt: skip


class ImpulseAdapter(SteppingAdapter):
    """An impulse engine's adapter (PyBullet's, PhysX's): the inverse at its step, one home.

    A subclass sets ``impulse`` (its record's name in ``impulse.registry``), ``settings`` with
    ``timestep`` and ``threshold``, and ``block(pair_restitution, threshold)``.
    """

    impulse: str

    def block(self, pair_restitution, threshold):
        """The engine's block for the pair's restitution and the threshold."""
        raise NotImplementedError

    def parameters(self, damping, scene, settings=None):
        """The engine's block for the law's e_N with ``damping`` at ``scene``'s load, at the step.

        ``scene`` needs ``accel`` (a ``DropScene``); the threshold is ``settings.threshold``.
        """
        settings = self.settings if settings is None else settings
        xi = float(self.law.scene_load_factor(scene.mass, scene.stiffness, scene.approach_speed, scene.accel))
        target = float(self.law.restitution(float(damping), xi, "kinematic"))
        ans = restitution_for(target, settings.timestep, scene.approach_speed, scene.accel, scene.radius,
                              settings.threshold, engine=self.impulse)  # fmt: skip
        return self.block(ans.restitution, settings.threshold)


class PyBulletImpulseAdapter(ImpulseAdapter):
    """Bullet's rigid contact with restitution through PyBullet (``adapters.contract``)."""

    name = "pybullet_impulse"
    law = get_law("hunt_crossley")
    module = "pybullet"
    settings = ImpulseSettings()
    # Answered only at the engine's step (no continuous block): the front door's impulse path.
    impulse = "pybullet_impulse"
    units = {
        "restitution": "1 (each body)",
        "restitutionVelocityThreshold": "m/s",
        "pair_restitution": "1",
        "critical_speed": "m/s (the loaded contact's: below it no bounce)",
    }

    def version(self):
        """PyBullet's API version number, as a string."""
        return str(_pybullet().getAPIVersion())

    def block(self, pair_restitution, threshold):
        """The engine's block for the pair's restitution and the threshold (``block``)."""
        return block(pair_restitution, threshold)

    def build_drop(self, scene, params, settings):
        """A fresh DIRECT client with the plane and the ball; touchdown states for every phase."""
        pb = _pybullet()
        client = pb.connect(pb.DIRECT)
        pb.setGravity(0.0, 0.0, -scene.gravity, physicsClientId=client)
        pb.setTimeStep(settings.timestep, physicsClientId=client)
        threshold = float(params["restitutionVelocityThreshold"])
        pb.setPhysicsEngineParameter(restitutionVelocityThreshold=threshold, physicsClientId=client)
        plane = pb.createMultiBody(0.0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=client),
                                   physicsClientId=client)  # fmt: skip
        shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=scene.radius, physicsClientId=client)
        ball = pb.createMultiBody(scene.mass, shape, basePosition=[0.0, 0.0, 2.0 * scene.radius],
                                  useMaximalCoordinates=settings.maximal, physicsClientId=client)  # fmt: skip
        each = params["restitution"]
        each = tuple(each) if isinstance(each, tuple) else (float(each), float(each))
        for body, e in ((ball, each[0]), (plane, each[1])):
            pb.changeDynamics(body, -1, restitution=float(e), lateralFriction=0.0, linearDamping=0.0,
                              angularDamping=0.0, physicsClientId=client)  # fmt: skip
        h = settings.timestep
        phases = list((np.arange(settings.phases) + 0.5) / settings.phases) + list(settings.extra_phases)
        return _Drop(client, ball, [touchdown_state(scene.approach_speed, scene.accel, h, p) for p in phases])

    def run(self, model, scene, settings):
        """Step each touchdown state ``settings.steps`` times; the client is closed after."""
        pb = _pybullet()
        h, c, b, n = settings.timestep, model.client, model.ball, settings.steps
        zs, ws = np.empty((len(model.states), n + 1)), np.empty((len(model.states), n + 1))
        push = [0.0, 0.0, -scene.force]
        start = time.perf_counter()
        try:
            for i, (z0, w0) in enumerate(model.states):
                pb.resetBasePositionAndOrientation(b, [0.0, 0.0, scene.radius + z0], [0, 0, 0, 1],
                                                   physicsClientId=c)  # fmt: skip
                pb.resetBaseVelocity(b, [0.0, 0.0, w0], [0.0, 0.0, 0.0], physicsClientId=c)
                zs[i, 0], ws[i, 0] = z0, w0
                for j in range(1, n + 1):
                    if scene.force:
                        pb.applyExternalForce(b, -1, push, [0.0, 0.0, 0.0], pb.LINK_FRAME, physicsClientId=c)
                    pb.stepSimulation(physicsClientId=c)
                    zs[i, j] = pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][2] - scene.radius
                    ws[i, j] = pb.getBaseVelocity(b, physicsClientId=c)[0][2]
        finally:
            pb.disconnect(physicsClientId=c)
        seconds = time.perf_counter() - start
        return Samples(np.arange(n + 1) * h, -zs[0], -ws[0], seconds, {"z": zs, "v": ws, "timestep": h})

    def measure(self, samples, scene):
        """The first phase's impact (``measure_impulse``); every phase's e_N in ``samples.extra``."""
        x = samples.extra
        h = x["timestep"]
        results = [
            measure_impulse(z, w, scene.accel, h, scene.approach_speed)
            for z, w in zip(x["z"], x["v"], strict=True)
        ]
        x["e_n_phases"] = np.array([r.e_n for r in results])
        x["contact_steps"] = np.array([max(round(r.t_end / h), 1) for r in results])
        x["separated"] = np.array([r.separated for r in results])
        return results[0]

    def static_penetration(self, scene):
        """Depth (m) below the plane where the ball rests: Bullet's ``linearSlop`` (the rigid contact)."""
        pb = _pybullet()
        settings = self.settings
        model = self.build_drop(scene, block(0.0, settings.threshold), settings)
        c, b = model.client, model.ball
        pb.resetBasePositionAndOrientation(b, [0.0, 0.0, scene.radius], [0, 0, 0, 1], physicsClientId=c)
        pb.resetBaseVelocity(b, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=c)
        try:
            for _ in range(settings.steps):
                if scene.force:
                    pb.applyExternalForce(b, -1, [0.0, 0.0, -scene.force], [0.0, 0.0, 0.0], pb.LINK_FRAME,
                                          physicsClientId=c)  # fmt: skip
                pb.stepSimulation(physicsClientId=c)
            z = pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][2]
        finally:
            pb.disconnect(physicsClientId=c)
        return scene.radius - z

    def timestep(self, settings):
        """PyBullet's fixed step, s."""
        return settings.timestep


def drop_sequence(scene, schedule, duration, settings=None):
    """Per-step states of a drop from rest at the height where ``scene.approach_speed`` is reached.

    ``schedule`` (``impulse.schedule.TouchdownSchedule``) sets the ball's restitution before every
    step through ``Rebounder`` (the plane's 1, the threshold 0); the run lasts ``duration`` s.
    Returns ``(z, w)``: height above the plane (m) and upward velocity (m/s) at every step, from
    the start.
    """
    pb = _pybullet()
    settings = settings or replace(ImpulseSettings(), timestep=schedule.timestep)
    h, a = settings.timestep, scene.accel
    model = ADAPTER.build_drop(scene, block(1.0, 0.0), replace(settings, phases=1))
    c, b = model.client, model.ball
    rebounder = Rebounder(schedule)
    height = scene.approach_speed**2 / (2.0 * a)
    # At rest at the top of the parabola: the stored velocity is its mean over the step, +a h / 2.
    z, w = height, 0.5 * a * h
    pb.resetBasePositionAndOrientation(b, [0.0, 0.0, scene.radius + z], [0, 0, 0, 1], physicsClientId=c)
    pb.resetBaseVelocity(b, [0.0, 0.0, w], [0.0, 0.0, 0.0], physicsClientId=c)
    n = int(math.ceil(duration / h))
    zs, ws = np.empty(n + 1), np.empty(n + 1)
    zs[0], ws[0] = z, w
    try:
        for j in range(1, n + 1):
            pb.changeDynamics(b, -1, restitution=rebounder.restitution(z, w), physicsClientId=c)
            if scene.force:
                pb.applyExternalForce(b, -1, [0.0, 0.0, -scene.force], [0.0, 0.0, 0.0], pb.LINK_FRAME,
                                      physicsClientId=c)  # fmt: skip
            pb.stepSimulation(physicsClientId=c)
            z = pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][2] - scene.radius
            w = pb.getBaseVelocity(b, physicsClientId=c)[0][2]
            zs[j], ws[j] = z, w
    finally:
        pb.disconnect(physicsClientId=c)
    return zs, ws


def block(pair_restitution, threshold):
    """The engine's block: each body's ``restitution`` (the square root of the pair's) and the threshold."""
    pair = np.asarray(pair_restitution, dtype=float)
    return {
        "restitution": float_or_array(np.sqrt(pair)) if pair.ndim else per_body(float(pair)),
        "restitutionVelocityThreshold": float_or_array(threshold),
        "pair_restitution": float_or_array(pair),
    }


ADAPTER = PyBulletImpulseAdapter()
ENGINE = Engine(adapter=ADAPTER, loader=LOADER, step_map=None, model_file=None, batched=None)
