"""The front door: from a scene in SI units to every number an engine needs (``ContactParameters``).

A simulation engineer has a mass, a stiffness, an approach speed, a constant load (gravity plus
a force) and a measured restitution, energetic (Stronge's eps) or kinematic (Newton's e_N, what a
drop test measures).  ``contact_parameters`` returns, for the contact law asked for (default
Hunt-Crossley, n = 3/2) or the law of the engine asked for: the load factor xi (paper Eq. 10
for Hunt-Crossley), the law's exact dimensionless damping for that restitution at that xi, its
physical damping, the end state and both restitutions of the impact it gives (one impact
integrated), and the parameters of each engine of the law in its own names and units.  One
result type for every law and for batches: ``scene.result.ContactParameters``.

The physical damping (and OpenSim's ``dissipation``) is a constant of the contact law, but for
the Hunt-Crossley laws the alpha it stands for is ``d v_minus``: it delivers the requested
restitution at this approach speed only.  So the parameters also carry the e_N the same physical
damping delivers at half and at twice the approach speed (one impact each, the load's xi at that
speed): a drop from another height needs its own damping.
"""

import math
import warnings

import numpy as np

from contactalpha.adapters.exudyn_contact import IMPACT_MODEL as EXUDYN_IMPACT_MODEL  # noqa: F401
from contactalpha.adapters.registry import adapter, check_radius_used, engine_parameters
from contactalpha.engine.driver import frozen_instance, impact_unchecked
from contactalpha.engine.scaling import influence_factor_unchecked, length_scale
from contactalpha.engine.solver import no_kinematic_inverse, solve_alpha
from contactalpha.engine.table import EPS_MIN, XI_MAX, alpha_tabulated
from contactalpha.laws import DEFAULT_LAW, get_law
from contactalpha.laws.domain import target_name
from contactalpha.stepping.registry import STEPPER_NAMES
from contactalpha.validation import PLAIN_FLOATS, check_scalar

from . import impulse_door, stepped
from .batched import broadcast_shape, check_rows
from .law_scene import SPEED_FACTORS, EngineScene, law_contact_parameters
from .reach import eps_zero_without_load
from .result import ContactParameters, NoSeparationWarning, format_parameters, no_separation_note  # noqa: F401
from .stepped_batch import at_step_batch

# The contact law this front door solves for by default (Hunt-Crossley, n = 3/2).
LAW = DEFAULT_LAW


def _positive(name, value):
    return check_scalar(name, value, 0.0, math.inf, lo_open=True, hi_open=True)


def scene_accel(mass: float, accel: float | None = None, force: float | None = None) -> float:
    """Relative acceleration of the load from exactly one of ``accel`` (m/s^2) and ``force`` (N)."""
    load, is_force = _load(accel, force)
    return load / _positive("mass", mass) if is_force else load


def _load(accel, force):
    """``(value, is_force)``: exactly one of ``accel`` and ``force``, checked."""
    if (accel is None) == (force is None):
        raise ValueError(
            f"give exactly one of accel (m/s^2) and force (N); got accel = {accel!r}, force = {force!r}"
        )
    if force is None:
        return check_scalar("accel", accel, 0.0, np.inf, hi_open=True), False
    return check_scalar("force", force, 0.0, np.inf, hi_open=True), True


def _target(eps, e_n):
    """``(value, restitution)`` from exactly one of ``eps`` and ``e_N``, checked."""
    if (eps is None) == (e_n is None):
        raise ValueError(
            f"give exactly one of eps (energetic) and e_N (kinematic); got eps = {eps!r}, e_N = {e_n!r}"
        )
    if e_n is None:
        return check_scalar("eps", eps, 0.0, 1.0), "energetic"
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
        where = f"{target_name(restitution)} = {value!r}, xi = {xi!r}"
        raise RuntimeError(f"exact alpha not found at {where}: {sol.status}")
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
    engine: str | None = None,
    timestep: float | str | None = None,
    verify: int | None = None,
) -> ContactParameters:
    """Contact parameters of one impact, or of a batch, in SI units, from the scene and a restitution.

    Parameters
    ----------
    eps : float or array, optional
        Stronge's energetic restitution, 0 <= eps <= 1 (eps = 0 only with a load).
    mass : float or array
        Effective mass m_e, kg (> 0).
    stiffness : float or array
        The law's physical stiffness k (> 0): N/m^1.5 for the Hertz laws (the default law,
        ``hertz_tsuji``), N/m for the n = 1 laws (``hunt_crossley_linear``, ``kelvin_voigt``,
        ``mujoco_soft``).  Never per unit mass: MuJoCo's ``solref`` divides by the mass itself.
    approach_speed : float or array
        Approach speed v_minus, m/s (> 0).
    e_N : float or array, optional
        Newton's kinematic restitution (separation speed / approach speed), 0 < e_N <= 1.
        Give exactly one of ``eps`` and ``e_N``.
    accel, force : float or array
        Give one: the constant acceleration pressing the bodies together (m/s^2, >= 0; gravity
        included if it acts), or the constant force (N, >= 0; ``accel = force / mass``).
    radius : float or array, optional
        Radius of a sphere meeting a half space, m (> 0): adds OpenSim's ``stiffness``.
    law : str or ContactLaw, optional
        The contact law (``contactalpha.laws``); default Hunt-Crossley n = 3/2.
    engine : str, optional
        A registered engine (``adapters.registry.ENGINE_NAMES``: opensim, exudyn, mujoco, drake,
        pybullet): solve for that engine's law and keep only its block in ``engines`` (the numbers
        ``contactalpha params --engine NAME`` prints).  Give ``law`` or ``engine``, not both
        (unless ``law`` is the engine's).
    timestep : float or "default", optional
        The engine's step, s ("default": the engine's own default, e.g. MuJoCo's 2 ms): the answer
        is then for the mean over a uniformly random touchdown phase at that step, through the
        engine's discrete map (``contactalpha.stepping``, docs/stepping.md); ``engines[engine]``
        holds those parameters and ``stepped`` the predicted mean, minimum and maximum.  Needs
        ``engine`` and a load.  For a batch (array inputs) and an e_N target, MuJoCo's and
        PyBullet's rows are solved together at formula speed (``stepping.batch_inverse``); Drake's,
        and eps targets, one scene at a time.  Without it the answer is the continuous law's.
    verify : int or "default", optional
        With ``timestep``: run the installed engine at this many touchdown phases and report the
        measured mean, minimum, maximum and the mean's sampling error in ``stepped.verify``
        ("default": the phases double until that error is small, ``stepped.verify``).

    Returns
    -------
    ContactParameters
        The one result type (``scene.result``): plain values for one scene, arrays of the broadcast
        shape when any input is an array (the law's fast evaluator gives the damping; each row's
        impact is integrated for its restitutions).  ``engines`` is keyed by engine.

    Raises
    ------
    ValueError
        Naming the value and its valid range, for bad or non-physical input (also a load so
        large for the approach speed that xi rounds to 1, and e_N = 0, which many alpha give);
        for a batch, naming the argument and its first bad index.
    scene.reach.UnreachableTarget
        A ``ValueError`` for a target no damping reaches (eps = 0 without a load), naming what would,
        or one the law's inverse does not resolve (a load factor next to 1, a target next to
        capture), naming what to change.
    RuntimeError
        If no damping is found for one scene (never a plausible wrong number).
    """
    if impulse_door.is_impulse(engine):  # a rigid contact with restitution: answered at its step
        row = (eps, mass, stiffness, approach_speed, e_N, accel, force, radius)
        return impulse_door.impulse_parameters(row, law, engine, timestep, verify, contact_parameters)
    batch = _batch(eps, mass, stiffness, approach_speed, e_N, accel, force, radius)
    map_radius = radius
    if radius is not None and engine in STEPPER_NAMES and stepped.needs_radius(engine):
        # The engine's step map reads the geometry (PyBullet's breaking threshold) even where its
        # law's parameters do not: checked here, on every path, and kept from the law if unread.
        map_radius = _checked_radius(radius, batch)
        if not _law_reads_radius(_law_of(law, engine)):
            radius = None
    if timestep is not None or verify is not None:
        scene = (eps, mass, stiffness, approach_speed, e_N, accel, force, radius, map_radius)
        return _at_step(*scene, law, engine, timestep, verify)
    chosen = _law_of(law, engine)
    if batch:
        batch_scene = (eps, mass, stiffness, approach_speed, e_N, accel, force, radius)
        return _only(_batched(*batch_scene, chosen), engine)
    value, restitution = _target(eps, e_N)
    for name, given in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed)):
        if given is None:
            raise ValueError(f"{name} is required (SI units)")
    m = _positive("mass", mass)
    k = _positive("stiffness", stiffness)
    v = _positive("approach_speed", approach_speed)
    load, is_force = _load(accel, force)
    a = load / m if is_force else load
    sphere = None if radius is None else _positive("radius", radius)
    if chosen.name != DEFAULT_LAW:
        check_radius_used(chosen, radius)
        return _only(law_contact_parameters(chosen, value, restitution, m, k, v, a, sphere), engine)
    xi = influence_factor_unchecked(m, k, v, a)
    if restitution == "energetic" and value == 0.0 and xi == 0.0:
        raise eps_zero_without_load()
    alpha, source = _alpha(value, xi, restitution)
    r = impact_unchecked(alpha, xi)
    if r.status != "ok":
        raise RuntimeError(f"impact at alpha = {alpha!r}, xi = {xi!r} failed: {r.status}")
    engines = engine_parameters(chosen, alpha, EngineScene(m, k, v, sphere))
    e_n_half, e_n_twice = (_fixed_damping_e_n(alpha, m, k, v, a, factor) for factor in SPEED_FACTORS)
    return _only(
        frozen_instance(
            ContactParameters,
            law=chosen.name,
            xi=xi,
            damping_name=chosen.damping,
            damping=alpha,
            physical_damping=chosen.physical_damping_unchecked(alpha, m, k, v),
            physical_unit=chosen.physical_unit,
            eps=r.eps,
            e_n=r.e_n,
            end_state=r.state,
            ok=True,
            reason="",
            accel=a,
            delta_star=float(length_scale(m, k, v)),
            source=source,
            engines=engines,
            e_n_half_speed=e_n_half,
            e_n_twice_speed=e_n_twice,
            engine=None,
            stepped=None,
        ),
        engine,
    )


def _at_step(eps, mass, stiffness, approach_speed, e_n, accel, force, radius, map_radius, law, engine,
             timestep, verify):  # fmt: skip
    """``contact_parameters`` at an engine's step (``scene.stepped``).

    ``radius`` is the continuous law's (None where it reads none), ``map_radius`` the step map's.
    """
    if timestep is None:
        raise ValueError("verify needs timestep= (the engine's step, s, or 'default')")
    if engine is None:
        raise ValueError("timestep needs engine=: the step is an engine's (mujoco, pybullet, drake)")
    restitution = "kinematic" if eps is None else "energetic"
    name = target_name(restitution)
    if _batch(eps, mass, stiffness, approach_speed, e_n, accel, force, map_radius):
        if verify is not None:
            raise ValueError("verify= takes one scene; a batch at the step is checked one scene at a time")
        broadcast_shape(mass=mass, stiffness=stiffness, approach_speed=approach_speed, accel=accel,
                        force=force, **{name: e_n if eps is None else eps}, radius=map_radius)  # fmt: skip
        target = check_rows(name, e_n if eps is None else eps, 0.0, 1.0, lo_open=True, hi_open=True)
        _check_load_rows(accel, force)
        cp = contact_parameters(eps, mass, stiffness, approach_speed, e_N=e_n, accel=accel, force=force,
                                radius=radius, law=law, engine=engine)  # fmt: skip
        return at_step_batch(cp, cp.engine, timestep, mass, stiffness, approach_speed, cp.accel, map_radius,
                             target, restitution)  # fmt: skip
    # The mean restitution at the step is 1 only without damping and with no loss to the step: an
    # open range, named as the target the user gave.
    value, restitution = _target(eps, e_n)
    check_scalar(name, value, 0.0, 1.0, lo_open=True, hi_open=True)
    cp = contact_parameters(eps, mass, stiffness, approach_speed, e_N=e_n, accel=accel, force=force,
                            radius=radius, law=law, engine=engine)  # fmt: skip
    args = (cp.engine, float(mass), float(stiffness), float(approach_speed), float(cp.accel), map_radius)
    cp = stepped.at_step(cp, args[0], timestep, *args[1:], value, restitution)
    return cp if verify is None else stepped.verify(cp, verify, *args[1:])


def _check_load_rows(accel, force):
    """A batch at the step needs every row's load > 0, as one scene does: else the whole batch is refused."""
    name, value = ("accel", accel) if force is None else ("force", force)
    try:
        check_rows(name, value, 0.0, np.inf, lo_open=True, hi_open=True)
    except ValueError as err:
        raise ValueError(f"timestep needs a load pressing the bodies together in every row: {err}") from None


def _checked_radius(radius, batch):
    """``radius`` checked > 0 and finite: by name for one scene, by its first bad index for a batch."""
    if not batch:
        return _positive("radius", radius)
    return check_rows("radius", radius, 0.0, np.inf, lo_open=True, hi_open=True)


def _law_reads_radius(law):
    """True when some engine of ``law`` reads the radius (``check_radius_used`` accepts one)."""
    try:
        check_radius_used(law, 1.0)
    except ValueError:
        return False
    return True


def _law_of(law, engine):
    """The law to solve for: ``law`` (default Hunt-Crossley), or ``engine``'s (they must agree)."""
    if engine is None:
        return get_law(DEFAULT_LAW if law is None else law)
    engines_law = adapter(engine).law
    if law is not None and get_law(law).name != engines_law.name:
        raise ValueError(
            f"law = {get_law(law).name!r} is not engine {engine!r}'s law {engines_law.name!r}: "
            "give engine= or law=, not both"
        )
    return engines_law


def _only(cp, engine):
    """``cp`` with only ``engine``'s block (and ``engine`` set), or ``cp`` itself when none is asked.

    One scene whose target leaves the bodies in contact warns (``NoSeparationWarning``).
    """
    if np.ndim(cp.ok) == 0 and no_separation_note(cp):
        warnings.warn(no_separation_note(cp), NoSeparationWarning, stacklevel=3)
    if engine is None:
        return cp
    return cp.replaced(engines={engine: cp.engines[engine]}, engine=engine)


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
    for name, given in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed)):
        if given is None:
            raise ValueError(f"{name} is required (SI units)")
    target, restitution = (e_n, "kinematic") if eps is None else (eps, "energetic")
    scene = (mass, stiffness, approach_speed, accel, target)
    return batched_parameters(*scene, restitution=restitution, law=law, radius=radius, force=force)


def _fixed_damping_e_n(alpha, mass, stiffness, speed, accel, factor):
    """Newton's e_N of an impact at ``factor`` times ``speed`` with the same damping ``mu = alpha k / v``."""
    try:
        xi = influence_factor_unchecked(mass, stiffness, speed * factor, accel)
    except ValueError:  # the load's xi rounds to 1 at that speed: no impact to speak of
        return math.nan
    r = impact_unchecked(alpha * factor, xi)
    return float(r.e_n) if r.status == "ok" else math.nan
