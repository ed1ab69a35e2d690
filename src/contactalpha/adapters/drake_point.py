"""A sphere dropped on a half space in Drake's MultibodyPlant, with compliant point contact.

**The law** (``hunt_crossley_linear``).  With ``ContactModel.kPoint`` the plant's normal force is
``f = k δ (1 + d δ')₊`` (``MultibodyPlant::CalcContactResultsPointPair``: ``fn = k * x * (1 + d * vn)``),
Hunt-Crossley with n = 1 and ``d = alpha / v_minus`` in s/m.  The pair's ``k`` and ``d`` come from
the two geometries' ``point_contact_stiffness`` and ``hunt_crossley_dissipation`` by
``internal::CombinePointContactParameters``:

    k = k1 k2 / (k1 + k2),    d = (k2 d1 + k1 d2) / (k1 + k2),

so giving both geometries ``2k`` and ``d`` makes the pair (k, d).  Checked in the engine: the ball
rests at δ = m a / k (``static_penetration``), and a drop on the continuous plant (``time_step =
0``) delivers the law's e_N.  The discrete plant (Drake's default ``time_step`` 1e-3 s and its
default ``lagged`` approximation; ``tamsi`` and ``similar`` also use ``hunt_crossley_dissipation``,
``sap`` uses ``relaxation_time`` instead and is not this law) steps in time; its rebound moves with
the step, and ``calibrate`` refines alpha on its own drops.

**The drop.**  A sphere on a prismatic joint along z above a ``HalfSpace``, gravity and a constant
generalized force ``-F`` on the joint; no friction.

Importing this module does not need Drake.
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
from contactalpha.stepping.drake_map import APPROXIMATIONS, TIMESTEP
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_range

# The one import guard of Drake (its adapter, its model-file reader and drop).
LOADER = Loader("Drake", ("pydrake.all",), "drake")


_drake = LOADER.load


@dataclass(frozen=True)
class DrakeSettings:
    """Settings of a Drake drop.

    ``time_step`` (s; 0 is the continuous plant, error-controlled at ``accuracy``), the discrete
    ``approximation``, ``phases`` touchdown phases averaged (discrete), ``window`` in undamped
    periods 2 pi sqrt(m/k), ``reports`` per period (continuous), ``tol`` on the delivered e_N.
    """

    time_step: float = TIMESTEP
    approximation: str = "lagged"
    accuracy: float = 1e-10
    phases: int = 8
    window: float = 3.0
    reports: int = 2000
    tol: float = 1e-3


@dataclass
class _Drop:
    diagram: object
    plant: object
    joint: object
    states: list


class DrakeAdapter(SteppingAdapter):
    """Drake's point contact (``hunt_crossley_dissipation``): the engine adapter (``adapters.contract``)."""

    name = "drake"
    law = get_law("hunt_crossley_linear")
    module = LOADER.module
    settings = DrakeSettings()
    # Units of ``parameters``.
    units = {
        "point_contact_stiffness": "N/m",
        "hunt_crossley_dissipation": "s/m",
        "pair_stiffness": "N/m",
        "pair_dissipation": "s/m",
    }

    def version(self):
        """Drake's version string."""
        import importlib.metadata

        _drake()
        return importlib.metadata.version(LOADER.package)

    def parameters(self, damping, scene, settings=None):
        """Each geometry's ``point_contact_stiffness`` (N/m), ``hunt_crossley_dissipation`` (s/m); the pair's.

        ``damping`` is the law's alpha (>= 0): ``d = alpha / v_minus``; arrays go through.
        """
        alpha = np.asarray(check_range("damping", damping, 0.0, math.inf, hi_open=True))
        d = alpha / scene.approach_speed
        k = np.broadcast_to(scene.stiffness, d.shape)
        return {
            "point_contact_stiffness": float_or_array(2.0 * k),
            "hunt_crossley_dissipation": float_or_array(d),
            "pair_stiffness": float_or_array(k),
            "pair_dissipation": float_or_array(d),
        }

    def build_drop(self, scene, params, settings, *, stiffness_each=None, dissipation_each=None):
        """The diagram; ``stiffness_each``/``dissipation_each`` = (ball, ground) override the equal split."""
        dk = _drake()
        if settings.approximation not in APPROXIMATIONS:
            raise ValueError(
                f"approximation = {settings.approximation!r} is outside the valid choices {APPROXIMATIONS}"
            )
        k_each = stiffness_each or (float(params["point_contact_stiffness"]),) * 2
        d_each = dissipation_each or (float(params["hunt_crossley_dissipation"]),) * 2
        builder = dk.DiagramBuilder()
        plant, _ = dk.AddMultibodyPlantSceneGraph(builder, time_step=float(settings.time_step))
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, -scene.gravity])
        body = plant.AddRigidBody("ball", dk.SpatialInertia.SolidSphereWithMass(scene.mass, scene.radius))

        def props(k, d):
            p = dk.ProximityProperties()
            dk.AddContactMaterial(
                dissipation=d, point_stiffness=k, friction=dk.CoulombFriction(0.0, 0.0), properties=p
            )
            return p

        ground = plant.world_body()
        plant.RegisterCollisionGeometry(
            ground, dk.RigidTransform(), dk.HalfSpace(), "ground", props(k_each[1], d_each[1])
        )
        plant.RegisterCollisionGeometry(
            body, dk.RigidTransform(), dk.Sphere(scene.radius), "ball", props(k_each[0], d_each[0])
        )
        joint = plant.AddJoint(
            dk.PrismaticJoint("z", plant.world_frame(), body.body_frame(), [0.0, 0.0, 1.0])
        )
        plant.set_contact_model(dk.ContactModel.kPoint)
        if settings.time_step > 0.0:
            approx = {
                "lagged": dk.DiscreteContactApproximation.kLagged,
                "tamsi": dk.DiscreteContactApproximation.kTamsi,
                "similar": dk.DiscreteContactApproximation.kSimilar,
            }[settings.approximation]
            plant.set_discrete_contact_approximation(approx)
        plant.Finalize()
        push = builder.AddSystem(dk.ConstantVectorSource([-scene.force]))
        builder.Connect(push.get_output_port(), plant.get_applied_generalized_force_input_port())
        diagram = builder.Build()
        h = settings.time_step
        if h > 0.0:
            phases = np.arange(settings.phases) / settings.phases
            states = [touchdown_state(scene.approach_speed, scene.accel, h, p) for p in phases]
        else:
            states = [(0.0, -scene.approach_speed)]
        return _Drop(diagram, plant, joint, states)

    def run(self, model, scene, settings):
        """Each touchdown state run over ``settings.window`` periods: per step (discrete) or per report."""
        dk = _drake()
        h = settings.time_step
        period = 2.0 * math.pi * math.sqrt(scene.mass / scene.stiffness)
        dt = h if h > 0.0 else period / settings.reports
        n = int(math.ceil(settings.window * period / dt)) + 4
        zs, vs = np.empty((len(model.states), n + 1)), np.empty((len(model.states), n + 1))
        seconds = 0.0
        for i, (z0, v0) in enumerate(model.states):
            sim = dk.Simulator(model.diagram)
            ctx = model.plant.GetMyMutableContextFromRoot(sim.get_mutable_context())
            model.joint.set_translation(ctx, scene.radius + z0)
            model.joint.set_translation_rate(ctx, v0)
            if h == 0.0:
                sim.get_mutable_integrator().set_target_accuracy(settings.accuracy)
            sim.Initialize()
            zs[i, 0], vs[i, 0] = z0, v0
            start = time.perf_counter()
            for j in range(1, n + 1):
                sim.AdvanceTo(j * dt)
                zs[i, j] = model.joint.get_translation(ctx) - scene.radius
                vs[i, j] = model.joint.get_translation_rate(ctx)
            seconds += time.perf_counter() - start
        t = np.arange(n + 1) * dt
        return Samples(t, -zs[0], -vs[0], seconds, {"z": zs, "v": vs, "timestep": h})

    def static_penetration(self, scene, params=None, settings=None):
        """Deformation (m) where the continuous plant's acceleration of the resting ball is zero (Brent)."""
        from scipy.optimize import brentq

        _drake()
        params = params or self.parameters(0.0, scene)
        model = self.build_drop(scene, params, DrakeSettings(time_step=0.0))
        root = model.diagram.CreateDefaultContext()
        ctx = model.plant.GetMyMutableContextFromRoot(root)

        def accel(delta):
            model.joint.set_translation(ctx, scene.radius - delta)
            model.joint.set_translation_rate(ctx, 0.0)
            return model.plant.EvalTimeDerivatives(ctx).get_vector().CopyToVector()[1]

        predicted = scene.mass * scene.accel / scene.stiffness
        return brentq(accel, 0.1 * predicted, 10.0 * predicted, xtol=1e-16 * predicted, rtol=1e-15)

    def timestep(self, settings):
        """The plant's step, s, or None for the continuous plant."""
        return settings.time_step if settings.time_step > 0.0 else None


ADAPTER = DrakeAdapter()
ENGINE = Engine(
    adapter=ADAPTER,
    loader=LOADER,
    step_map=stepper("drake"),
    model_file=ModelFile(
        suffixes=(".sdf", ".urdf"),
        reader=Ref("contactalpha.mechanism.drake_model:read_drake"),
        tuner=Ref("contactalpha.mechanism.tuners:DRAKE_TUNER"),
        refused_meshes=(".stl", ".dae"),
    ),
    batched=None,
)
