"""A sphere dropped on a plane in PhysX 5 through SAPIEN (CPU ``PhysxCpuSystem``): restitution and threshold.

PhysX's contact, as SAPIEN exposes it, is rigid: a ``PhysxMaterial(static, dynamic, restitution)``
on each shape (the pair's restitution is their average) and the scene's ``bounce_threshold``
(2 m/s by default); its compliant mode is not exposed.  Its step is ``impulse.physx_map`` (TGS,
read from PhysX's source, checked here step by step); the restitution whose phase mean at the step
is a loaded contact's e_N is ``impulse.inverse.restitution_for(..., engine="physx")``.

``law`` is the loaded contact the answer stands for (Hunt-Crossley, n = 3/2), as for
``adapters.pybullet_impulse``; the front door sets the threshold from its critical speed.

**The drop.**  A plane (``PhysxCollisionShapePlane``, its normal turned to +z) and a sphere of
``scene.mass``, no friction, no damping, no sleeping, the push as ``add_force_torque`` before every
step; SAPIEN's default step (0.01 s) and iterations (10 position, 1 velocity).  PhysX steps in
single precision: a drop is read as ``adapters.pybullet_impulse.measure_impulse`` reads one, with
a free step told at 1e-5 (its velocity) and a few float steps (its position:
``position_resolution``).  Importing this module does not need SAPIEN.
"""

import time
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.contract import Samples
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.pybullet_impulse import ImpulseAdapter, measure_impulse
from contactalpha.adapters.record import Engine
from contactalpha.adapters.stepped import float_or_array, touchdown_state
from contactalpha.impulse import physx_map
from contactalpha.impulse.schedule import Rebounder
from contactalpha.laws import get_law

LOADER = Loader("PhysX through SAPIEN", ("sapien", "sapien.physx"), "sapien", extra="physx")
# A free step in single precision: the velocity changed by -a h to this fraction.
FREE_RTOL = 1e-5
# ... and the position by h times the new velocity to this many float32 steps of the ball
# centre's height (or FREE_RTOL of a step's travel, whichever is larger): TGS moves the pose in
# each of its position iterations, each rounding to a float step (free steps measured up to 5).
POSITION_ULPS = 2 * physx_map.POSITION_ITERATIONS
# The plane's pose: PhysX's plane has its normal along +x; this turns it to +z (w, x, y, z: 120
# degrees about -(1, 1, 1), exact in float32, so the normal is exactly +z and PhysX's separation
# is the float32 centre's height less the float32 radius, exactly).
PLANE_QUATERNION = (0.5, -0.5, -0.5, -0.5)


_sapien = LOADER.load


@dataclass(frozen=True)
class PhysxSettings:
    """A SAPIEN drop: ``timestep`` (s), ``phases``, ``threshold`` (bounce threshold, m/s), ``steps``.

    ``extra_phases``: touchdown phases run after the ``phases`` midpoints.
    """

    timestep: float = physx_map.DEFAULT_TIMESTEP
    phases: int = 64
    threshold: float = physx_map.BOUNCE_THRESHOLD
    steps: int = 400
    tol: float = 1e-3
    extra_phases: tuple = ()


@dataclass
class _Drop:
    scene: object
    ball: object
    body: object
    states: list
    material: object = None


class PhysxAdapter(ImpulseAdapter):
    """PhysX 5's rigid contact with restitution through SAPIEN (``adapters.contract``)."""

    name = "physx"
    law = get_law("hunt_crossley")
    module = "sapien"
    settings = PhysxSettings()
    # Answered only at the engine's step (no continuous block): the front door's impulse path.
    impulse = "physx"
    units = {
        "restitution": "1 (each material: PhysX averages them)",
        "bounce_threshold": "m/s",
        "pair_restitution": "1",
        "critical_speed": "m/s (the loaded contact's: below it no bounce)",
    }

    def version(self):
        """SAPIEN's version string (its PhysX 5 inside)."""
        return str(_sapien().__version__)

    def block(self, pair_restitution, threshold):
        """The engine's block: the pair's restitution on each material (PhysX averages) and the threshold."""
        pair = float_or_array(pair_restitution)
        return {"restitution": pair, "bounce_threshold": float_or_array(threshold), "pair_restitution": pair}

    def build_drop(self, scene, params, settings):
        """A SAPIEN scene with the plane and the ball; touchdown states for every phase."""
        sapien = _sapien()
        physx = sapien.physx
        config = physx.get_scene_config()
        config.bounce_threshold = float(params["bounce_threshold"])
        config.gravity = np.array([0.0, 0.0, -scene.gravity])
        physx.set_scene_config(config)
        world = sapien.Scene([physx.PhysxCpuSystem()])
        world.set_timestep(settings.timestep)
        material = physx.PhysxMaterial(0.0, 0.0, float(params["restitution"]))
        ground = sapien.Entity()
        static = physx.PhysxRigidStaticComponent()
        static.attach(physx.PhysxCollisionShapePlane(material))
        ground.add_component(static)
        ground.set_pose(sapien.Pose(q=list(PLANE_QUATERNION)))
        world.add_entity(ground)
        ball = sapien.Entity()
        body = physx.PhysxRigidDynamicComponent()
        body.attach(physx.PhysxCollisionShapeSphere(scene.radius, material))
        body.mass = scene.mass
        ball.add_component(body)
        world.add_entity(ball)
        body.linear_damping, body.angular_damping, body.sleep_threshold = 0.0, 0.0, 0.0
        h = settings.timestep
        phases = list((np.arange(settings.phases) + 0.5) / settings.phases) + list(settings.extra_phases)
        states = [touchdown_state(scene.approach_speed, scene.accel, h, p) for p in phases]
        return _Drop(world, ball, body, states, material)

    def run(self, model, scene, settings):
        """Step each touchdown state ``settings.steps`` times."""
        sapien = _sapien()
        h, n, b = settings.timestep, settings.steps, model.body
        zs, ws = np.empty((len(model.states), n + 1)), np.empty((len(model.states), n + 1))
        push = [0.0, 0.0, -scene.force]
        start = time.perf_counter()
        for i, (z0, w0) in enumerate(model.states):
            model.ball.set_pose(sapien.Pose(p=[0.0, 0.0, scene.radius + z0]))
            b.linear_velocity, b.angular_velocity = [0.0, 0.0, w0], [0.0, 0.0, 0.0]
            zs[i, 0], ws[i, 0] = z0, w0
            for j in range(1, n + 1):
                if scene.force:
                    b.add_force_torque(push, [0.0, 0.0, 0.0])
                model.scene.step()
                zs[i, j] = float(model.ball.pose.p[2]) - scene.radius
                ws[i, j] = float(b.linear_velocity[2])
        seconds = time.perf_counter() - start
        return Samples(np.arange(n + 1) * h, -zs[0], -ws[0], seconds, {"z": zs, "v": ws, "timestep": h})

    def measure(self, samples, scene):
        """The first phase's impact (``measure_impulse`` in single precision); all phases' in ``extra``."""
        x = samples.extra
        h = x["timestep"]
        rows = zip(x["z"], x["v"], strict=True)
        a, v, r = scene.accel, scene.approach_speed, scene.radius
        results = [measure_impulse(z, w, a, h, v, FREE_RTOL, position_resolution(z, r)) for z, w in rows]
        x["e_n_phases"] = np.array([r.e_n for r in results])
        x["contact_steps"] = np.array([max(round(r.t_end / h), 1) for r in results])
        x["separated"] = np.array([r.separated for r in results])
        return results[0]

    def static_penetration(self, scene):
        """Depth (m) below the plane where the ball rests (PhysX's rest offset, 0, up to its float)."""
        settings = self.settings
        model = self.build_drop(scene, self.block(0.0, settings.threshold), settings)
        sapien = _sapien()
        model.ball.set_pose(sapien.Pose(p=[0.0, 0.0, scene.radius]))
        model.body.linear_velocity = [0.0, 0.0, 0.0]
        for _ in range(settings.steps):
            if scene.force:
                model.body.add_force_torque([0.0, 0.0, -scene.force], [0.0, 0.0, 0.0])
            model.scene.step()
        return scene.radius - float(model.ball.pose.p[2])

    def timestep(self, settings):
        """SAPIEN's fixed step, s."""
        return settings.timestep


def position_resolution(z, radius):
    """How finely PhysX's poses resolve a step's displacement (m): ``POSITION_ULPS`` float32 steps.

    ``z``: the heights read (above the plane, m) of a sphere of ``radius`` (m); the pose is the
    centre's, in single precision.
    """
    top = np.float32(radius + float(np.max(np.abs(z))))
    return POSITION_ULPS * float(np.spacing(top))


def drop_sequence(scene, schedule, duration, settings=None):
    """Per-step states of a drop from rest at the height where ``scene.approach_speed`` is reached.

    ``schedule`` (``impulse.schedule.TouchdownSchedule`` for ``"physx"``) sets the restitution of
    the one material both shapes share (so the pair's is that value) before every step through
    ``Rebounder``; the bounce threshold is 0.  The map is given PhysX's own separation, the
    float32 centre's height less the float32 radius (the height read plus ``r - float32(r)``): at
    rest it is within a float's step of 0, and its sign decides PhysX's branch and so what a
    release from rest delivers (``impulse.physx_map``).
    Returns ``(z, w)`` at every step from the start (the pose's height).
    """
    sapien = _sapien()
    settings = settings or PhysxSettings(timestep=schedule.timestep, phases=1)
    a, h = scene.accel, settings.timestep
    model = ADAPTER.build_drop(scene, ADAPTER.block(0.0, 0.0), settings)
    rebounder = Rebounder(schedule)
    physx = sapien.physx
    shapes = [
        model.body.collision_shapes[0],
        *(c.collision_shapes[0] for c in model.scene.physx_system.rigid_static_components),
    ]
    z, w = scene.approach_speed**2 / (2.0 * a), 0.5 * a * h
    model.ball.set_pose(sapien.Pose(p=[0.0, 0.0, scene.radius + z]))
    model.body.linear_velocity = [0.0, 0.0, w]
    n = int(np.ceil(duration / h))
    zs, ws = np.empty(n + 1), np.empty(n + 1)
    zs[0], ws[0] = z, w
    offset = scene.radius - float(np.float32(scene.radius))  # PhysX's separation less the height
    for j in range(1, n + 1):
        # a new material each step: PxMaterial::setRestitution clamps to [0, 1], the constructor
        # does not (a release from rest needs a coefficient of several)
        material = physx.PhysxMaterial(0.0, 0.0, rebounder.restitution(z + offset, w))
        for shape in shapes:
            shape.physical_material = material
        if scene.force:
            model.body.add_force_torque([0.0, 0.0, -scene.force], [0.0, 0.0, 0.0])
        model.scene.step()
        z, w = float(model.ball.pose.p[2]) - scene.radius, float(model.body.linear_velocity[2])
        zs[j], ws[j] = z, w
    return zs, ws


ADAPTER = PhysxAdapter()
ENGINE = Engine(adapter=ADAPTER, loader=LOADER, step_map=None, model_file=None, batched=None)
