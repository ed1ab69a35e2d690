"""A sphere dropped on the ground inside Exudyn, through ``ObjectContactSphereSphere``.

The scene: a mass point (the ball, mass ``m``, radius ``R``) and a fixed ground sphere of radius
``GROUND_RADIUS`` whose top is the plane ``y = 0``; the ball moves on the vertical through the
ground sphere's centre, where the connector's gap is exactly ``y - R`` whatever the ground
radius (Exudyn's force takes no radius: ``contactStiffness`` is k itself).  The load is a
``LoadForceVector`` of ``m g + F`` downward.  The contact uses ``contactStiffnessExponent`` 1.5,
``contactDamping`` 0 and an ``impactModel`` with a ``restitutionCoefficient`` (conversions in
``contactalpha.adapters.engine_conventions``).

Exudyn's impact models divide by the impact speed that the connector records in its data node
on the step where the gap turns from positive to non-positive (``PostNewtonStep``); both the
explicit and the implicit solvers run that step.  A gap that *starts* at 0 is never seen to
turn, and then no speed is recorded and the impact model adds no damping at all: the data node
here starts with a positive gap.  The recorded speed is the one at the end of the first contact
step, slightly above the true approach speed (gravity and the load act during that step); this
bias of the engine shows in the round trips at the 1e-7 .. 1e-5 level.

Solvers: ``"dopri5"``, Exudyn's error-controlled Dormand-Prince 5(4) at tight tolerances, and
``"generalized_alpha"``, its default implicit solver (spectral radius 1, fixed steps).

Importing this module does not need Exudyn; the functions that run it raise ``ImportError``
(with the install hint) when it is missing.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.base import Adapter
from contactalpha.adapters.contract import DropScene, Samples
from contactalpha.adapters.engine_conventions import EXUDYN_IMPACT_MODELS, exudyn_restitution_input
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.opensim_hc import STATIC_BRACKET
from contactalpha.adapters.record import Engine
from contactalpha.engine.scaling import length_scale, time_scale
from contactalpha.laws import get_law
from contactalpha.validation import check_positive, check_range

# The one import guard of Exudyn.
LOADER = Loader("Exudyn", ("exudyn", "exudyn.itemInterface"), "exudyn")
# Radius of the fixed ground sphere, m; along the line of centres it does not enter the gap.
GROUND_RADIUS = 1.0
SOLVERS = ("dopri5", "generalized_alpha")
# Relative tolerance of DOPRI5; the absolute one is this times delta* (m) per coordinate.
TOLERANCE = 1e-10
# Steps (generalized-alpha) or the largest step (DOPRI5) per scaled time unit t*.
STEPS_PER_TSTAR = 400
# Window of one measured impact, in t*.
WINDOW_TSTAR = 40.0
# Exudyn's impact model whose built-in mapping covers every alpha > 0 (see engine_conventions).
IMPACT_MODEL = 2
# Smallest step either solver may take, in t*: Exudyn's own floor is an absolute 1e-8 s, which a
# stiff contact's steps pass (steel, k = 2e10 N/m^1.5: t* ~ 8e-5 s, and the first contact step is
# cut far below 1e-8 s), so the run stopped with "SolverError: SolveDynamic terminated".
MIN_STEP_TSTAR = 1e-12


_exudyn = LOADER.load


def version():
    """Exudyn's version string; raises ImportError when it is not installed."""
    return _exudyn().__version__


def build_drop(mass, radius, stiffness, restitution, impact_model, gravity, force):
    """Exudyn system of the drop (see the module docstring), ball at touchdown, at rest.

    Returns
    -------
    (SystemContainer, mbs, handles) ; ``handles`` holds the node numbers ``ball`` and ``data`` and
    the object number ``contact``.
    """
    exu = _exudyn()
    ii = exu.itemInterface
    m = float(check_positive("mass", mass))
    r = float(check_positive("radius", radius))
    k = float(check_positive("stiffness", stiffness))
    e = float(check_range("restitution", restitution, 0.0, 1.0, lo_open=True))
    if impact_model not in EXUDYN_IMPACT_MODELS:
        raise ValueError(
            f"impact_model = {impact_model!r} is outside the valid choices {EXUDYN_IMPACT_MODELS}"
        )
    g = float(check_range("gravity", gravity, 0.0, np.inf, hi_open=True))
    f = float(check_range("force", force, 0.0, np.inf, hi_open=True))
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ii.ObjectGround(referencePosition=[0.0, -GROUND_RADIUS, 0.0]))
    m_ground = mbs.AddMarker(ii.MarkerBodyPosition(bodyNumber=ground))
    ball = mbs.AddNode(ii.NodePoint(referenceCoordinates=[0.0, r, 0.0]))
    mbs.AddObject(ii.MassPoint(mass=m, nodeNumber=ball))
    m_ball = mbs.AddMarker(ii.MarkerNodePosition(nodeNumber=ball))
    mbs.AddLoad(ii.LoadForceVector(markerNumber=m_ball, loadVector=[0.0, -(m * g + f), 0.0]))
    # Data: gap, tangential speed, recorded impact speed, plastic overlap; a positive gap to start.
    data = mbs.AddNode(
        ii.NodeGenericData(initialCoordinates=[1e-300, 0.0, 0.0, 0.0], numberOfDataCoordinates=4)
    )
    contact = mbs.AddObject(
        ii.ObjectContactSphereSphere(
            markerNumbers=[m_ground, m_ball],
            nodeNumber=data,
            spheresRadii=[GROUND_RADIUS, r],
            contactStiffness=k,
            contactDamping=0.0,
            contactStiffnessExponent=1.5,
            restitutionCoefficient=e,
            impactModel=int(impact_model),
            minimumImpactVelocity=0.0,
        )
    )
    return sc, mbs, {"ball": ball, "data": data, "contact": contact}


def static_penetration(mass, radius, stiffness, gravity, force):
    """Deformation (m) at which Exudyn's contact force carries ``m g + F``, found by root search.

    The connector's ``Force`` output at rest (ball and data coordinates set in the current
    configuration) is balanced against the load by Brent's method; the prediction is ``(m a / k)^(2/3)``.
    """
    exu = _exudyn()
    sc, mbs, h = build_drop(mass, radius, stiffness, 1.0, 2, gravity, force)
    mbs.Assemble()
    load = mass * gravity + force
    predicted = (load / stiffness) ** (2.0 / 3.0)

    def imbalance(delta):

        mbs.systemData.SetODE2Coordinates([0.0, -delta, 0.0], exu.ConfigurationType.Current)
        mbs.systemData.SetODE2Coordinates_t([0.0, 0.0, 0.0], exu.ConfigurationType.Current)
        # The connector's outputs read the contact state from its data node (gap first).
        mbs.systemData.SetDataCoordinates([-delta, 0.0, 0.0, 0.0], exu.ConfigurationType.Current)
        # ``Force`` is the connector's term on the left-hand side of the equations of motion of
        # marker 1 (the ball): minus the force acting on it.
        return -mbs.GetObjectOutput(h["contact"], exu.OutputVariableType.Force)[1] - load

    from scipy.optimize import brentq  # here: importing scipy.optimize takes a while

    lo, hi = (predicted * s for s in STATIC_BRACKET)
    return brentq(imbalance, lo, hi, xtol=1e-16 * predicted, rtol=1e-15)


@dataclass(frozen=True)
class ExudynSettings:
    """Settings of an Exudyn drop: the workflow's ``engines.exudyn`` section.

    ``tolerance`` of Exudyn's DOPRI5 (relative; absolute = tolerance delta*), ``steps_per_tstar``
    (generalized-alpha steps, or DOPRI5's largest step, per t*), ``window`` of one measured
    impact in t*.
    """

    tolerance: float = TOLERANCE
    steps_per_tstar: int = STEPS_PER_TSTAR
    window: float = WINDOW_TSTAR


@dataclass
class _Drop:
    mbs: object
    container: object
    handles: dict
    sensors: list


class ExudynAdapter(Adapter):
    """Exudyn's ``ObjectContactSphereSphere``: the engine adapter (``adapters.contract``).

    The law is Hunt-Crossley with n = 3/2; its damping parameter alpha enters through the
    ``restitutionCoefficient`` of ``impactModel`` 2 (``contactalpha.adapters.engine_conventions``).
    ``solver`` is one of ``SOLVERS``; the registry's adapter uses DOPRI5.
    """

    name = "exudyn"
    law = get_law("hunt_crossley")
    module = LOADER.module
    settings = ExudynSettings()
    # Units of ``parameters``.
    units = {
        "contactStiffness": "N/m^1.5",
        "contactStiffnessExponent": "1",
        "impactModel": "",
        "restitutionCoefficient": "1",
        "contactDamping": "N s/m",
        "minimumImpactVelocity": "m/s",
    }
    # The block's names and units in words (printed under its parameters by the front door).
    unit_notes = (
        "contactStiffness in N/m^1.5 (exponent 1.5) is k itself; restitutionCoefficient feeds",
        "  impactModel 2, which scales the damping with each impact's recorded speed",
        "  (minimumImpactVelocity 0); contactDamping must stay 0 (a linear damper)",
    )

    def __init__(self, solver="dopri5"):
        if solver not in SOLVERS:
            raise ValueError(f"solver = {solver!r} is outside the valid choices {SOLVERS}")
        self.solver = solver

    def version(self):
        """Exudyn's version string."""
        return version()

    def parameters(self, damping, scene, settings=None):
        """The connector's parameters for alpha = ``damping``: impactModel 2, contactDamping 0."""
        return {
            "contactStiffness": scene.stiffness,
            "contactStiffnessExponent": 1.5,
            "impactModel": IMPACT_MODEL,
            "restitutionCoefficient": exudyn_restitution_input(damping, IMPACT_MODEL),
            "contactDamping": 0.0,
            "minimumImpactVelocity": 0.0,
        }

    def build_drop(self, scene, params, settings):
        """The Exudyn system, assembled, with the ball at touchdown moving at the approach speed."""
        exu = _exudyn()
        ii = exu.itemInterface
        s = scene
        e, model = params["restitutionCoefficient"], params.get("impactModel", IMPACT_MODEL)
        sc, mbs, h = build_drop(s.mass, s.radius, s.stiffness, e, model, s.gravity, s.force)
        mbs.SetNodeParameter(h["ball"], "initialVelocities", [0.0, -s.approach_speed, 0.0])
        sensors = [
            mbs.AddSensor(
                ii.SensorNode(
                    nodeNumber=h["ball"], storeInternal=True, writeToFile=False, outputVariableType=kind
                )
            )
            for kind in (exu.OutputVariableType.Position, exu.OutputVariableType.Velocity)
        ]
        mbs.Assemble()
        return _Drop(mbs, sc, h, sensors)

    def run(self, model, scene, settings):
        """Solve over ``settings.window`` t* with ``self.solver``; states at every step."""
        exu = _exudyn()
        mbs, v = model.mbs, scene.approach_speed
        ds = float(length_scale(scene.mass, scene.stiffness, v))
        ts = float(time_scale(scene.mass, scene.stiffness, v))
        n = int(math.ceil(settings.window * settings.steps_per_tstar))
        sim = exu.SimulationSettings()
        ti = sim.timeIntegration
        ti.endTime = settings.window * ts
        ti.numberOfSteps = n
        ti.verboseMode = 0
        ti.minimumStepSize = MIN_STEP_TSTAR * ts
        sim.solution.file.write = False
        sim.solution.sensors.writePeriod = 0.5 * ts / settings.steps_per_tstar
        if self.solver == "dopri5":
            kind = exu.DynamicSolverType.DOPRI5
            ti.automaticStepSize = True
            ti.relativeTolerance = float(settings.tolerance)
            ti.absoluteTolerance = float(settings.tolerance) * ds
        else:
            kind = exu.DynamicSolverType.GeneralizedAlpha
            ti.generalizedAlpha.spectralRadius = 1.0
        start = time.perf_counter()
        ok = mbs.SolveDynamic(sim, solverType=kind)
        seconds = time.perf_counter() - start
        if not ok:
            raise RuntimeError(f"Exudyn's {self.solver} solver failed")
        pos, vel = (mbs.GetSensorStoredData(s) for s in model.sensors)
        speed = mbs.GetNodeOutput(model.handles["data"], exu.OutputVariableType.Coordinates)[2]
        extra = {"last_recorded_impact_speed": float(speed)}
        return Samples(pos[:, 0], scene.radius - pos[:, 2], -vel[:, 2], seconds, extra)

    def static_penetration(self, scene):
        """Deformation (m) at which Exudyn's contact carries the load at rest (``static_penetration``)."""
        return static_penetration(scene.mass, scene.radius, scene.stiffness, scene.gravity, scene.force)

    def timestep(self, settings):
        """None for DOPRI5 (error-controlled); the fixed step t*/steps_per_tstar is per scene otherwise."""
        return None


ADAPTER = ExudynAdapter()
ENGINE = Engine(adapter=ADAPTER, loader=LOADER, step_map=None, model_file=None, batched=None)


def drop_impact(
    mass,
    radius,
    stiffness,
    approach_speed,
    restitution,
    gravity,
    force,
    *,
    impact_model=IMPACT_MODEL,
    solver="dopri5",
    tolerance=TOLERANCE,
    steps_per_tstar=STEPS_PER_TSTAR,
    window=WINDOW_TSTAR,
):
    """One impact in Exudyn: the ball starts at touchdown at ``approach_speed``.

    Parameters
    ----------
    restitution : float
        Exudyn's ``restitutionCoefficient`` (use ``exudyn_restitution_input(alpha)`` for our alpha).
    impact_model : {1, 2}
    solver : {"dopri5", "generalized_alpha"}
        See the module docstring.
    tolerance : float
        Relative tolerance of DOPRI5 (its absolute tolerance is ``tolerance * delta*``).
    steps_per_tstar : int
        Largest step (DOPRI5) or fixed step (generalized-alpha) is ``t* / steps_per_tstar``; states
        are stored at every step.  Every step size (and the floor of the solvers' step reductions,
        ``MIN_STEP_TSTAR t*``) scales with the scene's ``t*``, so a stiff contact runs as a soft one.
    window : float
        Length of the run in scaled time units t*.

    Returns
    -------
    (MeasuredImpact, Samples)
        ``Samples.extra`` holds ``separated_later`` (the ball left the ground after a
        non-separating end: it must not), ``min_delta_after_end`` and
        ``last_recorded_impact_speed`` (the connector's data at the end of the run: the speed of
        the last touchdown in the window).
    """
    adapter = ExudynAdapter(solver)
    scene = DropScene(mass, stiffness, approach_speed, gravity, force, radius)
    settings = ExudynSettings(tolerance, steps_per_tstar, window)
    params = {"restitutionCoefficient": restitution, "impactModel": impact_model}
    samples = adapter.run(adapter.build_drop(scene, params, settings), scene, settings)
    return adapter.measure(samples, scene), samples
