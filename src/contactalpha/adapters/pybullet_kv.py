"""A sphere dropped on a plane in PyBullet, with ``contactStiffness`` and ``contactDamping``.

**The law** (``kelvin_voigt``).  Given a stiffness and a damping, Bullet's solver turns them into
an ERP and a CFM at its step (``btSequentialImpulseConstraintSolver``: ``denom = h k + c``,
``erp = h k / denom``, ``cfm = 1 / (h denom)``): an implicit spring-dashpot ``F = max(0, k δ + c
δ')``, which pushes only.  The pair's values come from the two bodies' by
``btManifoldResult::calculateCombinedContactStiffness`` (``1/(1/k1 + 1/k2)``) and
``calculateCombinedContactDamping`` (``c1 + c2``): a value set on both bodies acts as k/2 and 2c.
So each body gets ``contactStiffness = 2k`` and ``contactDamping = c/2``, and the pair is (k, c)
with ``c = 2 zeta sqrt(k m)``.  Checked in the engine: the ball rests at δ = m a / k, and small steps
approach the law's e_N.  The contact surface sits ``LINEAR_SLOP`` = 1e-5 m below the geometric
one (the solver's penetration is ``distance + m_linearSlop``); a drop's heights here are measured
from the geometric surface, where a user reads approach and rebound (as ``stepping.drop`` reads the map).
Bullet's own ``restitution`` is set to 0 here (it adds a velocity target of its own);
``delivered(scene, zeta, PyBulletSettings(restitution=e))`` measures what it delivers instead.

Bullet's implicit step is strongly dissipative when a contact spans few steps: at its default
1/240 s a contact of k/m = 1e4 s^-2 rebounds with e_N ~ 0.4 even without damping, and higher targets
are out of reach at that step (``calibrate`` says "unreachable").

**The drop.**  ``createMultiBody`` of a sphere above a plane, no friction, no linear or angular
damping (PyBullet's default is 0.04), gravity, and ``applyExternalForce(-F)`` before every step.

Importing this module does not need PyBullet.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.contract import Samples
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.record import Engine, ModelFile, Ref
from contactalpha.adapters.stepped import SteppingAdapter, float_or_array, touchdown_state
from contactalpha.laws import get_law
from contactalpha.stepping.pybullet_map import LINEAR_SLOP, TIMESTEP
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_range

# The one import guard of PyBullet (its adapter and its model-file drop).
LOADER = Loader("PyBullet", ("pybullet",), "pybullet")


_pybullet = LOADER.load


@dataclass(frozen=True)
class PyBulletSettings:
    """Settings of a PyBullet drop: ``timestep`` (s), ``phases``, ``window`` (periods), ``tol``.

    ``restitution`` is Bullet's own, on both bodies (0: the compliant contact alone).
    """

    timestep: float = TIMESTEP
    phases: int = 4
    window: float = 3.0
    tol: float = 1e-3
    restitution: float = 0.0


@dataclass
class _Drop:
    client: int
    ball: int
    states: list
    restitution: float


class PyBulletAdapter(SteppingAdapter):
    """Bullet's compliant contact through PyBullet: the engine adapter (``adapters.contract``)."""

    name = "pybullet"
    law = get_law("kelvin_voigt")
    module = LOADER.module
    settings = PyBulletSettings()
    # Units of ``parameters``.
    units = {
        "contactStiffness": "N/m",
        "contactDamping": "N s/m",
        "pair_stiffness": "N/m",
        "pair_damping": "N s/m",
    }

    def version(self):
        """PyBullet's API version number, as a string."""
        return str(_pybullet().getAPIVersion())

    def parameters(self, damping, scene, settings=None):
        """Each body's ``contactStiffness`` (N/m) and ``contactDamping`` (N s/m), and the pair's (k, c).

        ``damping`` is the law's damping ratio zeta (>= 0): ``c = 2 zeta sqrt(k m)``; arrays go through.
        """
        zeta = np.asarray(check_range("damping", damping, 0.0, math.inf, hi_open=True))
        c = 2.0 * zeta * np.sqrt(scene.stiffness * scene.mass)
        k = np.broadcast_to(scene.stiffness, c.shape)
        return {
            "contactStiffness": float_or_array(2.0 * k),
            "contactDamping": float_or_array(0.5 * c),
            "pair_stiffness": float_or_array(k),
            "pair_damping": float_or_array(c),
        }

    def build_drop(self, scene, params, settings, *, stiffness_each=None, damping_each=None):
        """A fresh DIRECT client with the plane and the ball; touchdown states for every phase.

        ``stiffness_each``/``damping_each`` = (ball, plane) override the equal split of ``params``;
        a stiffness of None leaves that body's values unset.
        """
        pb = _pybullet()
        restitution = settings.restitution
        client = pb.connect(pb.DIRECT)
        pb.setGravity(0.0, 0.0, -scene.gravity, physicsClientId=client)
        pb.setTimeStep(settings.timestep, physicsClientId=client)
        plane_shape = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=client)
        plane = pb.createMultiBody(0.0, plane_shape, physicsClientId=client)
        shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=scene.radius, physicsClientId=client)
        ball = pb.createMultiBody(
            scene.mass, shape, basePosition=[0.0, 0.0, 2.0 * scene.radius], physicsClientId=client
        )
        k_each = stiffness_each or (float(params["contactStiffness"]),) * 2
        c_each = damping_each or (float(params["contactDamping"]),) * 2
        for body, k, c in ((ball, k_each[0], c_each[0]), (plane, k_each[1], c_each[1])):
            # A body given None keeps Bullet's unset values (btCollisionObject: 1e30 N/m, 0.1 N s/m).
            values = {} if k is None else {"contactStiffness": float(k), "contactDamping": float(c)}
            pb.changeDynamics(
                body,
                -1,
                **values,
                restitution=float(restitution),
                lateralFriction=0.0,
                linearDamping=0.0,
                angularDamping=0.0,
                physicsClientId=client,
            )
        h = settings.timestep
        phases = np.arange(settings.phases) / settings.phases
        states = [touchdown_state(scene.approach_speed, scene.accel, h, p) for p in phases]
        return _Drop(client, ball, states, restitution)

    def run(self, model, scene, settings):
        """Step each touchdown state over ``settings.window`` periods; the client is closed after."""
        pb = _pybullet()
        h, c, b = settings.timestep, model.client, model.ball
        period = 2.0 * math.pi * math.sqrt(scene.mass / scene.stiffness)
        n = int(math.ceil(settings.window * period / h)) + 4
        zs, vs = np.empty((len(model.states), n + 1)), np.empty((len(model.states), n + 1))
        push = [0.0, 0.0, -scene.force]
        start = time.perf_counter()
        try:
            for i, (z0, v0) in enumerate(model.states):
                # Heights above the geometric surface, where a user reads the drop
                # (the map: ``kernels.surface``).
                pb.resetBasePositionAndOrientation(
                    b, [0.0, 0.0, scene.radius + z0], [0, 0, 0, 1], physicsClientId=c
                )
                pb.resetBaseVelocity(b, [0.0, 0.0, v0], [0.0, 0.0, 0.0], physicsClientId=c)
                zs[i, 0], vs[i, 0] = z0, v0
                for j in range(1, n + 1):
                    if scene.force:
                        pb.applyExternalForce(b, -1, push, [0.0, 0.0, 0.0], pb.LINK_FRAME, physicsClientId=c)
                    pb.stepSimulation(physicsClientId=c)
                    zs[i, j] = pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][2] - scene.radius
                    vs[i, j] = pb.getBaseVelocity(b, physicsClientId=c)[0][2]
        finally:
            pb.disconnect(physicsClientId=c)
        seconds = time.perf_counter() - start
        t = np.arange(n + 1) * h
        return Samples(t, -zs[0], -vs[0], seconds, {"z": zs, "v": vs, "timestep": h})

    def static_penetration(self, scene, params=None, settings=None):
        """Deformation (m) below the contact surface once the engine settles (critical damping by default)."""
        pb = _pybullet()
        settings = self.settings if settings is None else settings
        params = params or self.parameters(1.0, scene)
        model = self.build_drop(scene, params, settings)
        c, b = model.client, model.ball
        predicted = scene.mass * scene.accel / scene.stiffness
        pb.resetBasePositionAndOrientation(
            b, [0.0, 0.0, scene.radius - LINEAR_SLOP - predicted], [0, 0, 0, 1], physicsClientId=c
        )
        pb.resetBaseVelocity(b, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=c)
        n = int(math.ceil(40.0 * 2.0 * math.pi * math.sqrt(scene.mass / scene.stiffness) / settings.timestep))
        try:
            for _ in range(n):
                if scene.force:
                    pb.applyExternalForce(
                        b, -1, [0.0, 0.0, -scene.force], [0.0, 0.0, 0.0], pb.LINK_FRAME, physicsClientId=c
                    )
                pb.stepSimulation(physicsClientId=c)
            z = pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][2]
        finally:
            pb.disconnect(physicsClientId=c)
        return scene.radius - LINEAR_SLOP - z

    def timestep(self, settings):
        """PyBullet's fixed step, s."""
        return settings.timestep


ADAPTER = PyBulletAdapter()
# PyBullet reads no model file here: ``tune`` takes MuJoCo's or Drake's reading of the URDF.
ENGINE = Engine(
    adapter=ADAPTER,
    loader=LOADER,
    step_map=stepper("pybullet"),
    model_file=ModelFile(
        suffixes=(), reader=None, tuner=Ref("contactalpha.mechanism.tuners:PYBULLET_TUNER"), loads=(".urdf",)
    ),
    batched=None,
)
