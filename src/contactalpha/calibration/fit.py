"""Least-squares fit of a law to drop-test data, profile-likelihood intervals, information criteria.

Noise models (stated, one per data kind): impact times and trajectory heights carry independent
Gaussian errors of one unknown standard deviation (s or m); apex heights carry independent
Gaussian errors of one unknown size on their logarithm (a relative error).  The unknown sigma is
profiled out, so the fit minimises the residual sum of squares RSS and the log-likelihood is
``-n/2 log(RSS/n)`` up to a constant.

Nuisance parameters, fitted with the law's: the first approach speed ``v0`` (m/s) and, for
times and trajectories, the first touchdown time ``t0`` (s).  Parameters are fitted in their
natural units, scale parameters (stiffness, damping) as log10.

Intervals are profile-likelihood intervals of each law parameter: the set of values whose
RSS, with every other parameter refitted, stays below ``RSS_min (1 + F / (n - p))``, ``F`` the
upper quantile of the F(1, n - p) distribution; exact for a linear model with unknown sigma.
An interval that reaches the parameter's valid range before the threshold is reported open
(its end is the range's end and ``bounded`` is False).

Model selection: AIC ``n log(RSS/n) + 2 (p + 1)`` and BIC ``n log(RSS/n) + (p + 1) log n``
(sigma counted); the law with the lowest AIC is selected.
"""

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, least_squares
from scipy.stats import f as f_dist

from . import sequence as seq_mod
from .band import e_n_band
from .data import first_guess
from .hypotheses import STIFFNESS

LEVEL = 0.95
# Residual scales: they only condition the optimiser (sigma is estimated).
SCALES = {"times": 1e-4, "heights": 1e-2, "trajectory": 1e-3}
# Starting stiffnesses when none is given, log-spaced inside the law's range.
STIFFNESS_STARTS = 4
# Relative finite-difference step of the Jacobian (well above the contacts' 1e-12 tolerance).
DIFF_STEP = 1e-6
# Stiffness held by a law whose stiffness the data cannot see, when no guess is given, N/m^1.5.
HELD_STIFFNESS = 1e8
# Starts fitted (the best by their residuals after the scan).
FITTED_STARTS = 2
# Values of a law's first parameter tried before each start's fit.
SCAN_POINTS = 16
# The first approach speed is fitted within this factor of its rigid-bounce guess.
V0_RANGE = 4.0
# A nuisance parameter this close to an end of its range (fraction of the range) is "at" it.
AT_BOUND = 1e-3
# Most residual evaluations of one refit along a profile (warm-started: a few suffice).
PROFILE_NFEV = 40
# Smallest first step of a profile, as a fraction of the parameter's range (fitting coordinates).
MIN_STEP = 1e-5
# An interval end is located to this fraction of the Wald standard error, and never more coarsely
# than this fraction of the bracket it lies in (a flat profile has a huge standard error).
END_TOL_SE = 0.01
END_TOL_BRACKET = 1e-3
# Most contacts a trajectory's sequence is followed for.
MAX_CONTACTS = 500


@dataclass(frozen=True)
class Setup:
    """What is known: ball mass (kg), the constant acceleration a = g + F/m (m/s^2), given settings.

    ``given`` holds contact-law settings that are known, not fitted (MuJoCo's impedance ``d``); a
    law that has one and finds it absent here uses its default (``hypotheses.Law.given``).
    """

    mass: float
    accel: float
    given: dict = field(default_factory=dict)


@dataclass
class LawFit:
    """One law fitted to one data set.

    Attributes
    ----------
    law : the law's name.
    values : fitted law parameters (natural units); fixed ones included.
    intervals : name -> (lo, hi) of the profile-likelihood interval at ``level``.
    bounded : name -> (lo bounded, hi bounded).
    nuisance : fitted ``v0`` and ``t0``.
    free : names fitted (law parameters then nuisance).
    fixed : law parameters held at their start (the data cannot see them).
    given : contact-law settings given, not fitted (in ``values`` too: MuJoCo's impedance).
    e_n_band : (e_N, lo, hi) of each separating contact at its fitted approach speed
        (``sequence.v_in``), with the interval at ``level`` (``band.e_n_band``); NaN without intervals.
    rss, sigma, n, p, aic, bic : fit statistics (sigma in the data's units; log units for heights).
    residuals : observed minus fitted, data units (log ratio for heights).
    sequence : the fitted bounce sequence (``sequence.Sequence``).
    status : "ok" or why the fit is not trustworthy.
    """

    law: str
    values: dict
    intervals: dict
    bounded: dict
    nuisance: dict
    free: tuple
    fixed: tuple
    rss: float
    sigma: float
    n: int
    p: int
    aic: float
    bic: float
    residuals: np.ndarray
    sequence: seq_mod.Sequence
    status: str = "ok"
    level: float = LEVEL
    evaluations: int = 0
    given: tuple = ()
    e_n_band: tuple = ()


class Problem:
    """The residual function of one law on one data set, over a chosen set of free parameters."""

    def __init__(self, law, data, setup, fixed_law=()):
        self.law, self.data, self.setup = law, data, setup
        self.law_free = tuple(p for p in law.params if p.name not in fixed_law)
        self.nuis = ("v0",) if data.kind == "heights" else ("t0", "v0")
        self.names = tuple(p.name for p in self.law_free) + self.nuis
        self.scale = SCALES[data.kind]
        self.evaluations = 0
        self.fixed_values = {}
        if data.kind == "heights":
            self.obs = np.log(data.values)
        else:
            self.obs = data.values
        # Nuisance bounds around the rigid first guess: they keep a bad law out of degenerate fits
        # (a huge v0 that ends the bouncing at the first contact) without touching a sound one.
        v0, _ = first_guess(data, setup.accel)
        speed = (v0 / V0_RANGE, v0 * V0_RANGE)
        self.bounds = [p.fit_bounds for p in self.law_free]
        if data.kind == "heights":
            self.bounds.append(speed)
        else:
            t0 = data.t[0] if data.kind == "times" else _trajectory_t0(data)
            half = 0.5 * (np.diff(data.t[:2])[0] if data.kind == "times" else 2.0 * v0 / setup.accel)
            self.bounds += [(t0 - half, t0 + half), speed]

    def unpack(self, x):
        """(law values, nuisance dict) of a fitting vector."""
        values = dict(self.fixed_values)
        for p, xi in zip(self.law_free, x, strict=False):
            values[p.name] = p.from_fit(xi)
        nuis = dict(zip(self.nuis, x[len(self.law_free) :], strict=True))
        return values, nuis

    def sequence(self, x):
        """The bounce sequence at ``x``."""
        values, nuis = self.unpack(x)
        d = self.data
        count = {"times": d.count, "heights": d.count - 1}.get(d.kind, MAX_CONTACTS)
        self.evaluations += 1
        return seq_mod.simulate(
            self.law, values, self.setup.mass, self.setup.accel, nuis["v0"], nuis.get("t0", 0.0), count
        )

    def predict(self, x):
        """Model values of the observations (log heights for heights)."""
        s = self.sequence(x)
        d = self.data
        if d.kind == "times":
            return seq_mod.touchdown_times(s, d.count)
        if d.kind == "heights":
            h = np.concatenate([[s.v_in[0] ** 2 / (2.0 * s.accel)], seq_mod.apex_heights(s, d.count - 1)])
            return np.log(np.maximum(h, 1e-300))
        return seq_mod.height_at(s, d.t)

    def residuals(self, x):
        """(observed - model) / scale; a failed contact gives a large finite penalty."""
        r = (self.obs - self.predict(x)) / self.scale
        return np.where(np.isfinite(r), r, 1e12)


def _solve(problem, x0):
    lo, hi = np.array(problem.bounds).T
    x0 = np.clip(np.asarray(x0, dtype=float), lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo))
    return least_squares(
        problem.residuals, x0, bounds=(lo, hi), x_scale="jac", diff_step=DIFF_STEP, xtol=1e-12, ftol=1e-12
    )


def _starts(problem, stiffness_guess):
    law, data, setup = problem.law, problem.data, problem.setup
    v0, e = first_guess(data, setup.accel)
    e = float(np.clip(e, 0.05, 0.99))
    t0 = {"times": float(data.t[0]) if data.t.size else 0.0, "heights": 0.0}.get(data.kind)
    if t0 is None:
        t0 = _trajectory_t0(data)
    stiff = next(p for p in law.params if p.name == "stiffness")
    if stiffness_guess and stiff.unit == STIFFNESS.unit:
        ks = (stiffness_guess,)
    else:  # a few decades apart inside the law's range
        ks = tuple(np.geomspace(stiff.lo * 1e2, stiff.hi * 1e-2, STIFFNESS_STARTS))
    for k in ks:
        values = {**law.start(e, v0 * e), "stiffness": k}
        x = [p.to_fit(np.clip(values[p.name], p.lo, p.hi)) for p in problem.law_free]
        x += [v0] if data.kind == "heights" else [t0, v0]
        yield _scan_first(problem, np.array(x))


def _scan_first(problem, x):
    """``x`` with its first coordinate moved to the best of a coarse scan (a start, not a fit)."""
    lo, hi = problem.bounds[0]
    best, best_cost = x, _cost(problem, x)
    for value in np.linspace(lo, hi, SCAN_POINTS + 2)[1:-1]:
        trial = x.copy()
        trial[0] = value
        cost = _cost(problem, trial)
        if cost < best_cost:
            best, best_cost = trial, cost
    return best


def _cost(problem, x):
    r = problem.residuals(x)
    return float(r @ r)


def _trajectory_t0(data):
    z, t = data.values, data.t
    top = int(np.argmax(z))
    low = np.flatnonzero(z[top:] <= 0.02 * z[top])
    return float(t[top + low[0]]) if low.size else float(t[-1])


def _threshold(n, p, level):
    dof = max(n - p, 1)
    return 1.0 + f_dist.ppf(level, 1, dof) / dof


def fit_hypothesis(law, data, setup, *, stiffness_guess=None, level=LEVEL, intervals=True):
    """Fit ``law`` to ``data``; return a ``LawFit`` with profile-likelihood intervals.

    Parameters
    ----------
    law : hypotheses.Hypothesis
    data : data.DropData
    setup : Setup
    stiffness_guess : float, optional
        Start the stiffness there (N/m^1.5) instead of a few decades apart; a parameter the
        data cannot see (``timing_only`` with heights) is held at it (default 1e8).
    level : float
        Confidence level of the intervals.
    intervals : bool
        False skips the profiles (faster; intervals are NaN).
    """
    fixed = tuple(p.name for p in law.params if p.timing_only and data.kind == "heights")
    problem = Problem(law, data, setup, fixed)
    problem.fixed_values = {name: (stiffness_guess or HELD_STIFFNESS) for name in fixed}
    problem.fixed_values.update({name: setup.given.get(name, d) for name, d in law.given.items()})
    best = None
    starts = sorted(_starts(problem, stiffness_guess), key=lambda x0: _cost(problem, x0))
    for x0 in starts[:FITTED_STARTS]:
        sol = _solve(problem, x0)
        if best is None or sol.cost < best.cost:
            best = sol
    assert best is not None  # FITTED_STARTS >= 1 and there is always a start
    x = best.x
    r = problem.residuals(x) * problem.scale
    n, p = r.size, x.size
    rss = float(r @ r)
    values, nuis = problem.unpack(x)
    out = LawFit(
        law=law.name,
        values=values,
        intervals={},
        bounded={},
        nuisance=nuis,
        free=problem.names,
        fixed=fixed,
        rss=rss,
        sigma=math.sqrt(rss / max(n - p, 1)),
        n=n,
        p=p,
        aic=_ic(rss, n, p, 2.0),
        bic=_ic(rss, n, p, math.log(n)),
        residuals=r,
        sequence=problem.sequence(x),
        status="ok" if best.success else f"optimiser: {best.message}",
        level=level,
        given=tuple(law.given),
    )
    at_bound = [
        name
        for name, xi, (lo, hi) in zip(problem.names, x, problem.bounds, strict=True)
        if name in problem.nuis and min(xi - lo, hi - xi) <= AT_BOUND * (hi - lo)
    ]
    if at_bound:
        out.status = f"{', '.join(at_bound)} at the end of its range: the law does not follow the data"
    if out.sequence.status != "ok":
        out.status = f"a contact of the fitted sequence failed ({out.sequence.status})"
    if n <= p:
        out.status = f"{n} observations for {p} parameters: no intervals"
        intervals = False
    out.e_n_band = e_n_band(problem, best, level, interval=intervals)
    for j, prm in enumerate(problem.law_free):
        if intervals:
            lo, hi, blo, bhi = _profile(problem, best, j, _threshold(n, p, level) * rss)
            out.intervals[prm.name] = (prm.from_fit(lo), prm.from_fit(hi))
            out.bounded[prm.name] = (blo, bhi)
        else:
            out.intervals[prm.name] = (math.nan, math.nan)
            out.bounded[prm.name] = (False, False)
    out.evaluations = problem.evaluations
    return out


def _ic(rss, n, p, per_param):
    return n * math.log(max(rss, 1e-300) / n) + per_param * (p + 1)


def _crossing(fn, inside, outside, xtol):
    """Where ``fn`` crosses 0 between ``inside`` (< 0) and ``outside`` (> 0).

    ``outside`` when the warm-started refits do not show the sign change again (a rough profile).
    """
    a, b = sorted((inside, outside))
    try:
        return brentq(fn, a, b, xtol=xtol, rtol=1e-10, maxiter=40)
    except ValueError:
        return outside


def _profile(problem, best, j, limit):
    """Profile interval of fitting coordinate ``j``: ``(lo, hi, lo bounded, hi bounded)``."""
    x_hat = best.x
    scale2 = problem.scale**2
    # Wald standard error from the Jacobian, only to size the first steps.
    jac = best.jac
    rss = 2.0 * best.cost * scale2
    dof = max(jac.shape[0] - jac.shape[1], 1)
    try:
        cov = np.linalg.inv(jac.T @ jac) * (2.0 * best.cost / dof)
        se = math.sqrt(max(cov[j, j], 0.0))
    except np.linalg.LinAlgError:
        se = math.nan
    if not np.isfinite(se) or se == 0.0:
        se = 1e-3 * max(1.0, abs(x_hat[j]))
    lo_b, hi_b = problem.bounds[j]
    others = [i for i in range(x_hat.size) if i != j]
    sub_bounds = [problem.bounds[i] for i in others]
    warm = {"x": x_hat[others].copy()}

    def excess(value):
        """Profiled RSS at coordinate ``value`` minus the limit."""

        def res(y):
            full = np.empty_like(x_hat)
            full[j] = value
            full[others] = y
            return problem.residuals(full)

        lo, hi = np.array(sub_bounds).T
        y0 = np.clip(warm["x"], lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo))
        opts = {"bounds": (lo, hi), "x_scale": "jac", "diff_step": DIFF_STEP, "xtol": 1e-10}
        sol = least_squares(res, y0, max_nfev=PROFILE_NFEV, **opts)
        if sol.status == 0:  # not converged within the cap: an unconverged refit would shrink the interval
            sol = least_squares(res, sol.x, max_nfev=10 * PROFILE_NFEV, **opts)
        warm["x"] = sol.x
        return 2.0 * sol.cost * scale2 - limit

    ends = []
    for sign in (-1.0, 1.0):
        warm["x"] = x_hat[others].copy()
        inside, f_in = x_hat[j], rss - limit
        edge = lo_b if sign < 0 else hi_b
        if (inside - edge) * sign >= 0.0:  # the estimate sits on its range's end
            ends.append((edge, False))
            continue
        step, end, bounded = max(2.0 * se, MIN_STEP * (hi_b - lo_b)), None, True
        for _ in range(40):
            trial = inside + sign * step
            if (trial - edge) * sign >= 0.0:
                trial = edge
            f_t = excess(trial)
            if f_t > 0.0:
                # The refits along the way are warm-started, so the sign at ``inside`` is the one seen.
                xtol = min(END_TOL_SE * se, END_TOL_BRACKET * abs(trial - inside))
                end = trial if f_in >= 0.0 else _crossing(excess, inside, trial, xtol)
                break
            if trial == edge:
                end, bounded = edge, False
                break
            inside, f_in = trial, f_t
            step *= 2.0
        if end is None:
            end, bounded = inside, False
        ends.append((end, bounded))
    (lo, blo), (hi, bhi) = ends
    return lo, hi, blo, bhi
