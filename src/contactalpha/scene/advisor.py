"""The scene advisor: which contact model a scene needs, and whether its load may be ignored.

For a scene (restitution ``eps``, mass, Hertz stiffness, approach speed and a constant
acceleration or force towards the contact) the advisor gives the load's influence factor
``xi`` (Eq. 10) and its level in the paper's words, the exact alpha and end state, and
for every model of the registry the restitution it really delivers in this scene (one
impact integrated with the model's alpha at this ``xi``), its end state, its cost per
evaluation and whether it is **adequate**: delivered eps within ``tol`` of the requested
eps and the same end state as the exact alpha.  The load may be ignored when the exact
alpha at ``xi = 0`` is adequate.

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

import functools
import time
from dataclasses import asdict, dataclass

import numpy as np

from contactalpha import models
from contactalpha.engine.driver import impact
from contactalpha.engine.exact import alpha_exact
from contactalpha.engine.scaling import influence_factor
from contactalpha.engine.solver import RESTITUTIONS, solve_alpha
from contactalpha.validation import check_range, check_scalar

from .parameters import scene_accel

# The paper's three levels of xi (Sect. 3): small 0-0.1, moderate 0.1-0.5, large 0.5-1.
XI_LEVELS = (("small", 0.0, 0.1), ("moderate", 0.1, 0.5), ("large", 0.5, 1.0))
# Default tolerance on the delivered restitution.
DEFAULT_TOL = 0.01
# Cost of a model: best time per point of one vectorised call on COST_POINTS points, over
# COST_REPEATS calls (best, not mean: the floor is what the model costs, the rest is the machine).
COST_POINTS = 256
COST_REPEATS = 5
# Points of the cost sample: spread over the domain every model accepts.
COST_EPS = (0.05, 0.99)
COST_XI = (0.0, 0.9)
# Adequate models within this factor of the cheapest adequate one cost the same (timings of the
# closed forms spread by ~1.2x from run to run); among them the most accurate is recommended.
COST_TIE = 1.5
# Symbol of the restitution each definition (engine.solver.RESTITUTIONS) requests, for the text output.
RESTITUTION_SYMBOL = {"energetic": "eps", "kinematic": "e_N"}


def xi_level(xi):
    """The paper's level of ``xi``: "small", "moderate" or "large"."""
    x = float(check_range("xi", xi, 0.0, 1.0, hi_open=True))
    return next(name for name, lo, hi in XI_LEVELS if lo <= x < hi)


def is_adequate(delivered, state, requested, exact_state, tol):
    """Adequate: ``|delivered - requested| <= tol`` and the exact end state (element-wise; NaN is not)."""
    delivered = np.asarray(delivered, dtype=float)
    close = np.abs(delivered - np.asarray(requested, dtype=float)) <= tol
    return close & (np.asarray(state) == np.asarray(exact_state))


def cheapest(names, adequate, costs, errors):
    """The recommended model among the adequate ones: cheapest, and most accurate within ``COST_TIE``.

    Parameters
    ----------
    names : sequence of str
    adequate : sequence of bool
    costs : mapping name -> seconds per evaluation
    errors : sequence of float
        ``|delivered - requested|`` per model.

    Returns
    -------
    str or None
        None when no model is adequate.
    """
    ok = [i for i, good in enumerate(adequate) if good]
    if not ok:
        return None
    floor = min(costs[names[i]] for i in ok)
    tied = [i for i in ok if costs[names[i]] <= COST_TIE * floor]
    return names[min(tied, key=lambda i: (errors[i], costs[names[i]]))]


def measure_costs(names=None):
    """Cost per evaluation (s) of each model: the best of ``COST_REPEATS`` vectorised calls.

    Parameters
    ----------
    names : sequence of str, optional
        Default: every registered model.

    Returns
    -------
    dict name -> float
    """
    names = tuple(models.MODELS) if names is None else tuple(names)
    return dict(_costs(names))


@functools.cache
def _costs(names):
    grid = np.linspace(0.0, 1.0, COST_POINTS)
    eps = COST_EPS[0] + (COST_EPS[1] - COST_EPS[0]) * grid
    xi = COST_XI[0] + (COST_XI[1] - COST_XI[0]) * grid[::-1]
    out = []
    for name in names:
        models.alpha(eps[:2], xi[:2], model=name)  # load and compile outside the clock
        best = np.inf
        for _ in range(COST_REPEATS):
            clock = time.perf_counter()
            models.alpha(eps, xi, model=name)
            best = min(best, time.perf_counter() - clock)
        out.append((name, best / COST_POINTS))
    return tuple(out)


@dataclass(frozen=True)
class ModelVerdict:
    """One model in one scene: its alpha, what it delivers, its cost, whether it is adequate."""

    name: str
    uses_xi: bool
    alpha: float
    delivered_eps: float
    state: str
    error: float
    cost_seconds: float
    adequate: bool
    note: str = ""


@dataclass(frozen=True)
class Advice:
    """The advisor's answer for one scene (see ``advise``)."""

    eps: float
    mass: float
    stiffness: float
    approach_speed: float
    accel: float
    tol: float
    restitution: str
    xi: float
    xi_level: str
    exact_alpha: float
    exact_state: str
    exact_eps: float
    exact_e_n: float
    models: tuple
    cheapest: str | None
    ignore_load: bool
    ignore_load_eps: float
    ignore_load_state: str

    def to_dict(self):
        """Plain data (for ``--json``)."""
        return asdict(self)


def _deliver(alpha, xi, restitution):
    """Restitution delivered in the definition requested (e_N = 0 without separation), end state, status."""
    r = impact(alpha, xi)
    delivered = r.eps if restitution == "energetic" else r.e_n
    return float(delivered), str(r.state), str(r.status)


def advise(
    eps,
    mass,
    stiffness,
    approach_speed,
    *,
    accel=None,
    force=None,
    tol=DEFAULT_TOL,
    restitution="energetic",
    costs=None,
):
    """Which model a scene needs.

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
        gravity included if it acts), or the constant force (N, >= 0; ``accel = force / mass``).
    tol : float
        Tolerance on the delivered restitution, > 0.
    restitution : {"energetic", "kinematic"}
        Stronge's energetic eps (Eq. 17) or Newton's kinematic e_N; the delivered restitution
        of every model is reported and judged in the same definition.
    costs : mapping name -> seconds, optional
        Cost per evaluation of each model; default ``measure_costs()`` (once per process).

    Returns
    -------
    Advice
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
    xi = float(influence_factor(m, k, v, a))
    sol = solve_alpha(e, xi, restitution=restitution)
    if not sol.ok:
        raise RuntimeError(f"exact alpha not found at eps = {e!r}, xi = {xi!r}: {sol.status}")
    exact_state = str(sol.state)
    costs = measure_costs() if costs is None else dict(costs)
    verdicts = []
    for name, model in models.MODELS.items():
        try:
            alpha = float(models.alpha(e, xi, model=name))
        except ValueError as exc:  # outside the model's domain: reported, never adequate
            verdicts.append(
                ModelVerdict(
                    name,
                    model.uses_xi,
                    np.nan,
                    np.nan,
                    "failed",
                    np.nan,
                    costs.get(name, np.nan),
                    False,
                    str(exc),
                )
            )
            continue
        if not (np.isfinite(alpha) and alpha >= 0.0):
            verdicts.append(
                ModelVerdict(
                    name,
                    model.uses_xi,
                    alpha,
                    np.nan,
                    "failed",
                    np.nan,
                    costs.get(name, np.nan),
                    False,
                    f"alpha = {alpha!r} is not a damping factor",
                )
            )
            continue
        delivered, state, status = _deliver(alpha, xi, restitution)
        good = bool(is_adequate(delivered, state, e, exact_state, tol))
        note = "" if status == "ok" else status
        verdicts.append(
            ModelVerdict(
                name,
                model.uses_xi,
                alpha,
                delivered,
                state,
                abs(delivered - e),
                costs.get(name, np.nan),
                good,
                note,
            )
        )
    ignore_eps, ignore_state, _ = _deliver(float(alpha_exact(e)), xi, restitution)
    best = cheapest(
        [mv.name for mv in verdicts],
        [mv.adequate for mv in verdicts],
        {mv.name: mv.cost_seconds for mv in verdicts},
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
        xi=xi,
        xi_level=xi_level(xi),
        exact_alpha=float(sol.alpha),
        exact_state=exact_state,
        exact_eps=float(sol.eps_reached),
        exact_e_n=float(sol.e_n_reached),
        models=tuple(verdicts),
        cheapest=best,
        ignore_load=bool(is_adequate(ignore_eps, ignore_state, e, exact_state, tol)),
        ignore_load_eps=ignore_eps,
        ignore_load_state=ignore_state,
    )


def format_advice(adv):
    """The advice as a text table (the command line's output)."""
    sym = RESTITUTION_SYMBOL[adv.restitution]
    lines = [
        f"restitution  {sym} = {adv.eps:g} ({adv.restitution})",
        f"xi           {adv.xi:.6g} ({adv.xi_level}: small < 0.1 <= moderate < 0.5 <= large)",
        f"exact alpha  {adv.exact_alpha:.10g} ({adv.exact_state}; eps = {adv.exact_eps:.6g}, "
        f"e_N = {adv.exact_e_n:.6g})",
        f"ignore load  {'yes' if adv.ignore_load else 'no'}: alpha at xi = 0 delivers {sym} = "
        f"{adv.ignore_load_eps:.6g} ({adv.ignore_load_state})",
        f"cheapest adequate model (|{sym} - {adv.eps:g}| <= {adv.tol:g}, same end state): {adv.cheapest}",
        "",
        f"{'model':22s} {'alpha':>12s} {'delivered ' + sym:>14s} {'end state':15s} {'ns/eval':>10s}"
        "  adequate",
    ]
    for mv in adv.models:
        verdict = ("yes" if mv.adequate else "no") + (f"  {mv.note}" if mv.note else "")
        lines.append(
            f"{mv.name:22s} {mv.alpha:12.6g} {mv.delivered_eps:14.6g} {mv.state:15s} "
            f"{mv.cost_seconds * 1e9:10.1f}  {verdict}"
        )
    return "\n".join(lines)
