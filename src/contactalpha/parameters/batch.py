"""The front door for arrays of scenes: every engine's parameters as arrays, for domain randomisation.

``contact_parameters`` sends array input here.  Each scene is a mass, a stiffness, an approach
speed, a load and a target restitution; the arrays broadcast.  The law's damping comes from the
law's fast evaluator (``ContactLaw.fast_damping``; for Hunt-Crossley, n = 3/2, the shipped exact
table at ``engine.scaling``'s xi, as the scalar front door), and each registered engine of that law
converts it (``adapters.registry.engine_parameters``).  The stiffness is the law's physical one
(N/m for n = 1, MuJoCo's included; N/m^1.5 for n = 3/2).  Each row's impact is integrated
(``ContactLaw.impact``) for its restitutions and end state, as one scene's is, but only when one
of those fields is first read (``parameters.result.Deferred``): the damping and the engine blocks come
at the table's speed, and the integration costs about a thousand times more per row.

The batch rules:

- a row outside the evaluator's domain (a target below its smallest restitution, a load factor
  above its largest) gets NaN in every number (engine blocks included, MuJoCo's ``solref`` too),
  ``ok = False`` and a ``reason``; the other rows are bit for bit what a batch without it gives
  (every step works row by row); a row whose integrated impact fails reads NaN in the integrated
  fields (``eps``, ``e_n``, ``end_state`` "none", the e_N at half and twice the speed);
- a bad value (a NaN, a negative mass, a target above 1) refuses the whole batch with a
  ``ValueError`` naming the argument, its first bad index and that value.
"""

import numpy as np
from numba import njit

from contactalpha.adapters.registry import check_radius_used
from contactalpha.engine.firstcall import twin_rows
from contactalpha.engine.scaling import A_ROUNDS_TO_ONE, length_scale, scales_kernel, xi_of_load_kernel
from contactalpha.engine.table import EPS_MIN, XI_MAX, tabulated_or_nan
from contactalpha.engine.threads import flat_owned, run_rows
from contactalpha.laws import get_law
from contactalpha.laws.domain import target_name
from contactalpha.laws.fast import ENGINE_TABLE, fast_damping_unchecked
from contactalpha.laws.maps import impact_unchecked

from .block_scene import BlockScene
from .checks import broadcast_shape, check_rows
from .one_scene import SPEED_FACTORS, engine_blocks, fixed_damping_e_n
from .result import ContactParameters, Deferred


@twin_rows
@njit(cache=True, nogil=True, error_model="numpy")
def _hertz_load_factor_rows(mass, stiffness, speed, accel, xi, scale_ok, start, stop):
    """Rows ``start .. stop - 1`` of the load factor: delta_star, A and Eq. 10, into ``xi``.

    ``engine.scaling``'s delta_star, ``A = a delta_star / v^2`` and its Eq. 10
    (``xi_of_load_kernel``); NaN where A is not below ``A_ROUNDS_TO_ONE`` or xi rounds to 1;
    ``scale_ok`` False where delta_star or t_star is beyond the doubles.
    """
    for i in range(start, stop):
        v = speed[i]
        d, t = scales_kernel(mass[i], stiffness[i], v)
        scale_ok[i] = 0.0 < d < np.inf and 0.0 < t < np.inf
        A = accel[i] * d / (v * v)
        x = xi_of_load_kernel(A) if A < A_ROUNDS_TO_ONE else np.nan
        xi[i] = x if x < 1.0 else np.nan


def hertz_load_factor(mass, stiffness, approach_speed, accel):
    """The paper's influence factor xi (Eq. 10) of arrays of Hunt-Crossley scenes.

    ``engine.scaling.influence_factor``'s direct path (``A = a delta* / v^2``), each row in one
    compiled pass (in ``engine.threads``' threads); a load so large that xi rounds to 1 gives NaN
    here, a scene whose length or time scale is beyond the doubles the ``ValueError`` of
    ``engine.scaling.length_scale``.
    """
    m, k, v, a = np.broadcast_arrays(mass, stiffness, approach_speed, accel)
    xi = np.empty(m.shape)
    scale_ok = np.empty(m.shape, dtype=np.bool_)
    flat = [flat_owned(x) for x in (m, k, v, a)]
    run_rows(_hertz_load_factor_rows, xi.size, *flat, xi.reshape(-1), scale_ok.reshape(-1))
    if not scale_ok.all():
        length_scale(mass, stiffness, approach_speed)  # raises, naming the first such scene
    return xi


def _load_factor(law):
    """Load factor of arrays of scenes: Eq. 10 through ``engine.scaling`` for n = 3/2, else the law's."""
    if law.fast is ENGINE_TABLE:
        return hertz_load_factor
    return lambda m, k, v, a: law_load_factor(law, m, k, v, a)


def law_load_factor(law, mass, stiffness, approach_speed, accel):
    """Load factor xi of checked scenes of ``law``; NaN where the load is so large that xi rounds to 1."""
    A = np.asarray(law.load_unchecked(mass, stiffness, approach_speed, accel), dtype=float)
    xi = np.full(A.shape, np.nan)
    finite = np.isfinite(A)
    xi[finite] = law.load_factor_unchecked(A[finite])
    return np.where(xi < 1.0, xi, np.nan)


def _domain(law):
    """(smallest target, largest load factor) of the law's fast evaluator."""
    if law.fast is ENGINE_TABLE:
        return EPS_MIN, XI_MAX
    return law.restitution_domain[0], law.load_domain[1]


def _reasons(law, e, xi, ok):
    """Why each row has no answer ("" where it has one), with the row's offending value."""
    lo_e, hi_xi = _domain(law)
    why = np.full(e.shape, "", dtype=object)
    for i in zip(*np.nonzero(~ok), strict=True):
        if e[i] < lo_e:
            why[i] = f"target {float(e[i])!r} below the batch evaluator's {lo_e} (one scene's call solves it)"
        elif not np.isfinite(xi[i]):
            why[i] = "load so large that the load factor xi rounds to 1"
        elif xi[i] > hi_xi:
            why[i] = (
                f"load factor xi = {float(xi[i])!r} above the batch evaluator's {hi_xi} "
                "(one scene's call solves it)"
            )
        else:
            why[i] = "no damping found (the evaluator or the impact failed)"
    return why


def masked_rows(x, ok):
    """Engine value ``x`` with NaN in the rows without an answer (a tuple entry by entry)."""
    if isinstance(x, tuple):
        return tuple(masked_rows(v, ok) for v in x)
    if isinstance(x, np.ndarray | float | int) and not isinstance(x, bool):
        x = np.asarray(x, dtype=float)
        if x.ndim > ok.ndim:  # a row per world (MuJoCo's (n, 2) solref): the trailing axis is the row's
            return np.where(ok.reshape(ok.shape + (1,) * (x.ndim - ok.ndim)), x, np.nan)
        return np.where(ok, np.broadcast_to(x, ok.shape), np.nan)
    return x


def batched_parameters(
    mass,
    stiffness,
    approach_speed,
    accel,
    target,
    *,
    restitution="kinematic",
    law="hunt_crossley",
    radius=None,
    force=None,
    engine=None,
):
    """Every engine's parameters for arrays of scenes (see the module docstring).

    Parameters
    ----------
    mass, stiffness, approach_speed : array_like
        kg, the law's physical stiffness (N/m^1.5 for n = 3/2, N/m for n = 1), m/s; all > 0.
    accel : array_like or None
        Acceleration of the load pressing the bodies together, m/s^2 (>= 0); None with ``force``.
    target : array_like
        Target restitution in (0, 1].
    restitution : {"kinematic", "energetic"}
        Newton's e_N or Stronge's eps.
    law : str or ContactLaw
        The contact law (``contactalpha.laws``).
    radius : array_like, optional
        Sphere radius, m (adds OpenSim's stiffness).
    force : array_like, optional
        The load as a force, N (>= 0), instead of ``accel``: ``accel = force / mass``.
    engine : str, optional
        Only this engine's block in ``engines`` (an engine of ``law``); default every engine of the law.

    Returns
    -------
    ContactParameters
        Every per-scene field an array of the broadcast shape (``parameters.result``).
    """
    law = get_law(law)
    name = target_name(restitution)
    check_radius_used(law, radius)
    m, k, v = (
        check_rows(n, x, 0.0, np.inf, lo_open=True, hi_open=True)
        for n, x in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed))
    )
    if (accel is None) == (force is None):
        raise ValueError("give exactly one of accel (m/s^2) and force (N) arrays")
    broadcast_shape(mass=mass, stiffness=stiffness, approach_speed=approach_speed, accel=accel, force=force,
                    **{name: target}, radius=radius)  # fmt: skip
    if force is None:
        a = check_rows("accel", accel, 0.0, np.inf, hi_open=True)
    else:
        a = check_rows("force", force, 0.0, np.inf, hi_open=True) / m
    e = check_rows(name, target, 0.0, 1.0, lo_open=True)
    r = None if radius is None else check_rows("radius", radius, 0.0, np.inf, lo_open=True, hi_open=True)
    m, k, v, a, e, r_all = np.broadcast_arrays(m, k, v, a, e, 1.0 if r is None else r)
    r = None if r is None else r_all
    load_factor = _load_factor(law)
    xi = load_factor(m, k, v, a)
    lo_e, hi_xi = _domain(law)
    if law.fast is ENGINE_TABLE:  # n = 3/2: the front door's own xi and table, bit for bit
        damping = tabulated_or_nan(e, xi, restitution)  # NaN outside [EPS_MIN, 1] x [0, XI_MAX]
    else:
        inside = np.isfinite(xi) & (xi <= hi_xi) & (e >= lo_e)
        damping = np.full(e.shape, np.nan)
        damping[inside] = fast_damping_unchecked(law, e[inside], xi[inside], restitution)
    ok = np.isfinite(damping)
    p = np.where(ok, damping, 0.0)

    def rows(x):
        return np.where(ok, x, np.nan)

    def impacts():
        # Each row's impact, integrated once when one of its fields is first read (``Deferred``);
        # a row whose impact fails reads NaN there.
        if "hit" not in cache:
            cache["hit"] = impact_unchecked(law, p, np.where(ok, xi, 0.0))
        hit = cache["hit"]
        return hit, ok & (np.asarray(hit.status) == "ok")

    def impact_field(name):
        def compute():
            hit, good = impacts()
            value = getattr(hit, name)
            if name == "state":
                return np.where(good, np.asarray(value, dtype=object), "none")
            return np.where(good, value, np.nan)

        return Deferred(compute)

    def speed_field(factor):
        return Deferred(lambda: rows(fixed_damping_e_n(law, p, m, k, v, a, factor, load_factor)))

    cache = {}

    engines = engine_blocks(law, p, BlockScene(m, k, v, r), engine)
    return ContactParameters(
        law=law.name,
        xi=rows(xi),
        damping_name=law.damping,
        damping=rows(damping),
        physical_damping=rows(law.physical_damping_unchecked(p, m, k, v)),
        physical_unit=law.physical_unit,
        eps=impact_field("eps"),
        e_n=impact_field("e_n"),
        end_state=impact_field("state"),
        ok=ok,
        reason=_reasons(law, e, xi, ok),
        accel=a,
        delta_star=rows(law.length_scale_unchecked(m, k, v)),
        source=np.where(ok, "table" if law.fast is ENGINE_TABLE else law.fast.name, "none"),
        engines={name: {key: masked_rows(x, ok) for key, x in b.items()} for name, b in engines.items()},
        e_n_half_speed=speed_field(SPEED_FACTORS[0]),
        e_n_twice_speed=speed_field(SPEED_FACTORS[1]),
    )
