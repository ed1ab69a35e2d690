"""The front door: from a scene in SI units to every number an engine needs.

A simulation engineer has a mass, a Hertz stiffness, an approach speed, a constant load
(gravity plus a force) and a measured restitution, energetic (Stronge's eps) or kinematic
(Newton's e_N, what a drop test measures).  ``contact_parameters`` returns the load's influence
factor xi (paper Eq. 10), the exact alpha for that restitution at that xi, the damping
``mu = alpha k / v_minus`` of the contact law (paper Eq. 23, ``f = k delta^{3/2} + mu
delta^{3/2} delta_dot``), the end state and both restitutions of the impact that alpha gives
(one impact integrated), and the parameter of each supported engine in its own convention
(``engine_conventions``).
"""

import math
from dataclasses import dataclass

import numpy as np

from contactalpha.engine.driver import frozen_instance, impact
from contactalpha.engine.scaling import influence_factor, length_scale
from contactalpha.engine.solver import no_kinematic_inverse, solve_alpha
from contactalpha.engine.table import EPS_MIN, XI_MAX, alpha_tabulated
from contactalpha.validation import PLAIN_FLOATS, check_scalar

from .engine_conventions import exudyn_restitution_input, opensim_dissipation, opensim_stiffness

# Exudyn's impact model whose built-in mapping covers every alpha > 0 (see engine_conventions).
EXUDYN_IMPACT_MODEL = 2


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
    engines: dict


def _positive(name, value):
    if type(value) in PLAIN_FLOATS and 0.0 < value < math.inf:
        return value
    return check_scalar(name, value, 0.0, math.inf, lo_open=True, hi_open=True)


def scene_accel(mass, accel=None, force=None):
    """Relative acceleration of the load from exactly one of ``accel`` (m/s^2) and ``force`` (N)."""
    if (accel is None) == (force is None):
        raise ValueError(
            f"give exactly one of accel (m/s^2) and force (N); got accel = {accel!r}, force = {force!r}"
        )
    name, value = ("accel", accel) if force is None else ("force", force)
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
    eps=None,
    mass=None,
    stiffness=None,
    approach_speed=None,
    *,
    e_N=None,  # noqa: N803  (Newton's e_N, as the paper and the issue write it)
    accel=None,
    force=None,
    radius=None,
):
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

    Returns
    -------
    ContactParameters

    Raises
    ------
    ValueError
        Naming the value and its valid range, for bad or non-physical input (also a load so
        large for the approach speed that xi rounds to 1, and e_N = 0, which many alpha give).
    RuntimeError
        If the solver fails outside the table's domain (never a plausible wrong number).
    """
    value, restitution = _target(eps, e_N)
    for name, given in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed)):
        if given is None:
            raise ValueError(f"{name} is required (SI units)")
    m = _positive("mass", mass)
    k = _positive("stiffness", stiffness)
    v = _positive("approach_speed", approach_speed)
    a = scene_accel(m, accel, force)
    xi = influence_factor(m, k, v, a)
    if restitution == "energetic" and value == 0.0 and xi == 0.0:
        raise ValueError("eps = 0.0 needs a load: without one alpha -> infinity; give accel or force > 0")
    alpha, source = _alpha(value, xi, restitution)
    r = impact(alpha, xi)
    if r.status != "ok":
        raise RuntimeError(f"impact at alpha = {alpha!r}, xi = {xi!r} failed: {r.status}")
    engines = {
        "opensim": {"dissipation": opensim_dissipation(alpha, v)},
        "exudyn": {
            "contactStiffness": k,
            "contactStiffnessExponent": 1.5,
            "impactModel": EXUDYN_IMPACT_MODEL,
            "restitutionCoefficient": exudyn_restitution_input(alpha, EXUDYN_IMPACT_MODEL),
            "contactDamping": 0.0,
            "minimumImpactVelocity": 0.0,
        },
    }
    if radius is not None:
        engines["opensim"]["stiffness"] = opensim_stiffness(k, _positive("radius", radius))
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
    )


def format_parameters(cp):
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
    for engine, values in cp.engines.items():
        for name, value in values.items():
            lines.append(f"{engine + '.' + name:32s} {value:.15g}")
    return "\n".join(lines)
