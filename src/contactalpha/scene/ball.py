"""The bouncing ball of the paper's Sect. 6: repeated impacts under a constant force.

A ball (mass ``m``, radius ``R``, Hertz stiffness ``k``) is pushed onto rigid
ground by gravity ``g`` and a constant force ``F``; the deformation is
``delta = R - y`` (Eq. 42) and the constant acceleration is ``a = g + F/m``.

- **Flight** (``delta < 0``): ``delta'' = a``, an exact parabola.  A ball that
  leaves the ground with speed ``u`` lands again after ``2 u / a`` with speed
  ``u``, so flights need no integrator.
- **Contact** (``delta >= 0``): one impact of the jitted engine
  (``kernel.impact_kernel``) in the scaling of that impact's approach speed
  ``v`` (docs/science.md, "Scaling"), converted back with ``length_scale`` and
  ``time_scale``.  Case A keeps the external forces, Eq. 24: scaled load
  ``A = a delta* / v^2``, and alpha comes from the model at this impact's
  influence factor ``xi(m, k, v, a)`` (Eq. 10).  Case B drops them during
  contact, Eq. 43: ``A = 0``, and alpha comes from the same model at
  ``xi = 0`` -- the model as it would be used by someone who ignores the
  external forces; a model that ignores xi anyway gives the same alpha in
  both cases.
- **End**: a contact that does not separate (nonseparation, creep, no
  restitution) ends the bouncing for good.  Proof for case A: the scaled
  energy ``e = v^2/2 + x^{5/2}/2 - A x`` never grows (the damping power
  ``5/4 alpha x^{3/2} v^2`` is >= 0); a contact that ends without separation
  stops at ``0 < x_e <= x_eq`` where ``e < 0``, whereas leaving the ground needs
  ``x = 0`` and ``e = v^2/2 >= 0``.  The ball then settles at the static
  deformation ``delta_eq = (m a / k)^{2/3}``.  Case B (``A = 0``) always
  separates, with the same velocity ratio at every impact: it never comes to
  rest, and only the time limit ends it.

Energy ledger (all in J, heights from the ground): kinetic ``m ydot^2 / 2``,
elastic ``2/5 k delta^{5/2}``, gravity potential ``m g y`` and the potential
of ``F``, ``F y`` (so the work of ``F`` is minus its change).  Flights keep
the total constant exactly.  In case A a contact lowers it by the damping work
only.  In case B the contact equation leaves out ``m a``, so inside a contact
the total also dips by ``m a delta``; that term is zero again at separation,
so every separating contact of case B also lowers the total by its damping
work only.  The damping work per contact is computed here from the scaled
energy identity (docs/science.md, "The restitution identity");
``damping_work_reference`` integrates
it independently with SciPy along the contact, for the tests.
"""

from dataclasses import dataclass, field

import numpy as np

from contactalpha import models
from contactalpha.engine.codes import (
    END_STATES,
    N_REC,
    NO_RESTITUTION,
    NONSEPARATION,
    OUT_EPS2,
    OUT_STATE,
    OUT_STATUS,
    OUT_STEPS,
    OUT_T_END,
    OUT_V_END,
    OUT_X_END,
    OUT_X_MAX,
    REC_T,
    REC_V,
    REC_X,
    SEPARATION,
    STATUS,
)
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL
from contactalpha.engine.kernel import impact_kernel
from contactalpha.engine.scaling import influence_factor, length_scale, time_scale
from contactalpha.validation import check_range, check_scalar, check_tolerances

# Standard gravity, m/s^2; the paper does not state its value.
GRAVITY = 9.81
# Cap on the scaled time step inside a contact, so recorded contact paths are
# smooth enough to plot (a contact lasts about 3.3 scaled time units).
CONTACT_MAX_STEP = 0.02
# Rows reserved for one recorded contact path; ample for CONTACT_MAX_STEP.
CONTACT_MAX_ROWS = 200_000
# Samples of each flight parabola in the time series (flights are exact, so
# this only sets how smooth the plotted curve is).
FLIGHT_SAMPLES = 40


@dataclass(frozen=True)
class ContactNumerics:
    """Integrator settings of every contact (``simulate``'s defaults; the ``ball.numerics`` section)."""

    rtol: float = RTOL
    atol: float = ATOL
    max_step: float = CONTACT_MAX_STEP
    flight_samples: int = FLIGHT_SAMPLES


# Guard against a runaway loop; case B at the default time limit needs ~100.
MAX_COLLISIONS = 100_000
# Cases of the paper's Fig. 11: A keeps the external forces in the contact
# equation (Eq. 24), B leaves them out (Eq. 43).
CASES = ("A", "B")
# End states of a run.
RESTS = "rests"
BOUNCING = "bouncing at time limit"
FAILED = "failed"
# Phase codes of the time series.
FLIGHT = 0
CONTACT = 1


@dataclass(frozen=True)
class Scene:
    """The bouncing-ball scene of Sect. 6, validated.

    Attributes
    ----------
    mass : kg, > 0 (paper: 0.5).
    radius : m, > 0 (paper: 0.08).
    stiffness : Hertz stiffness k, N/m^1.5, > 0 (paper: 1.4e8).
    approach_speed : first approach speed, m/s, > 0 (paper: 0.5).
    force : constant force F pushing the ball down, N, >= 0.
    eps : restitution coefficient asked of the model, in (0, 1].
    gravity : m/s^2, >= 0; ``g + F/m`` must be > 0 so the ball comes back.
    t_end : time limit of a run, s, > 0.
    """

    mass: float = 0.5
    radius: float = 0.08
    stiffness: float = 1.4e8
    approach_speed: float = 0.5
    force: float = 5.1
    eps: float = 0.8
    gravity: float = GRAVITY
    t_end: float = 0.3

    def __post_init__(self):
        # Each field one real number (a bool, text or a list is refused), kept as a float.
        ranges = {
            "mass": (0.0, np.inf, True, True),
            "radius": (0.0, np.inf, True, True),
            "stiffness": (0.0, np.inf, True, True),
            "approach_speed": (0.0, np.inf, True, True),
            "force": (0.0, np.inf, False, True),
            "eps": (0.0, 1.0, True, False),
            "gravity": (0.0, np.inf, False, True),
            "t_end": (0.0, np.inf, True, True),
        }
        for name, (lo, hi, lo_open, hi_open) in ranges.items():
            value = check_scalar(name, getattr(self, name), lo, hi, lo_open=lo_open, hi_open=hi_open)
            object.__setattr__(self, name, value)
        if self.accel <= 0.0:
            raise ValueError(
                f"g + F/m = {self.accel!r} is outside the valid range (0, inf): the ball would not return"
            )

    @property
    def accel(self):
        """Constant acceleration ``a = g + F/m`` towards the ground, m/s^2."""
        return float(self.gravity + self.force / self.mass)

    @property
    def rest_deformation(self):
        """Static deformation ``delta_eq = (m a / k)^{2/3}`` of the resting ball, m."""
        return (self.mass * self.accel / self.stiffness) ** (2.0 / 3.0)

    def influence(self, speed):
        """Influence factor xi of the load ``m a`` on an impact at approach ``speed`` (Eq. 10)."""
        return influence_factor(self.mass, self.stiffness, speed, self.accel)


@dataclass
class BallRun:
    """A simulated run; physical units throughout.

    Attributes
    ----------
    scene, model, case : what was run.
    t, delta, ddelta : time series (s, m, m/s) of the deformation ``R - y``
        and its rate; flights are sampled, contacts are the engine's steps.
    phase : FLIGHT or CONTACT per sample; ``collision``: 0-based index of the
        contact a sample belongs to or follows.
    collisions : dict of per-contact arrays (see ``COLLISION_FIELDS``).
    end_state : RESTS, BOUNCING or FAILED; ``end_time`` when it was reached
        (``inf`` when the last contact creeps to rest); ``status`` the
        engine's status of the last contact.
    """

    scene: Scene
    model: str
    case: str
    t: np.ndarray
    delta: np.ndarray
    ddelta: np.ndarray
    phase: np.ndarray
    collision: np.ndarray
    collisions: dict = field(default_factory=dict)
    end_state: str = FAILED
    end_time: float = np.nan
    status: str = "ok"

    @property
    def count(self):
        """Number of contacts begun before the time limit (the final, non-separating one included)."""
        return int(self.collisions["t_start"].size)

    @property
    def rebounds(self):
        """Number of contacts that ended with the ball leaving the ground."""
        return int(np.sum(self.collisions["state"] == SEPARATION))


# Per-contact fields of ``BallRun.collisions``: name -> (units, meaning).
COLLISION_FIELDS = {
    "t_start": ("s", "time the contact begins"),
    "t_stop": ("s", "time the contact ends (inf: creeps to rest)"),
    "v_in": ("m/s", "approach speed"),
    "xi": ("1", "influence factor of m a at this approach speed (Eq. 10)"),
    "alpha": ("1", "damping factor given by the model"),
    "A": ("1", "scaled load in the contact equation (0 in case B)"),
    "eps_post": ("1", "Stronge's restitution of the contact as integrated (Eq. 17)"),
    "state": ("1", "end-state code of the contact (impact.END_STATES)"),
    "status": ("1", "engine status code (impact.STATUS; 0 = ok)"),
    "v_out": ("m/s", "rebound speed (0 without separation)"),
    "delta_max": ("m", "maximum deformation"),
    "delta_end": ("m", "deformation at the end of the contact"),
    "energy_in": ("J", "total energy when the contact begins"),
    "energy_out": ("J", "total energy when the contact ends"),
    "damping_work": ("J", "damping work of the contact, from the scaled energy identity"),
    "steps": ("1", "integrator steps"),
}


def energy_terms(scene, delta, ddelta, case="A", in_contact=None):
    """Energy ledger of states ``(delta, ddelta)``, J.

    Parameters
    ----------
    scene : Scene
    delta, ddelta : array_like
        Deformation ``R - y`` (m) and its rate (m/s).
    case : "A" or "B"
        In case B the term ``m a delta`` left out of the contact equation is
        reported as ``switched_off`` for samples ``in_contact``.
    in_contact : array_like of bool, optional
        Which samples are contacts (default: ``delta > 0``).

    Returns
    -------
    dict of ndarray
        ``kinetic``, ``elastic``, ``gravity``, ``force_potential``, ``total``
        (their sum) and ``switched_off``.
    """
    d = np.asarray(delta, dtype=float)
    dd = np.asarray(ddelta, dtype=float)
    y = scene.radius - d
    pos = np.maximum(d, 0.0)
    if in_contact is None:
        in_contact = d > 0.0
    terms = {
        "kinetic": 0.5 * scene.mass * dd**2,
        "elastic": 0.4 * scene.stiffness * pos**2.5,
        "gravity": scene.mass * scene.gravity * y,
        "force_potential": scene.force * y,
    }
    terms["total"] = terms["kinetic"] + terms["elastic"] + terms["gravity"] + terms["force_potential"]
    off = scene.mass * scene.accel * pos * np.asarray(in_contact, dtype=float)
    terms["switched_off"] = off if case == "B" else np.zeros_like(off)
    return terms


def _check_case(case):
    if case not in CASES:
        raise ValueError(f"case = {case!r} is outside the valid choices {CASES}")
    return case


def contact_alpha(scene, speed, model, case):
    """Damping factor of one contact: the model at this impact's xi (case A) or at xi = 0 (case B)."""
    xi = scene.influence(speed) if _check_case(case) == "A" else 0.0
    return float(models.alpha(scene.eps, xi, model=model))


def run_contact(scene, speed, alpha, case, rtol, atol, max_step):
    """Run one contact; return the scaled path, the kernel output and the scales."""
    ds = float(length_scale(scene.mass, scene.stiffness, speed))
    ts = float(time_scale(scene.mass, scene.stiffness, speed))
    A = scene.accel * ds / speed**2 if case == "A" else 0.0
    rec = np.empty((CONTACT_MAX_ROWS, N_REC))
    out, n = impact_kernel(alpha, A, rtol, atol, MAX_STEPS, rec, max_step)
    return rec[:n], out, A, ds, ts


def _scaled_damping(A, x_e, v_e):
    """Scaled damping work ``1/2 - e_end`` of a contact (docs/science.md, "The restitution identity")."""
    return 0.5 - (0.5 * v_e**2 + 0.5 * x_e**2.5 - A * x_e)


def _flight(t0, u, a, t_limit, n):
    """Samples of the flight that leaves the ground at ``t0`` with speed ``u``, up to ``t_limit``."""
    dur = 2.0 * u / a
    tau = np.linspace(0.0, min(dur, t_limit - t0), n)
    return t0 + tau, -u * tau + 0.5 * a * tau**2, -u + a * tau, dur


def simulate(
    scene,
    model,
    case="A",
    *,
    rtol=RTOL,
    atol=ATOL,
    max_step=CONTACT_MAX_STEP,
    flight_samples=FLIGHT_SAMPLES,
):
    """Simulate the bouncing ball from its first contact until it rests or ``scene.t_end``.

    A contact that begins before ``t_end`` is always finished (so the ledger
    stays whole); a flight is cut at ``t_end``.

    Parameters
    ----------
    scene : Scene
    model : str
        Name in ``models.MODELS``; alpha is evaluated per contact.
    case : "A" or "B"
        A: Eq. 24 in contact (external forces kept); B: Eq. 43 (left out).
    rtol, atol : float
        Tolerances of the contact integrator (scaled units).
    max_step : float
        Cap on the scaled contact step, for smooth recorded paths.
    flight_samples : int
        Samples per flight parabola (>= 2).

    Returns
    -------
    BallRun
    """
    _check_case(case)
    if model not in models.MODELS:
        raise ValueError(f"unknown model {model!r}; known models: {', '.join(sorted(models.MODELS))}")
    rtol, atol = check_tolerances(rtol, atol)
    check_range("max_step", max_step, 0.0, np.inf, lo_open=True)
    if int(flight_samples) < 2:
        raise ValueError(f"flight_samples = {flight_samples!r} is outside the valid range [2, inf)")
    a = scene.accel
    series: dict[str, list[np.ndarray]] = {"t": [], "delta": [], "ddelta": [], "phase": [], "collision": []}
    rows: dict[str, list] = {name: [] for name in COLLISION_FIELDS}
    t, speed = 0.0, float(scene.approach_speed)
    end_state, end_time, status = BOUNCING, scene.t_end, "ok"
    i = 0
    while t < scene.t_end:
        if i >= MAX_COLLISIONS:
            end_state, end_time, status = FAILED, t, f"more than {MAX_COLLISIONS} collisions"
            break
        alpha = contact_alpha(scene, speed, model, case)
        path, out, A, ds, ts = run_contact(scene, speed, alpha, case, rtol, atol, max_step)
        code, stat = int(out[OUT_STATE]), int(out[OUT_STATUS])
        x_m, x_e, v_e, t_e = out[OUT_X_MAX], out[OUT_X_END], out[OUT_V_END], out[OUT_T_END]
        _append(series, t + path[:, REC_T] * ts, path[:, REC_X] * ds, path[:, REC_V] * speed, CONTACT, i)
        e_in = float(energy_terms(scene, 0.0, speed)["total"])
        e_out = float(energy_terms(scene, x_e * ds, v_e * speed)["total"])
        fields = {
            "t_start": t,
            "t_stop": t + t_e * ts,
            "v_in": speed,
            "xi": scene.influence(speed),
            "alpha": alpha,
            "A": A,
            "eps_post": np.sqrt(max(out[OUT_EPS2], 0.0)) if code != NO_RESTITUTION else 0.0,
            "state": code,
            "status": stat,
            "v_out": -v_e * speed if code == SEPARATION else 0.0,
            "delta_max": x_m * ds,
            "delta_end": x_e * ds,
            "energy_in": e_in,
            "energy_out": e_out,
            "damping_work": scene.mass * speed**2 * _scaled_damping(A, x_e, v_e),
            "steps": out[OUT_STEPS],
        }
        for name, value in fields.items():
            rows[name].append(value)
        i += 1
        if stat != 0 or code not in (SEPARATION, NONSEPARATION, 3, NO_RESTITUTION):
            end_state, end_time, status = FAILED, fields["t_stop"], STATUS.get(stat, "failed")
            break
        if code != SEPARATION:
            end_state, end_time = RESTS, fields["t_stop"]
            break
        t = fields["t_stop"]
        speed = fields["v_out"]
        if t >= scene.t_end:
            break
        ft, fd, fdd, dur = _flight(t, speed, a, scene.t_end, flight_samples)
        _append(series, ft, fd, fdd, FLIGHT, i - 1)
        t += dur
    arrays = {k: np.concatenate(v) if v else np.empty(0) for k, v in series.items()}
    return BallRun(
        scene=scene,
        model=model,
        case=case,
        t=arrays["t"],
        delta=arrays["delta"],
        ddelta=arrays["ddelta"],
        phase=arrays["phase"].astype(np.int8),
        collision=arrays["collision"].astype(np.int64),
        collisions={k: np.asarray(v, dtype=float) for k, v in rows.items()},
        end_state=end_state,
        end_time=float(end_time),
        status=status,
    )


def _append(series, t, d, dd, phase, index):
    series["t"].append(np.asarray(t, dtype=float))
    series["delta"].append(np.asarray(d, dtype=float))
    series["ddelta"].append(np.asarray(dd, dtype=float))
    series["phase"].append(np.full(np.size(t), phase))
    series["collision"].append(np.full(np.size(t), index))


def end_state_name(code):
    """Name of a contact end-state code."""
    return END_STATES[int(code)]


def damping_work_reference(alpha, A, tau_end, *, rtol=1e-12, atol=1e-14):
    """Scaled damping work of one contact by SciPy quadrature, independent of the engine.

    Integrates ``x'' = A - 5/4 x^{3/2} (1 + alpha x')`` from ``x = 0, x' = 1``
    together with ``W' = 5/4 alpha x^{3/2} x'^2`` (the damping power) with
    ``solve_ivp`` (DOP853) up to the scaled time ``tau_end``.

    Returns
    -------
    W, x, v : float
        Damping work and the state at ``tau_end``.
    """
    from scipy.integrate import solve_ivp  # lazy: 0.2-0.7 s of import in every job

    def rhs(_, s):
        x, v, _w = s
        h = 1.25 * max(x, 0.0) ** 1.5
        return [v, A - h * (1.0 + alpha * v), alpha * h * v * v]

    sol = solve_ivp(rhs, (0.0, tau_end), [0.0, 1.0, 0.0], method="DOP853", rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"reference quadrature failed: {sol.message}")
    x, v, w = sol.y[:, -1]
    return float(w), float(x), float(v)
