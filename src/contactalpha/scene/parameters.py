"""The front door: from a scene in SI units to every number an engine needs.

A simulation engineer has a mass, a Hertz stiffness, an approach speed, a constant load
(gravity plus a force) and a measured restitution, energetic (Stronge's eps) or kinematic
(Newton's e_N, what a drop test measures).  ``contact_parameters`` returns the load's influence
factor xi (paper Eq. 10), the exact alpha for that restitution at that xi, the damping
``mu = alpha k / v_minus`` of the contact law (paper Eq. 23, ``f = k delta^{3/2} + mu
delta^{3/2} delta_dot``), the end state and both restitutions of the impact that alpha gives
(one impact integrated), and the parameter of each supported engine in its own convention
(``engine_conventions``, whose ``UNIT_NOTES`` the text output prints).

The damping ``mu`` (and OpenSim's ``dissipation``) is a constant of the contact law, but the
alpha it stands for is ``mu v_minus / k``: it delivers the requested restitution at this approach
speed only.  So the parameters also carry the e_N the same ``mu`` delivers at half and at twice
the approach speed (one impact each, the load's xi at that speed): a drop from another height
needs its own ``mu``.
"""

import math
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.exudyn_contact import IMPACT_MODEL as EXUDYN_IMPACT_MODEL  # noqa: F401
from contactalpha.adapters.registry import check_radius_used, engine_parameters
from contactalpha.engine.driver import frozen_instance, impact
from contactalpha.engine.scaling import influence_factor, length_scale
from contactalpha.engine.solver import no_kinematic_inverse, solve_alpha
from contactalpha.engine.table import EPS_MIN, XI_MAX, alpha_tabulated
from contactalpha.laws import DEFAULT_LAW, get_law
from contactalpha.validation import PLAIN_FLOATS, check_scalar

from contactalpha.adapters.engine_conventions import UNIT_NOTES
from .law_scene import law_contact_parameters

# Approach speeds, as factors of the given one, at which the fixed damping mu is checked.
SPEED_FACTORS = (0.5, 2.0)

# The contact law this front door solves for (Hunt-Crossley, n = 3/2).
LAW = DEFAULT_LAW


@dataclass(frozen=True)
class _EngineScene:
    """What an adapter's ``parameters`` reads of a scene (``radius`` may be None)."""

    mass: float
    stiffness: float
    approach_speed: float
    radius: object


@dataclass(frozen=True)
class ContactParameters:
    """Everything ``contact_parameters`` derives for one contact (SI units).

    Attributes
    ----------
    xi : influence factor of the load (Eq. 10), in [0, 1).
    alpha : exact hysteresis damping factor for the requested restitution at ``xi``.
    damping : ``mu = alpha k / v_minus``, N s / m^2.5 (paper Eq. 23).
    end_state : how the impact with ``alpha`` ends: separation, nonseparation, creep, no_restitution.
    eps, e_n : Stronge's energetic and Newton's kinematic restitution of that impact (one of them
        is the requested value to the solver's tolerance, or to the table's ~1e-7 in alpha).
    accel : relative acceleration of the load, m/s^2.
    delta_star : maximum compression of the undamped unloaded contact, m (the length scale).
    alpha_source : "table" (shipped exact table) or "solver" (outside the table's domain).
    e_n_half_speed, e_n_twice_speed : Newton's e_N that the same ``damping`` mu (the same OpenSim
        ``dissipation``) delivers at half and at twice the approach speed (NaN where the load's
        xi rounds to 1 at half the speed).  Exudyn's parameters scale with each impact's speed.
    engines : parameters per engine, each in its own names and units:
        ``opensim`` (Simbody ``HuntCrossleyForce``): ``dissipation`` c in s/m, and ``stiffness``
        E in Pa of each of the two geometries (only when a sphere radius is given);
        ``exudyn`` (``ObjectContactSphereSphere``): ``contactStiffness``,
        ``contactStiffnessExponent``, ``impactModel``, ``restitutionCoefficient``,
        ``contactDamping``, ``minimumImpactVelocity``.
    """

    xi: float
    alpha: float
    damping: float
    end_state: str
    eps: float
    e_n: float
    accel: float
    delta_star: float
    alpha_source: str
    engines: dict[str, dict[str, float]]
    e_n_half_speed: float
    e_n_twice_speed: float


def _positive(name, value):
    if type(value) in PLAIN_FLOATS and 0.0 < value < math.inf:
        return value
    return check_scalar(name, value, 0.0, math.inf, lo_open=True, hi_open=True)


def scene_accel(mass: float, accel: float | None = None, force: float | None = None) -> float:
    """Relative acceleration of the load from exactly one of ``accel`` (m/s^2) and ``force`` (N)."""
    if (accel is None) == (force is None):
        raise ValueError(
            f"give exactly one of accel (m/s^2) and force (N); got accel = {accel!r}, force = {force!r}"
        )
    name, value = ("accel", accel) if force is None else ("force", force)
    assert value is not None  # exactly one of them is given (checked above)
    if not (type(value) in PLAIN_FLOATS and 0.0 <= value < math.inf):
        value = check_scalar(name, value, 0.0, np.inf, hi_open=True)
    return value if force is None else value / mass


def _target(eps, e_n):
    """``(value, restitution)`` from exactly one of ``eps`` and ``e_N``, checked."""
    if (eps is None) == (e_n is None):
        raise ValueError(
            f"give exactly one of eps (energetic) and e_N (kinematic); got eps = {eps!r}, e_N = {e_n!r}"
        )
    if e_n is None:
        if not (type(eps) in PLAIN_FLOATS and 0.0 <= eps <= 1.0):
            eps = check_scalar("eps", eps, 0.0, 1.0)
        return eps, "energetic"
    if not (type(e_n) in PLAIN_FLOATS and 0.0 <= e_n <= 1.0):
        e_n = check_scalar("e_N", e_n, 0.0, 1.0)
    if e_n == 0.0:
        raise no_kinematic_inverse()
    return e_n, "kinematic"


def _alpha(value, xi, restitution):
    """``(alpha, source)``: the shipped table inside its domain, the solver outside it."""
    if EPS_MIN <= value <= 1.0 and xi <= XI_MAX:
        return alpha_tabulated(value, xi, restitution=restitution), "table"
    sol = solve_alpha(value, xi, restitution=restitution)
    if not sol.ok:
        raise RuntimeError(f"exact alpha not found at {restitution} {value!r}, xi = {xi!r}: {sol.status}")
    return sol.alpha, "solver"


def contact_parameters(
    eps: float | None = None,
    mass: float | None = None,
    stiffness: float | None = None,
    approach_speed: float | None = None,
    *,
    e_N: float | None = None,  # noqa: N803  (Newton's e_N, as the paper and the issue write it)
    accel: float | None = None,
    force: float | None = None,
    radius: float | None = None,
    law: str | None = None,
) -> ContactParameters:
    """Contact parameters of one impact, in SI units, from the scene and a measured restitution.

    Parameters
    ----------
    eps : float, optional
        Stronge's energetic restitution, 0 <= eps <= 1 (eps = 0 only with a load).
    mass : float
        Effective mass m_e, kg (> 0).
    stiffness : float
        Hertz stiffness k, N/m^1.5 (> 0).
    approach_speed : float
        Approach speed v_minus, m/s (> 0).
    e_N : float, optional
        Newton's kinematic restitution (separation speed / approach speed), 0 < e_N <= 1.
        Give exactly one of ``eps`` and ``e_N``.
    accel, force : float
        Give one: the constant acceleration pressing the bodies together (m/s^2, >= 0; gravity
        included if it acts), or the constant force (N, >= 0; ``accel = force / mass``).
    radius : float, optional
        Radius of a sphere meeting a half space, m (> 0): adds OpenSim's ``stiffness``.
    law : str or ContactLaw, optional
        The contact law (``contactalpha.laws``); default Hunt-Crossley n = 3/2.  Another law
        returns ``scene.law_scene.LawParameters``, with ``stiffness`` in that law's units.

    Returns
    -------
    ContactParameters
        Or, when any input is an array, ``scene.batched.BatchedParameters`` (any ``law``): every
        engine's parameters as arrays over the broadcast scenes (the law's fast evaluator, no
        impact integrated).

    Raises
    ------
    ValueError
        Naming the value and its valid range, for bad or non-physical input (also a load so
        large for the approach speed that xi rounds to 1, and e_N = 0, which many alpha give).
    RuntimeError
        If the solver fails outside the table's domain (never a plausible wrong number).
    """
    if _batch(eps, mass, stiffness, approach_speed, e_N, accel, force, radius):
        return _batched(eps, mass, stiffness, approach_speed, e_N, accel, force, radius, law)
    value, restitution = _target(eps, e_N)
    for name, given in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed)):
        if given is None:
            raise ValueError(f"{name} is required (SI units)")
    m = _positive("mass", mass)
    k = _positive("stiffness", stiffness)
    v = _positive("approach_speed", approach_speed)
    a = scene_accel(m, accel, force)
    if law is not None and get_law(law).name != DEFAULT_LAW:
        check_radius_used(law, radius)
        return law_contact_parameters(law, value, restitution, m, k, v, a)
    xi = influence_factor(m, k, v, a)
    if restitution == "energetic" and value == 0.0 and xi == 0.0:
        raise ValueError("eps = 0.0 needs a load: without one alpha -> infinity; give accel or force > 0")
    alpha, source = _alpha(value, xi, restitution)
    r = impact(alpha, xi)
    if r.status != "ok":
        raise RuntimeError(f"impact at alpha = {alpha!r}, xi = {xi!r} failed: {r.status}")
    sphere = None if radius is None else _positive("radius", radius)
    engines = engine_parameters(LAW, alpha, _EngineScene(m, k, v, sphere))
    e_n_half, e_n_twice = (_fixed_damping_e_n(alpha, m, k, v, a, factor) for factor in SPEED_FACTORS)
    return frozen_instance(
        ContactParameters,
        xi=xi,
        alpha=alpha,
        damping=alpha * k / v,
        end_state=r.state,
        eps=r.eps,
        e_n=r.e_n,
        accel=a,
        delta_star=float(length_scale(m, k, v)),
        alpha_source=source,
        engines=engines,
        e_n_half_speed=e_n_half,
        e_n_twice_speed=e_n_twice,
    )


def _batch(*values):
    """True when any input is an array (or a list) of more than a plain number."""
    return any(v is not None and type(v) not in PLAIN_FLOATS and np.ndim(v) > 0 for v in values)


def _batched(eps, mass, stiffness, approach_speed, e_n, accel, force, radius, law):
    """Arrays of scenes: ``scene.batched.batched_parameters`` (see there)."""
    from contactalpha.scene.batched import batched_parameters

    if (eps is None) == (e_n is None):
        raise ValueError("give exactly one of eps (energetic) and e_N (kinematic) arrays")
    if (accel is None) == (force is None):
        raise ValueError("give exactly one of accel (m/s^2) and force (N) arrays")
    a = accel if force is None else np.asarray(force, dtype=float) / np.asarray(mass, dtype=float)
    target, restitution = (e_n, "kinematic") if eps is None else (eps, "energetic")
    return batched_parameters(
        mass, stiffness, approach_speed, a, target, restitution=restitution, law=law or LAW, radius=radius
    )


def _fixed_damping_e_n(alpha, mass, stiffness, speed, accel, factor):
    """Newton's e_N of an impact at ``factor`` times ``speed`` with the same damping ``mu = alpha k / v``."""
    try:
        xi = influence_factor(mass, stiffness, speed * factor, accel)
    except ValueError:  # the load's xi rounds to 1 at that speed: no impact to speak of
        return math.nan
    r = impact(alpha * factor, xi)
    return float(r.e_n) if r.status == "ok" else math.nan


def format_parameters(cp: ContactParameters) -> str:
    """``ContactParameters`` as aligned text lines (the command line's output)."""
    lines = [
        f"xi              {cp.xi:.15g}",
        f"alpha           {cp.alpha:.15g}   ({cp.alpha_source})",
        f"damping mu      {cp.damping:.15g} N s/m^2.5",
        f"end state       {cp.end_state}",
        f"eps             {cp.eps:.15g}",
        f"e_N             {cp.e_n:.15g}",
        f"accel           {cp.accel:.15g} m/s^2",
        f"delta_star      {cp.delta_star:.15g} m",
    ]
    lines.append(
        f"the same mu delivers e_N = {cp.e_n_half_speed:.6g} at half and {cp.e_n_twice_speed:.6g} at twice "
        "this approach speed: it holds at this speed only"
    )
    for engine, values in cp.engines.items():
        for name, value in values.items():
            lines.append(f"{engine + '.' + name:32s} {value:.15g}")
        lines.extend(f"  {line}" for line in UNIT_NOTES.get(engine, ()))
    return "\n".join(lines)
