"""A sphere dropped on the ground inside Simbody, through OpenSim's ``HuntCrossleyForce``.

The scene: one body (the ball: mass ``m``, a ``ContactSphere`` of radius ``R``) on a vertical
``SliderJoint``, a ``ContactHalfSpace`` as the ground, gravity ``g`` and a constant downward
``PrescribedForce`` ``F``; both geometries share one ``ContactParameters`` (stiffness and
dissipation from ``contactalpha.adapters.engine_conventions``; no friction).  The deformation is
``delta = R - y``.  OpenSim's own ``Manager`` integrates (Runge-Kutta-Merson, error-controlled at
``accuracy``); states are read at report times and ``adapters.measure`` cuts the impact out of them.

The dissipation ``c`` of a ``HuntCrossleyForce`` belongs to the model's topology, while the exact
alpha belongs to each impact's approach speed.  ``bounce`` therefore rebuilds the model during
each flight with the ``c`` of the coming touchdown and carries the state (time, height, speed)
over: a restart in flight changes nothing else, since no contact force acts there.

Importing this module does not need OpenSim; the functions that run it raise ``ImportError``
(with the install hint) when it is missing.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from contactalpha import models
from contactalpha.adapters.base import Adapter
from contactalpha.adapters.contract import DropScene, Samples
from contactalpha.adapters.engine_conventions import (
    opensim_alpha,
    opensim_dissipation,
    opensim_dissipation_unchecked,
    opensim_stiffness,
    opensim_stiffness_unchecked,
)
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.measure import measure_impact
from contactalpha.adapters.record import Engine
from contactalpha.engine.scaling import time_scale
from contactalpha.laws import get_law
from contactalpha.validation import check_alpha, check_positive, check_range

# The one import guard of OpenSim; it quietens OpenSim's logger to warnings.
LOADER = Loader(
    "OpenSim", ("opensim",), "opensim", setup=lambda opensim: opensim.Logger.setLevelString("Warn")
)
# Default integrator accuracy of OpenSim's Manager (relative, per step).
ACCURACY = 1e-10
# Report times per scaled time unit t* = delta*/v_minus (a contact lasts about 3.3 t*).
SAMPLES_PER_TSTAR = 200
# Window of one measured impact, in t*: long enough for the end of a heavily loaded contact.
WINDOW_TSTAR = 40.0
# Bracket of the static penetration search, as multiples of the predicted (m a / k)^(2/3).
STATIC_BRACKET = (0.1, 10.0)


_opensim = LOADER.load


def version():
    """OpenSim's version string; raises ImportError when it is not installed."""
    return _opensim().GetVersion()


@dataclass
class DropModel:
    """An OpenSim model of the drop, with the handles the runners need."""

    model: object
    state: object
    coordinate: object
    radius: float


def build_drop(mass, radius, stiffness, dissipation, gravity, force):
    """OpenSim model of a sphere above a half space (see the module docstring).

    Parameters
    ----------
    mass : float
        kg (> 0).
    radius : float
        m (> 0).
    stiffness : float
        Hertz stiffness k of the contact, N/m^1.5 (> 0); converted to OpenSim's per-geometry
        ``stiffness`` by ``opensim_stiffness``.
    dissipation : float
        OpenSim's dissipation c, s/m (>= 0).
    gravity, force : float
        m/s^2 and N, both downward (>= 0).

    Returns
    -------
    DropModel
    """
    osim = _opensim()
    m = float(check_positive("mass", mass))
    r = float(check_positive("radius", radius))
    c = float(check_range("dissipation", dissipation, 0.0, np.inf, hi_open=True))
    g = float(check_range("gravity", gravity, 0.0, np.inf, hi_open=True))
    f = float(check_range("force", force, 0.0, np.inf, hi_open=True))
    model = osim.Model()
    model.setName("contactalpha_drop")
    model.setGravity(osim.Vec3(0.0, -g, 0.0))
    ball = osim.Body("ball", m, osim.Vec3(0.0), osim.Inertia(0.4 * m * r * r))
    model.addBody(ball)
    # A slider moves along its frames' x axis; turning both frames by 90 deg about z makes it y.
    up = osim.Vec3(0.0, 0.0, 0.5 * math.pi)
    joint = osim.SliderJoint("slider", model.getGround(), osim.Vec3(0.0), up, ball, osim.Vec3(0.0), up)
    model.addJoint(joint)
    # A half space fills x > 0 of its frame; turned by -90 deg about z it fills y < 0.
    floor = osim.ContactHalfSpace(
        osim.Vec3(0.0), osim.Vec3(0.0, 0.0, -0.5 * math.pi), model.getGround(), "floor"
    )
    sphere = osim.ContactSphere(r, osim.Vec3(0.0), ball, "sphere")
    model.addContactGeometry(floor)
    model.addContactGeometry(sphere)
    contact = osim.HuntCrossleyForce()
    contact.setName("contact")
    contact.setStiffness(opensim_stiffness(stiffness, r))
    contact.setDissipation(c)
    contact.setStaticFriction(0.0)
    contact.setDynamicFriction(0.0)
    contact.setViscousFriction(0.0)
    contact.addGeometry("floor")
    contact.addGeometry("sphere")
    model.addForce(contact)
    push = osim.PrescribedForce("push", ball)
    push.setForceFunctions(osim.Constant(0.0), osim.Constant(-f), osim.Constant(0.0))
    push.setForceIsInGlobalFrame(True)
    model.addForce(push)
    state = model.initSystem()
    return DropModel(model, state, joint.getCoordinate(), r)


def set_state(drop, t, delta, delta_dot):
    """Put the ball at deformation ``delta`` (m) moving at ``delta_dot`` (m/s) at time ``t`` (s)."""
    drop.state.setTime(float(t))
    drop.coordinate.setValue(drop.state, drop.radius - float(delta))
    drop.coordinate.setSpeedValue(drop.state, -float(delta_dot))


def static_penetration(mass, radius, stiffness, gravity, force):
    """Deformation (m) at which the engine's contact force carries ``m g + F``, found by root search.

    The engine's acceleration of the resting ball (``realizeAcceleration`` at zero speed) is
    zeroed by Brent's method; the prediction is ``(m a / k)^(2/3)``.
    """
    drop = build_drop(mass, radius, stiffness, 0.0, gravity, force)
    predicted = (mass * (gravity + force / mass) / stiffness) ** (2.0 / 3.0)

    def acceleration(delta):

        set_state(drop, 0.0, delta, 0.0)
        drop.model.realizeAcceleration(drop.state)
        return drop.coordinate.getAccelerationValue(drop.state)

    from scipy.optimize import brentq  # here: importing scipy.optimize takes a while

    lo, hi = (predicted * s for s in STATIC_BRACKET)
    return brentq(acceleration, lo, hi, xtol=1e-16 * predicted, rtol=1e-15)


def integrate(drop, times, accuracy=ACCURACY, stop=None):
    """Integrate the model from its current state through report ``times`` with OpenSim's Manager.

    ``stop(delta, delta_dot)``, if given, is asked after each report; the run ends at the first
    report where it is true (that report included).  ``drop.state`` is left at the last report.
    """
    osim = _opensim()
    manager = osim.Manager(drop.model)
    manager.setIntegratorMethod(osim.Manager.IntegratorMethod_RungeKuttaMerson)
    manager.setIntegratorAccuracy(float(accuracy))
    manager.initialize(drop.state)
    rows = np.empty((len(times), 3))
    n = 0
    start = time.perf_counter()
    for t in times:
        s = manager.integrate(float(t))
        rows[n] = s.getTime(), drop.radius - drop.coordinate.getValue(s), -drop.coordinate.getSpeedValue(s)
        n += 1
        if stop is not None and stop(rows[n - 1, 1], rows[n - 1, 2]):
            break
    seconds = time.perf_counter() - start
    drop.state = osim.State(s)  # a copy: the Manager owns s and frees it with itself
    return Samples(rows[:n, 0], rows[:n, 1], rows[:n, 2], seconds)


def report_times(t0, mass, stiffness, approach_speed, window=WINDOW_TSTAR, per_tstar=SAMPLES_PER_TSTAR):
    """Report times after ``t0`` covering ``window`` scaled time units of one impact."""
    ts = float(time_scale(mass, stiffness, approach_speed))
    n = int(math.ceil(window * per_tstar))
    return t0 + ts * window * np.arange(1, n + 1) / n


@dataclass(frozen=True)
class OpenSimSettings:
    """Settings of an OpenSim drop: the workflow's ``engines.opensim`` section.

    ``accuracy`` of OpenSim's Runge-Kutta-Merson integrator, report times ``per_tstar`` scaled
    time unit t*, and the ``window`` (in t*) of one measured impact.
    """

    accuracy: float = ACCURACY
    per_tstar: int = SAMPLES_PER_TSTAR
    window: float = WINDOW_TSTAR


class OpenSimAdapter(Adapter):
    """Simbody's ``HuntCrossleyForce`` through OpenSim: the engine adapter (``adapters.contract``).

    The law is Hunt-Crossley with n = 3/2; its damping parameter is alpha, and the engine's
    parameters are ``dissipation`` (s/m) and the ``stiffness`` (Pa) of each of the two geometries
    (``contactalpha.adapters.engine_conventions``).
    """

    name = "opensim"
    law = get_law("hunt_crossley")
    module = LOADER.module
    settings = OpenSimSettings()
    # Units of ``parameters``.
    units = {"dissipation": "s/m", "stiffness": "Pa"}
    # The block's names and units in words (printed under its parameters by the front door).
    unit_notes = (
        "dissipation c in s/m: f = k delta^1.5 (1 + 1.5 c delta_dot); a constant, so it holds at",
        "  this approach speed only",
        "stiffness in Pa is Simbody's per-geometry modulus-like number, neither Young's modulus nor E*:",
        "  give it to both the sphere and the half space; Simbody combines two as E_i / 2^1.5 and",
        "  uses k = (4/3) sqrt(R) E, so E_i = 3 k / sqrt(2 R) = 2^1.5 E* (Hertz's E*, hertz_stiffness)",
    )

    def version(self):
        """OpenSim's version string."""
        return version()

    def parameters(self, damping, scene, settings=None):
        """``dissipation`` c = 2 alpha / (3 v_minus), s/m, and each geometry's ``stiffness``, Pa.

        The stiffness needs the sphere's radius: without one (``scene.radius`` None) it is left out.
        ``scene`` holds checked values (a ``DropScene``, or the front door's scene).
        """
        out = {"dissipation": opensim_dissipation_unchecked(check_alpha(damping), scene.approach_speed)}
        if scene.radius is not None:
            out["stiffness"] = opensim_stiffness_unchecked(scene.stiffness, scene.radius)
        return out

    def build_drop(self, scene, params, settings):
        """The OpenSim model with the ball at touchdown, moving at the approach speed."""
        s = scene
        drop = build_drop(s.mass, s.radius, s.stiffness, params["dissipation"], s.gravity, s.force)
        set_state(drop, 0.0, 0.0, s.approach_speed)
        return drop

    def run(self, model, scene, settings):
        """Integrate over ``settings.window`` t*; the touchdown state heads the samples."""
        v = scene.approach_speed
        times = report_times(0.0, scene.mass, scene.stiffness, v, settings.window, settings.per_tstar)
        samples = integrate(model, times, settings.accuracy)
        t = np.concatenate([[0.0], samples.t])
        d = np.concatenate([[0.0], samples.delta])
        dd = np.concatenate([[v], samples.delta_dot])
        return Samples(t, d, dd, samples.seconds, samples.extra)

    def static_penetration(self, scene):
        """Deformation (m) at which OpenSim's contact carries the load at rest (``static_penetration``)."""
        return static_penetration(scene.mass, scene.radius, scene.stiffness, scene.gravity, scene.force)

    def timestep(self, settings):
        """None: OpenSim's integrator controls its error."""
        return None


ADAPTER = OpenSimAdapter()
ENGINE = Engine(adapter=ADAPTER, loader=LOADER, step_map=None, model_file=None, batched=None)


def drop_impact(
    mass,
    radius,
    stiffness,
    approach_speed,
    dissipation,
    gravity,
    force,
    *,
    accuracy=ACCURACY,
    window=WINDOW_TSTAR,
    per_tstar=SAMPLES_PER_TSTAR,
):
    """One impact in OpenSim: the ball starts at touchdown at ``approach_speed``.

    ``Samples.extra["separated_later"]`` tells whether the ball left the ground anywhere in the
    window after a non-separating end (it must not).

    Returns
    -------
    (MeasuredImpact, Samples)
    """
    scene = DropScene(mass, stiffness, approach_speed, gravity, force, radius)
    settings = OpenSimSettings(accuracy, per_tstar, window)
    samples = ADAPTER.run(ADAPTER.build_drop(scene, {"dissipation": dissipation}, settings), scene, settings)
    return ADAPTER.measure(samples, scene), samples


# Fields of one contact of ``bounce``: name -> (units, meaning).
BOUNCE_FIELDS = {
    "t_touch": ("s", "touchdown, located on the engine's samples"),
    "t_end": ("s", "end of the contact (separation, or the speed's return to 0)"),
    "v_in": ("m/s", "approach speed predicted from the flight before (sets the dissipation)"),
    "v_in_measured": ("m/s", "approach speed read at the located touchdown"),
    "xi": ("1", "influence factor of m a at v_in (Eq. 10)"),
    "alpha": ("1", "damping factor (3/2) c v_in that the engine applies"),
    "dissipation": ("s/m", "OpenSim dissipation c = 2 alpha / (3 v_in) of this contact"),
    "eps": ("1", "Stronge's restitution measured in the engine"),
    "e_n": ("1", "Newton's restitution measured in the engine"),
    "separated": ("1", "1 if the ball left the ground"),
    "seconds": ("s", "wall-clock time of the engine's integration"),
}


def bounce(
    scene,
    model="exact",
    *,
    per_impact=True,
    accuracy=ACCURACY,
    per_tstar=SAMPLES_PER_TSTAR,
    window=WINDOW_TSTAR,
    settle=200,
):
    """The bouncing ball of Sect. 6, case A, in OpenSim, with alpha per impact.

    Each contact's dissipation is ``c = 2 alpha / (3 v_in)`` with alpha from ``model`` at that
    contact's influence factor (``scene.influence(v_in)``, as the package's own simulation's case A).
    A contact is integrated report by report until the ball is seen in flight; the model is then
    rebuilt with the next contact's ``c`` and the state carried over.  The flight is run in one
    call to just before the predicted touchdown, ``v_in = sqrt(w^2 + 2 a h)`` for upward speed
    ``w`` at height ``h`` above touchdown, and the contact with fine reports after it.  A contact
    that ends without separation ends the bouncing; the run then continues to ``scene.t_end`` with
    ``settle`` reports to check that the ball stays on the ground.

    Parameters
    ----------
    scene : contactalpha.scene.ball.Scene
    model : str
        Name of an alpha model (``contactalpha.models.MODELS``).
    per_impact : bool
        False keeps the first contact's ``c`` for every contact, as an engine user who sets the
        dissipation once would (its alpha then drifts as ``(3/2) c v_in``).

    Returns
    -------
    dict
        ``contacts`` (dict of arrays, ``BOUNCE_FIELDS``), ``count`` (contacts begun, the final
        one included), ``rebounds``, ``rest_time`` (end of the final contact, s; NaN if the ball
        still bounces at ``scene.t_end``), ``left_ground_after_rest`` (bool), ``rest_delta`` (m,
        the deformation at ``scene.t_end``), ``seconds``.
    """
    a = scene.accel
    rows: dict[str, list[float]] = {name: [] for name in BOUNCE_FIELDS}
    t, d, dd, v_in = 0.0, 0.0, scene.approach_speed, scene.approach_speed
    rest_time, seconds = np.nan, 0.0
    while t < scene.t_end:
        if per_impact or not rows["alpha"]:
            c = float(opensim_dissipation(models.alpha(scene.eps, scene.influence(v_in), model=model), v_in))
        alpha = float(opensim_alpha(c, v_in))
        drop = build_drop(scene.mass, scene.radius, scene.stiffness, c, scene.gravity, scene.force)
        set_state(drop, t, d, dd)
        ts = float(time_scale(scene.mass, scene.stiffness, v_in))
        head = Samples(np.array([t]), np.array([d]), np.array([dd]))
        if d < 0.0:  # in flight: run to half a t* before the predicted touchdown
            t_touch = t + (-dd + v_in) / a
            head = integrate(drop, [max(t, t_touch - 0.5 * ts)], accuracy)
            seconds += head.seconds
        state = {"max": False}

        def seen_in_flight(delta, delta_dot, state=state):
            state["max"] |= delta > 0.0 and delta_dot <= 0.0
            return state["max"] and delta < 0.0

        times = report_times(float(head.t[-1]), scene.mass, scene.stiffness, v_in, window, per_tstar)
        body = integrate(drop, times, accuracy, stop=seen_in_flight)
        seconds += body.seconds
        tt = np.concatenate([head.t, body.t])
        res = measure_impact(
            tt, np.concatenate([head.delta, body.delta]), np.concatenate([head.delta_dot, body.delta_dot]), a
        )
        for name, value in (
            ("t_touch", res.t_touch),
            ("t_end", res.t_end),
            ("v_in", v_in),
            ("v_in_measured", res.approach_speed),
            ("xi", scene.influence(v_in)),
            ("alpha", alpha),
            ("dissipation", c),
            ("eps", res.eps),
            ("e_n", res.e_n),
            ("separated", float(res.separated)),
            ("seconds", head.seconds + body.seconds),
        ):
            rows[name].append(value)
        if not res.separated:
            rest_time = res.t_end
            break
        t, d, dd = float(body.t[-1]), float(body.delta[-1]), float(body.delta_dot[-1])
        v_in = math.sqrt(dd * dd + 2.0 * a * -d)
    contacts = {k: np.asarray(v, dtype=float) for k, v in rows.items()}
    left, rest_delta = False, np.nan
    if np.isfinite(rest_time) and scene.t_end > drop.state.getTime():
        hold = integrate(drop, np.linspace(drop.state.getTime(), scene.t_end, settle + 1)[1:], accuracy)
        seconds += hold.seconds
        left, rest_delta = bool(np.any(hold.delta <= 0.0)), float(hold.delta[-1])
    return {
        "contacts": contacts,
        "count": int(contacts["t_touch"].size),
        "rebounds": int(np.sum(contacts["separated"])),
        "rest_time": float(rest_time),
        "left_ground_after_rest": left,
        "rest_delta": rest_delta,
        "seconds": seconds,
    }
