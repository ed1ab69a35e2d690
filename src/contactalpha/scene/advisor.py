"""The scene advisor: which contact model a scene needs, and whether its load may be ignored.

For a scene (restitution ``eps``, mass, Hertz stiffness, approach speed and a constant
acceleration or force towards the contact) the advisor gives the load's influence factor
``xi`` (Eq. 10) and its level in the paper's words, the exact alpha and end state, and for
every model of the registry what it delivers and whether it is **adequate**.

Adequacy is judged over the speeds the scene will see, not at one speed: by default the approach
speeds of its bounce sequence with the exact alpha, from the given approach speed down to the
first contact that does not separate (``scene.bounces``; one speed when there is no load, since
the body then never returns), or ``speeds=(low, high)``, a range the user gives (sampled at
``RANGE_SAMPLES`` log-spaced speeds, both ends included, after the given approach speed). At
each speed the model's alpha is taken at that impact's own ``xi`` and one impact is integrated;
the model is adequate when at every speed the delivered restitution is within ``tol`` of the
requested one and the end state is the exact alpha's. Its **margin** is ``tol`` minus its
largest error over the speeds (negative: inadequate), reported with the speed where that error
occurs; an adequate model also ends every judged impact in the exact alpha's end state. The load
may be ignored when the exact alpha at ``xi = 0`` is adequate in the same sense.

The recommendation is deterministic: the same input gives the same advice, byte for byte.  No
timing enters it; each model's cost is a fixed count from ``COST_MODEL`` (arithmetic operations
per evaluation, a libm call such as exp, log or a non-integer power counted as ``LIBM_OPS``).
The recommended model is the cheapest adequate one, the most accurate among those within
``COST_TIE`` of its cost (ties broken by the registry's order).  When the load may not be
ignored, a model that ignores the load is never recommended, even where its formula's error
happens to offset the load's effect over these speeds: its verdict says so in its note.

Restitution is Stronge's energetic eps (Eq. 17) or, with ``restitution="kinematic"``,
Newton's kinematic e_N = v_out / v_in.  Then the requested number is e_N: the exact alpha
is the one that delivers it, every model is given it as its restitution coefficient (the
classical models were derived without a load, where e_N = eps), and what each delivers
is compared as e_N.  Ignoring the load means the exact alpha at xi = 0 for this number,
the same in both definitions.  The registry's load-aware models (and ``exact``) are
formulas in Stronge's eps, so given e_N they miss it; the advice also gives both
restitutions of the exact impact (``exact_eps``, ``exact_e_n``): a model fed
``exact_eps`` delivers the requested e_N as well as it delivers eps.
"""

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from contactalpha import models
from contactalpha.engine.driver import impact
from contactalpha.engine.exact import alpha_exact
from contactalpha.engine.scaling import influence_factor
from contactalpha.engine.solver import RESTITUTIONS, solve_alpha
from contactalpha.laws import DEFAULT_LAW, get_law
from contactalpha.laws.domain import target_name
from contactalpha.validation import check_positive, check_range, check_scalar

from .law_scene import law_advise
from .load import scene_accel

# The paper's three levels of xi (Sect. 3): small 0-0.1, moderate 0.1-0.5, large 0.5-1.
XI_LEVELS = (("small", 0.0, 0.1), ("moderate", 0.1, 0.5), ("large", 0.5, 1.0))
# Default tolerance on the delivered restitution.
DEFAULT_TOL = 0.01
# Operations one libm call (exp, log, log1p, a non-integer power) counts for in the cost model.
LIBM_OPS = 20
# The cost model: operations per evaluation of each model, counted from its formula (libm
# calls x LIBM_OPS + arithmetic).  Approximate counts; only their ranking and ratios matter.
COST_MODEL = {
    "hunt_crossley": 2,  # 1.5 (1 - eps)
    "lankarani_nikravesh": 3,  # 0.75 (1 - eps^2)
    "flores": 3,  # 1.6 (1 - eps) / eps
    "hu_guo": 3,  # 1.5 (1 - eps) / eps
    "gonthier": 3,  # (1 - eps^2) / eps
    "shen_zero_load": 1 * LIBM_OPS + 3,  # one power
    "exact_unloaded": 1 * LIBM_OPS + 30,  # engine.unloaded: one exp or log, a degree-13 polynomial
    "exact": 5 * LIBM_OPS + 150,  # table: log, 2 log1p, exp, sqrt; 1-D and 2-D quintic splines
    "shen_published": 9 * LIBM_OPS + 30,  # Eq. 40: powers and a Gaussian
    "shen_refit": 9 * LIBM_OPS + 30,
    "closed_form": 20 * LIBM_OPS + 80,  # models.closed_form: exps, logs and powers
    # A Newton solve: ~5 impacts of ~80 DOP853 steps of 12 stages, ~40 operations a stage.
    "exact_solve": 5 * 80 * 12 * 40,
}
# Adequate models within this factor of the cheapest adequate one's cost count as equally cheap;
# among them the most accurate is recommended.
COST_TIE = 1.5
# Log-spaced speeds at which a user-given speed range is judged (both ends included).
RANGE_SAMPLES = 9
# Largest number of bounce speeds judged: beyond it, this many spread evenly along the sequence.
MAX_SPEEDS = 40
# Contacts of the exact bounce sequence beyond which it is cut (``bounces.predict_bounces``).
MAX_CONTACTS = 10_000
# Symbol of the restitution each definition (engine.solver.RESTITUTIONS) requests, for the text output.
RESTITUTION_SYMBOL = {"energetic": "eps", "kinematic": "e_N"}


def xi_level(xi: float) -> str:
    """The paper's level of ``xi``: "small", "moderate" or "large"."""
    x = float(check_range("xi", xi, 0.0, 1.0, hi_open=True))
    return next(name for name, lo, hi in XI_LEVELS if lo <= x < hi)


def is_adequate(delivered, state, requested, exact_state, tol):
    """Adequate: ``|delivered - requested| <= tol`` and the exact end state (element-wise; NaN is not)."""
    delivered = np.asarray(delivered, dtype=float)
    close = np.abs(delivered - np.asarray(requested, dtype=float)) <= tol
    return close & (np.asarray(state) == np.asarray(exact_state))


def cheapest(
    names: Sequence[str],
    adequate: Sequence[bool] | np.ndarray,
    costs: Mapping[str, float],
    errors: Sequence[float] | np.ndarray,
) -> str | None:
    """The recommended model among the adequate ones: cheapest, and most accurate within ``COST_TIE``.

    Parameters
    ----------
    names : sequence of str
    adequate : sequence of bool
    costs : mapping name -> cost per evaluation (any fixed unit: ``COST_MODEL``'s operations)
    errors : sequence of float
        ``|delivered - requested|`` per model (the largest over the judged speeds).

    Returns
    -------
    str or None
        None when no model is adequate.  Exact ties go to the first of ``names``.
    """
    ok = [i for i, good in enumerate(adequate) if good]
    if not ok:
        return None
    floor = min(costs[names[i]] for i in ok)
    tied = [i for i in ok if costs[names[i]] <= COST_TIE * floor]
    return names[min(tied, key=lambda i: (errors[i], costs[names[i]], i))]


def model_costs(names: Sequence[str] | None = None, costs: Mapping[str, float] | None = None) -> dict:
    """The cost per evaluation of each model: ``costs`` if given (checked), else ``COST_MODEL``.

    Raises
    ------
    ValueError
        If a model has no cost, or a cost is not a positive finite number.
    """
    names = tuple(models.MODELS) if names is None else tuple(names)
    table = COST_MODEL if costs is None else costs
    if not isinstance(table, Mapping):
        raise ValueError(f"costs must be a mapping model name -> cost per evaluation; got {costs!r}")
    missing = [n for n in names if n not in table]
    if missing:
        where = "COST_MODEL (register its cost there)" if costs is None else "costs"
        raise ValueError(
            f"no cost for model(s) {missing} in {where}; give every model of {list(names)} a positive cost"
        )
    out = {}
    for n in names:
        value = table[n]
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0.0 < value < math.inf:
            raise ValueError(f"cost of model {n!r} = {value!r} is outside the valid range (0, inf)")
        out[n] = float(value)
    return out


@dataclass(frozen=True)
class ModelVerdict:
    """One model in one scene: its alpha, what it delivers over the judged speeds, its cost, adequacy.

    Attributes
    ----------
    name, uses_xi : the registry's model and whether it uses the load.
    alpha : its alpha at the given approach speed (its ``xi``), the first of the judged speeds.
    delivered_eps : the restitution it delivers there (in the requested definition).
    state : the end state there.
    error : its largest ``|delivered - requested|`` over the judged speeds (NaN if it failed).
    worst_speed : the approach speed (m/s) of that largest error.
    margin : ``tol - error`` (negative or NaN: not adequate; adequacy also needs the end states).
    cost : operations per evaluation (``COST_MODEL``, or the ``costs`` given).
    adequate : within ``tol`` with the exact end state at every judged speed.
    note : why it failed, or why an adequate model is not recommended.
    """

    name: str
    uses_xi: bool
    alpha: float
    delivered_eps: float
    state: str
    error: float
    worst_speed: float
    margin: float
    cost: float
    adequate: bool
    note: str = ""


@dataclass(frozen=True)
class Advice:
    """The advisor's answer for one scene (see ``advise``).

    Attributes
    ----------
    eps, mass, stiffness, approach_speed, accel, tol, restitution : the scene as given (accel in m/s^2).
    speeds : the approach speeds (m/s) at which every model was judged, ``approach_speed`` first.
    speeds_from : "bounces" (the exact bounce sequence) or "range" (the ``speeds`` given).
    xi, xi_level : the load's influence factor at ``approach_speed`` and its level.
    exact_alpha, exact_state, exact_eps, exact_e_n : the exact impact at ``approach_speed``.
    models : a ``ModelVerdict`` per registered model.
    cheapest : the recommended model (None: no model adequate); ``margin`` its margin.
    ignore_load : whether the exact alpha at xi = 0 is adequate over ``speeds``;
        ``ignore_load_eps``/``ignore_load_state`` what it delivers at ``approach_speed``,
        ``ignore_load_margin`` its margin over ``speeds``.
    """

    eps: float
    mass: float
    stiffness: float
    approach_speed: float
    accel: float
    tol: float
    restitution: str
    speeds: tuple[float, ...]
    speeds_from: str
    xi: float
    xi_level: str
    exact_alpha: float
    exact_state: str
    exact_eps: float
    exact_e_n: float
    models: tuple[ModelVerdict, ...]
    cheapest: str | None
    margin: float
    ignore_load: bool
    ignore_load_eps: float
    ignore_load_state: str
    ignore_load_margin: float

    @property
    def recommended(self) -> str | None:
        """The recommended model (``cheapest``)."""
        return self.cheapest

    def to_dict(self) -> dict:
        """Plain data (for ``--json``)."""
        return asdict(self)


def _deliver(alpha, xi, restitution):
    """Delivered restitution in the requested definition (e_N = 0 without separation), states, statuses."""
    r = impact(alpha, xi)
    delivered = r.eps if restitution == "energetic" else r.e_n
    return np.atleast_1d(delivered), np.atleast_1d(r.state), np.atleast_1d(r.status)


def _bounce_speeds(eps, mass, stiffness, speed, accel, restitution):
    """Approach speeds of the exact bounce sequence, from ``speed`` to its first non-separating contact."""
    if accel == 0.0:
        return (speed,)  # nothing brings the body back
    if restitution == "energetic":
        from .ball import Scene
        from .bounces import predict_bounces

        scene = Scene(
            mass=mass, stiffness=stiffness, approach_speed=speed, force=mass * accel, eps=eps, gravity=0.0
        )
        seq = predict_bounces(scene, "exact_solve", max_contacts=MAX_CONTACTS)
        return tuple(float(v) for v in seq.approach_speeds)
    # Newton's e_N: each exact contact returns e_N times its approach speed and always separates;
    # the sequence is followed while the load's xi stays below the exact table's top.
    from contactalpha.engine.table import XI_MAX

    speeds = [speed]
    while len(speeds) < MAX_CONTACTS and influence_factor(mass, stiffness, speeds[-1] * eps, accel) <= XI_MAX:
        speeds.append(speeds[-1] * eps)
    return tuple(speeds)


def _thin(speeds):
    """At most ``MAX_SPEEDS`` of ``speeds``, spread evenly along the sequence (first and last kept)."""
    if len(speeds) <= MAX_SPEEDS:
        return tuple(speeds)
    picks = np.unique(np.round(np.linspace(0, len(speeds) - 1, MAX_SPEEDS)).astype(int))
    return tuple(speeds[i] for i in picks)


def _judged_speeds(eps, mass, stiffness, speed, accel, restitution, speeds):
    if speeds is None:
        return _thin(_bounce_speeds(eps, mass, stiffness, speed, accel, restitution)), "bounces"
    try:
        low, high = (
            float(check_positive(n, v)) for n, v in zip(("speeds[0]", "speeds[1]"), speeds, strict=True)
        )
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"speeds must be (low, high), two speeds in m/s with 0 < low <= high; {exc}"
        ) from None
    if low > high:
        raise ValueError(f"speeds = ({low!r}, {high!r}): low must not exceed high")
    grid = [float(v) for v in (np.geomspace(high, low, RANGE_SAMPLES) if low < high else [low])]
    return (speed, *(v for v in grid if v != speed)), "range"


def _verdict(name, alphas, delivered, states, exact_states, e, tol, speeds, cost, uses_xi, note=""):
    errors = np.abs(delivered - e)
    finite = np.isfinite(errors)
    worst = int(np.argmax(np.where(finite, errors, np.inf)))
    error = float(errors[worst])
    wrong_state = np.flatnonzero(states != exact_states)
    if wrong_state.size and not note:
        i = int(wrong_state[0])
        note = f"end state {states[i]} at {speeds[i]:.6g} m/s, exact {exact_states[i]}"
    return ModelVerdict(
        name=name,
        uses_xi=uses_xi,
        alpha=float(alphas[0]),
        delivered_eps=float(delivered[0]),
        state=str(states[0]),
        error=error,
        worst_speed=float(speeds[worst]),
        margin=tol - error,
        cost=cost,
        adequate=bool(tol - error >= 0.0 and not wrong_state.size),
        note=note,
    )


def advise(
    eps: float,
    mass: float,
    stiffness: float,
    approach_speed: float,
    *,
    accel: float | None = None,
    force: float | None = None,
    tol: float = DEFAULT_TOL,
    restitution: str = "energetic",
    speeds: tuple[float, float] | None = None,
    costs: Mapping[str, float] | None = None,
    law: str | None = None,
) -> Advice:
    """Which model a scene needs, judged over the speeds it will see.

    Parameters
    ----------
    eps : float
        Requested restitution, 0 < eps <= 1, in the definition ``restitution`` names.
    mass : float
        Effective mass m_e, kg (> 0).
    stiffness : float
        Hertz stiffness k, N/m^1.5 (> 0).
    approach_speed : float
        Approach speed of the impact, m/s (> 0).
    accel, force : float
        Give one: the constant acceleration pressing the bodies together (m/s^2, >= 0;
        gravity included if it acts), or the constant force (N, >= 0; ``accel = force / mass``:
        add the weight ``mass * g`` yourself if gravity acts).
    tol : float
        Tolerance on the delivered restitution, > 0.
    restitution : {"energetic", "kinematic"}
        Stronge's energetic eps (Eq. 17) or Newton's kinematic e_N; the delivered restitution
        of every model is reported and judged in the same definition.
    speeds : (float, float), optional
        A range of approach speeds (m/s) to judge over; default the scene's exact bounce
        sequence from ``approach_speed`` down to rest.
    costs : mapping name -> cost, optional
        Cost per evaluation of every model (positive, any fixed unit); default ``COST_MODEL``.
    law : str or ContactLaw, optional
        The contact law (``contactalpha.laws``); default Hunt-Crossley n = 3/2.  Another law
        judges that law's registered models at ``approach_speed`` and returns
        ``scene.law_scene.LawAdvice``; it takes neither ``speeds`` nor ``costs`` (ValueError).

    Returns
    -------
    Advice
        The same input gives the same advice, byte for byte.

    Raises
    ------
    ValueError
        Naming the value and its valid range or choices (``costs`` lacking a model included).
    """
    if restitution not in RESTITUTIONS:
        raise ValueError(f"restitution = {restitution!r} is outside the valid choices {RESTITUTIONS}")
    e = check_scalar("eps", eps, 0.0, 1.0, lo_open=True)
    m, k, v = (
        check_scalar(n, x, 0.0, np.inf, lo_open=True, hi_open=True)
        for n, x in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed))
    )
    a = float(scene_accel(m, accel=accel, force=force))
    tol = check_scalar("tol", tol, 0.0, 1.0, lo_open=True)
    if law is not None and get_law(law).name != DEFAULT_LAW:
        for name, given in (("speeds", speeds), ("costs", costs)):
            if given is not None:  # law_advise judges at the scene's speed, with no cost model
                raise ValueError(
                    f"{name} = {given!r} is not taken with law {get_law(law).name!r}: its models are judged "
                    "at the scene's approach speed only; leave it out"
                )
        return law_advise(law, e, restitution, m, k, v, a, tol)
    cost = model_costs(costs=costs)
    xi = float(influence_factor(m, k, v, a))
    sol = solve_alpha(e, xi, restitution=restitution)
    if not sol.ok:
        where = f"{target_name(restitution)} = {e!r}, xi = {xi!r}"
        raise RuntimeError(f"exact alpha not found at {where}: {sol.status}")
    judged, source = _judged_speeds(e, m, k, v, a, restitution, speeds)
    xis = np.array([influence_factor(m, k, s, a) for s in judged])
    exact = solve_alpha(np.full(xis.shape, e), xis, restitution=restitution)
    if not np.all(exact.ok):
        bad = int(np.argmin(exact.ok))
        raise RuntimeError(
            f"exact alpha not found at {judged[bad]!r} m/s (xi = {xis[bad]!r}): "
            f"{np.atleast_1d(exact.status)[bad]}"
        )
    exact_states = np.atleast_1d(exact.state)
    verdicts = []
    for name, model in models.MODELS.items():
        try:
            alphas = np.atleast_1d(
                np.asarray(models.alpha(np.full(xis.shape, e), xis, model=name), dtype=float)
            )
        except (ValueError, RuntimeError) as exc:  # outside the model's domain: reported, never adequate
            nan = np.full(xis.shape, np.nan)
            verdicts.append(
                _verdict(name, nan, nan, np.full(xis.shape, "failed"), exact_states, e, tol, judged,
                         cost[name], model.uses_xi, str(exc))
            )  # fmt: skip
            continue
        if not np.all(np.isfinite(alphas) & (alphas >= 0.0)):
            bad = alphas[~(np.isfinite(alphas) & (alphas >= 0.0))][0]
            nan = np.full(xis.shape, np.nan)
            verdicts.append(
                _verdict(name, alphas, nan, np.full(xis.shape, "failed"), exact_states, e, tol, judged,
                         cost[name], model.uses_xi, f"alpha = {bad!r} is not a damping factor")
            )  # fmt: skip
            continue
        delivered, states, status = _deliver(alphas, xis, restitution)
        note = "; ".join(sorted(set(status[status != "ok"])))
        verdicts.append(
            _verdict(
                name, alphas, delivered, states, exact_states, e, tol, judged, cost[name], model.uses_xi, note
            )
        )
    unloaded = np.full(xis.shape, float(alpha_exact(e)))
    delivered, states, _ = _deliver(unloaded, xis, restitution)
    ignore = _verdict("ignore_load", unloaded, delivered, states, exact_states, e, tol, judged, 1.0, False)
    if not ignore.adequate:  # the load matters: a load-ignoring model adequate here is so by luck
        verdicts = [_unrecommendable(mv) if mv.adequate and not mv.uses_xi else mv for mv in verdicts]
    best = cheapest(
        [mv.name for mv in verdicts],
        [mv.adequate and not mv.note.startswith(LUCK) for mv in verdicts],
        {mv.name: mv.cost for mv in verdicts},
        [mv.error for mv in verdicts],
    )
    return Advice(
        eps=e,
        mass=m,
        stiffness=k,
        approach_speed=v,
        accel=a,
        tol=tol,
        restitution=restitution,
        speeds=judged,
        speeds_from=source,
        xi=xi,
        xi_level=xi_level(xi),
        exact_alpha=float(sol.alpha),
        exact_state=str(sol.state),
        exact_eps=float(sol.eps_reached),
        exact_e_n=float(sol.e_n_reached),
        models=tuple(verdicts),
        cheapest=best,
        margin=next((mv.margin for mv in verdicts if mv.name == best), math.nan),
        ignore_load=ignore.adequate,
        ignore_load_eps=ignore.delivered_eps,
        ignore_load_state=ignore.state,
        ignore_load_margin=ignore.margin,
    )


# Note of an adequate load-ignoring model while the load may not be ignored.
LUCK = "not recommended: it ignores the load, which matters here"


def _unrecommendable(mv):
    from dataclasses import replace

    return replace(mv, note=f"{LUCK} (its formula's error offsets the load's effect over these speeds)")


def format_advice(adv: Advice) -> str:
    """The advice as a text table (the command line's output)."""
    sym = RESTITUTION_SYMBOL[adv.restitution]
    lo, hi = min(adv.speeds), max(adv.speeds)
    where = "the exact bounce sequence" if adv.speeds_from == "bounces" else "the given range"
    lines = [
        f"restitution  {sym} = {adv.eps:g} ({adv.restitution})",
        f"xi           {adv.xi:.6g} ({adv.xi_level}: small < 0.1 <= moderate < 0.5 <= large)",
        f"exact alpha  {adv.exact_alpha:.10g} ({adv.exact_state}; eps = {adv.exact_eps:.6g}, "
        f"e_N = {adv.exact_e_n:.6g})",
        f"speeds       {len(adv.speeds)} approach speed(s) from {hi:.6g} to {lo:.6g} m/s ({where})"
        + (
            "; the first contact does not separate: give a speed range to judge more"
            if len(adv.speeds) == 1
            else ""
        ),
        f"ignore load  {'yes' if adv.ignore_load else 'no'}: alpha at xi = 0 delivers {sym} = "
        f"{adv.ignore_load_eps:.6g} ({adv.ignore_load_state}) at {adv.approach_speed:g} m/s; "
        f"margin {adv.ignore_load_margin:.3g}",
        f"recommended  {adv.cheapest} (cheapest adequate: |{sym} - {adv.eps:g}| <= {adv.tol:g} and the "
        f"exact end state at every speed; margin {adv.margin:.3g})",
        "",
        f"{'model':22s} {'alpha':>12s} {'delivered ' + sym:>14s} {'end state':15s} {'ops/eval':>9s}"
        f" {'margin':>9s} {'worst m/s':>10s}  adequate",
    ]
    for mv in adv.models:
        verdict = ("yes" if mv.adequate else "no") + (f"  {mv.note}" if mv.note else "")
        lines.append(
            f"{mv.name:22s} {mv.alpha:12.6g} {mv.delivered_eps:14.6g} {mv.state:15s} {mv.cost:9.0f}"
            f" {mv.margin:9.3g} {mv.worst_speed:10.4g}  {verdict}"
        )
    return "\n".join(lines)
