"""The front door: from a scene in SI units to every number an engine needs (``ContactParameters``).

A simulation engineer has a mass, a stiffness, an approach speed, a constant load (gravity plus
a force) and a measured restitution, energetic (Stronge's eps) or kinematic (Newton's e_N, what a
drop test measures).  ``contact_parameters`` returns, for the contact law asked for (default
Hunt-Crossley, n = 3/2) or the law of the engine asked for: the load factor xi (paper Eq. 10
for Hunt-Crossley), the law's exact dimensionless damping for that restitution at that xi, its
physical damping, the end state and both restitutions of the impact it gives (one impact
integrated), and the parameters of each engine of the law in its own names and units.  One
result type for every law and for batches: ``parameters.result.ContactParameters``.

The physical damping (and OpenSim's ``dissipation``) is a constant of the contact law, but for
the Hunt-Crossley laws the alpha it stands for is ``d v_minus``: it delivers the requested
restitution at this approach speed only.  So the parameters also carry the e_N the same physical
damping delivers at half and at twice the approach speed (one impact each, the load's xi at that
speed): a drop from another height needs its own damping.

This module checks the call and picks one path, each in its own module: one scene
(``one_scene``), a batch (``batch``), and, with ``timestep``, the continuous answer carried to the
engine's step for one scene (``at_step``, ``verify``) or a batch (``at_step_batch``).  Each input
is checked once, the continuous answer is solved once, and no path calls back into this one.
"""

import warnings

import numpy as np

from contactalpha.adapters.registry import check_radius_used
from contactalpha.laws import DEFAULT_LAW
from contactalpha.laws.domain import target_name
from contactalpha.laws.fast import ENGINE_TABLE
from contactalpha.scene.load import checked_load, positive
from contactalpha.stepping import registry as stepping_registry
from contactalpha.validation import check_scalar

from . import impulse
from .at_step import at_step, needs_radius
from .at_step_batch import at_step_batch
from .batch import batched_parameters
from .checks import (
    broadcast_shape,
    check_load_rows,
    check_rows,
    checked_radius,
    checked_target,
    is_batch,
    law_of,
    law_reads_radius,
    require_scene,
)
from .one_scene import hunt_crossley_parameters, law_parameters
from .result import ContactParameters, NoSeparationWarning, no_separation_note
from .verify import verify_on_engine

# The contact law this front door solves for by default (Hunt-Crossley, n = 3/2).
LAW = DEFAULT_LAW


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
        The one result type (``parameters.result``): plain values for one scene, arrays of the broadcast
        shape when any input is an array (the law's fast evaluator gives the damping; each row's
        impact is integrated for its restitutions).  ``engines`` is keyed by engine.

    Raises
    ------
    ValueError
        Naming the value and its valid range, for bad or non-physical input (also a load so
        large for the approach speed that xi rounds to 1, and e_N = 0, which many alpha give);
        for a batch, naming the argument and its first bad index.
    parameters.reach.UnreachableTarget
        A ``ValueError`` for a target no damping reaches (eps = 0 without a load), naming what would,
        or one the law's inverse does not resolve (a load factor next to 1, a target next to
        capture), naming what to change.
    RuntimeError
        If no damping is found for one scene (never a plausible wrong number).
    """
    if impulse.is_impulse(engine):  # a rigid contact with restitution: answered at its step
        row = (eps, mass, stiffness, approach_speed, e_N, accel, force, radius)
        return impulse.impulse_parameters(row, law, engine, timestep, verify, contact_parameters)
    batch = is_batch(eps, mass, stiffness, approach_speed, e_N, accel, force, radius)
    radius, map_radius = _radii(radius, law, engine, batch)
    stepped = timestep is not None or verify is not None
    if stepped:
        _check_step_call(timestep, engine)
    if batch:
        if stepped:
            target, restitution = _step_rows(eps, mass, stiffness, approach_speed, e_N, accel, force,
                                             map_radius, verify)  # fmt: skip
        chosen = law_of(law, engine)
        rows = _batch(eps, mass, stiffness, approach_speed, e_N, accel, force, radius, chosen, engine)
        cp = _answer_for(rows, engine)
        if not stepped:
            return cp
        return at_step_batch(cp, engine, timestep, mass, stiffness, approach_speed, cp.accel, map_radius,
                             target, restitution)  # fmt: skip
    if stepped:
        # The mean restitution at the step is 1 only without damping and with no loss to the step: an
        # open range, named as the target the user gave.
        value, restitution = checked_target(eps, e_N)
        check_scalar(target_name(restitution), value, 0.0, 1.0, lo_open=True, hi_open=True)
    chosen = law_of(law, engine)
    if not stepped:
        value, restitution = checked_target(eps, e_N)
    m, k, v, a, sphere = _checked_scene(mass, stiffness, approach_speed, accel, force, radius)
    cp = _answer_for(_one_scene(value, restitution, m, k, v, a, sphere, chosen, engine), engine)
    if not stepped:
        return cp
    scene = (m, k, v, a, map_radius)
    cp = at_step(cp, engine, timestep, *scene, value, restitution)
    return cp if verify is None else verify_on_engine(cp, verify, *scene)


def _radii(radius, law, engine, batch):
    """``(radius, map_radius)``: the radius the continuous law reads (None where none) and the step map's.

    The engine's step map reads the geometry (PyBullet's breaking threshold) even where its law's
    parameters do not: checked here, on every path, and kept from the law if unread.
    """
    if radius is None or engine not in stepping_registry.STEPPER_NAMES or not needs_radius(engine):
        return radius, radius
    map_radius = checked_radius(radius, batch)
    return (radius if law_reads_radius(law_of(law, engine)) else None), map_radius


def _check_step_call(timestep, engine):
    """A call at the step names the step and the engine whose step it is."""
    if timestep is None:
        raise ValueError("verify needs timestep= (the engine's step, s, or 'default')")
    if engine is None:
        raise ValueError("timestep needs engine=: the step is an engine's (mujoco, pybullet, drake)")


def _step_rows(eps, mass, stiffness, approach_speed, e_n, accel, force, map_radius, verify):
    """``(target, restitution)`` of a batch at the step: the target rows in the open range (0, 1), checked.

    Every row needs a load > 0; ``verify`` takes one scene.
    """
    restitution = "kinematic" if eps is None else "energetic"
    name = target_name(restitution)
    if verify is not None:
        raise ValueError("verify= takes one scene; a batch at the step is checked one scene at a time")
    given = e_n if eps is None else eps
    broadcast_shape(mass=mass, stiffness=stiffness, approach_speed=approach_speed, accel=accel,
                    force=force, **{name: given}, radius=map_radius)  # fmt: skip
    target = check_rows(name, given, 0.0, 1.0, lo_open=True, hi_open=True)
    check_load_rows(accel, force)
    return target, restitution


def _checked_scene(mass, stiffness, approach_speed, accel, force, radius):
    """``(mass, stiffness, approach_speed, accel, radius)`` of one scene, each checked once, as floats."""
    require_scene(mass, stiffness, approach_speed)
    m = positive("mass", mass)
    k = positive("stiffness", stiffness)
    v = positive("approach_speed", approach_speed)
    load, is_force = checked_load(accel, force)
    a = load / m if is_force else load
    return m, k, v, a, None if radius is None else positive("radius", radius)


def _one_scene(value, restitution, m, k, v, a, radius, law, engine):
    """The continuous answer of one checked scene (``one_scene``).

    The law whose evaluator is the engine's own table (Hunt-Crossley, n = 3/2) takes that table and
    ``engine.solver``; every other law its own inverse, as the batch does (``batch``).
    """
    if law.fast is ENGINE_TABLE:
        return hunt_crossley_parameters(law, value, restitution, m, k, v, a, radius, engine)
    check_radius_used(law, radius)
    return law_parameters(law, value, restitution, m, k, v, a, radius, engine)


def _batch(eps, mass, stiffness, approach_speed, e_n, accel, force, radius, law, engine):
    """The continuous answer of arrays of scenes (``batch.batched_parameters``, which checks the rows)."""
    if (eps is None) == (e_n is None):
        raise ValueError("give exactly one of eps (energetic) and e_N (kinematic) arrays")
    if (accel is None) == (force is None):
        raise ValueError("give exactly one of accel (m/s^2) and force (N) arrays")
    require_scene(mass, stiffness, approach_speed)
    target, restitution = (e_n, "kinematic") if eps is None else (eps, "energetic")
    return batched_parameters(mass, stiffness, approach_speed, accel, target, restitution=restitution,
                              law=law, radius=radius, force=force, engine=engine)  # fmt: skip


def _answer_for(cp, engine):
    """``cp`` with ``engine`` set (its block is the only one), or ``cp`` itself when none is asked.

    One scene whose target leaves the bodies in contact warns (``NoSeparationWarning``) at the
    caller of ``contact_parameters``.
    """
    if np.ndim(cp.ok) == 0 and no_separation_note(cp):
        warnings.warn(no_separation_note(cp), NoSeparationWarning, stacklevel=3)
    return cp if engine is None else cp.replaced(engine=engine)
