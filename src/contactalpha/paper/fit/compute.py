"""Least-squares refits of Shen et al.'s closed forms (Eqs. 26, 34, 39, 40) to a computed surface.

Every fit minimises weighted *relative* residuals in alpha,
``r = sqrt(w) (alpha_model / alpha_surface - 1)``, with ``scipy.optimize.least_squares``
(trust-region reflective, ``loss`` as given; default ``linear``, plain least squares).
The default weights ``area`` are trapezoidal cell areas of the (eps, xi) grid,
normalised to mean 1: the loss then approximates the mean square relative error
over the domain, whatever the grid's refinement (the log-spaced xi near 0 would
otherwise dominate).  ``uniform`` weights count every grid point once.

The Eq. 40 and Eq. 39 fits use the exact Jacobian of their residuals (``shen.eq40_gradient``,
``shen.eq39_gradient``) unless ``jacobian="2-point"`` asks for scipy's finite difference.

Standard errors come from the Jacobian at the optimum,
``cov = s^2 (J^T J)^{-1}``, ``s^2 = sum r^2 / (n - p)``.  They treat the misfit as
noise; it is not (it is smooth model error), so they measure how sharply the
surface pins each constant, not a sampling error.  A published constant is
``consistent`` when ``|refit - published| <= VERDICT_K * SE``.

Points where the surface failed (nonzero ``status``) or has no finite alpha are
excluded, named and counted (``Exclusions``); a fit that does not converge
raises ``FitNotConverged`` from ``require_converged`` with scipy's message.
"""

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from contactalpha.engine.codes import STATUS
from contactalpha.engine.driver import impact
from contactalpha.engine.exact import alpha_exact
from contactalpha.models import shen

# Coverage factor of the verdict: about 95 % for a normal estimate.
VERDICT_K = 2.0
# Residual that stands in for a non-finite model value (and caps huge ones), so the optimiser backs off.
BAD_RESIDUAL = 1e3
# Function-evaluation budget of one least-squares fit: ours converge in under 200; a fit still
# going at 1000 is wandering (and on 12 000 points costs minutes), so it is reported as such.
MAX_NFEV = 1000
# Damping factors above this are not integrated for the restitution error (cost ~ alpha^2).
ALPHA_CAP = 1e6
# Eq. 26 is fitted to the xi = 0.2 section on eps <= this (the paper's region I, Fig. 5).
EQ26_EPS_MAX = 0.15
# Bounds of the per-slice Eq. 39 constants (tau, sigma, beta, b, eta): keep the exp term finite.
SLICE_BOUNDS = ([-1.0, 1e-4, 1e-6, -3.0, 1e-3], [1.0, 10.0, 1e3, 3.0, 1e3])
# Two per-slice fits whose costs agree to this relative tolerance found the same minimum, and the
# third start is skipped.  On the default surface the first two agree so in 105 of 123 sections,
# and in none of them did the third find a lower cost (it saves a quarter of the slice fits' time).
SLICE_SAME_COST = 1e-6
# Exponent a of (1 - eps)^a held fixed in the per-slice fits: it trades off with tau and sigma.
SLICE_A = 6.0
# Lower bound of positive constants of Eq. 40 in the global refit.
POSITIVE = {"beta": 1e-8, "width_coef": 1e-8}
# Evaluation budget of each other reading's refit (fit_eq40_alternative), reported for its RMS only.
# From the main refit's second term, sigma_a0 and "none" converge in 40-115 evaluations on our
# grids; the beta readings drift on (tau_one up, width_coef down) and would use all of MAX_NFEV,
# about 20 ms an evaluation on the default grid.
READING_MAX_NFEV = 150
# Continuation of the Eq. 40 refit: a first fit on every 4th row and column of the grid.
COARSE_STRIDE = 4
# ... done only with at least this many points per fitted constant.
COARSE_MIN_RATIO = 5
# xi grid of the Eq. 34 fit: the paper's range, uniform, independent of the surface grid.
S21_XI = np.linspace(0.0, 0.99, 100)
WEIGHTS = ("area", "uniform")
# Jacobians of the Eq. 40 and Eq. 39 fits: "exact" (shen.eq40_gradient, shen.eq39_gradient: one
# pass of about four model evaluations) or "2-point" (scipy's finite difference: one evaluation
# per constant, the path before issue 14; kept to measure against, benchmarks/bench_refit.py).
JACOBIANS = ("exact", "2-point")
LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")


class FitNotConverged(RuntimeError):
    """A least-squares fit stopped without meeting its convergence tests."""


@dataclass(frozen=True)
class Points:
    """Surface points used by a fit (flat arrays of equal length)."""

    eps: np.ndarray
    xi: np.ndarray
    alpha: np.ndarray
    lam: np.ndarray
    weight: np.ndarray

    def __len__(self):
        return self.eps.size

    def subset(self, mask):
        """The points where ``mask`` is True, weights renormalised to mean 1."""
        w = self.weight[mask]
        return Points(self.eps[mask], self.xi[mask], self.alpha[mask], self.lam[mask], w / w.mean())


@dataclass(frozen=True)
class Exclusions:
    """Surface points left out of the fits, and why."""

    eps: np.ndarray
    xi: np.ndarray
    reason: list

    @property
    def count(self):
        """Number of excluded points."""
        return int(self.eps.size)

    def counts(self):
        """Number of excluded points per reason."""
        reasons, n = np.unique(np.asarray(self.reason, dtype=str), return_counts=True)
        return dict(zip(reasons.tolist(), n.tolist(), strict=True))

    def describe(self, limit=10):
        """One line: how many points, why, and the first ``limit`` of them."""
        if not self.count:
            return "0 points excluded"
        rows = list(zip(self.eps, self.xi, self.reason, strict=True))[:limit]
        listed = ", ".join(f"(eps={e:g}, xi={x:g}: {r})" for e, x, r in rows)
        head = "; ".join(f"{n} {r}" for r, n in self.counts().items())
        more = "" if self.count <= limit else f" ... and {self.count - limit} more"
        return f"{self.count} points excluded ({head}): {listed}{more}"


@dataclass
class FitResult:
    """Outcome of one least-squares fit.

    Attributes
    ----------
    label : what was fitted.
    names : constant names, in order.
    x0, x, se : start, optimum and standard error (NaN where the surface does not determine it).
    cost : half the sum of squared (weighted) residuals at the optimum.
    converged : scipy's ``status > 0``; ``message`` says why it stopped.
    n_points : residuals fitted.
    """

    label: str
    names: list
    x0: np.ndarray
    x: np.ndarray
    se: np.ndarray
    cost: float
    nfev: int
    converged: bool
    message: str
    n_points: int
    loss: str = "linear"
    extra: dict = field(default_factory=dict)

    def values(self):
        """Fitted constants as a dict."""
        return dict(zip(self.names, self.x.tolist(), strict=True))

    @property
    def rms(self):
        """Root mean square of the (weighted) residual at the optimum."""
        return float(np.sqrt(2.0 * self.cost / max(self.n_points, 1)))


def require_converged(*fits):
    """Raise ``FitNotConverged`` naming every fit among ``fits`` that did not converge."""
    bad = [f"{f.label}: {f.message} (after {f.nfev} evaluations)" for f in fits if not f.converged]
    if bad:
        raise FitNotConverged("least-squares fit did not converge: " + "; ".join(bad))


def _check_choice(name, value, valid):
    if value not in valid:
        raise ValueError(f"{name} = {value!r} is not one of the valid values {list(valid)}")
    return value


def standard_errors(jac, cost, n):
    """Standard errors from the Jacobian of the residuals at the optimum (NaN if not determined)."""
    jac = np.asarray(jac, dtype=float)
    p = jac.shape[1]
    if n <= p or np.linalg.matrix_rank(jac) < p:
        return np.full(p, np.nan)
    s2 = 2.0 * cost / (n - p)
    cov = s2 * np.linalg.inv(jac.T @ jac)
    return np.sqrt(np.clip(np.diag(cov), 0.0, None))


def least_squares_fit(
    residuals,
    x0,
    names,
    label,
    *,
    bounds=(-np.inf, np.inf),
    loss="linear",
    max_nfev=MAX_NFEV,
    jac=None,
):
    """Minimise ``residuals(x)`` from ``x0`` with ``least_squares`` and return a ``FitResult``.

    ``jac(x)``, if given, returns ``(residuals(x), d residuals / d x)`` exactly; otherwise the
    Jacobian is scipy's 2-point finite difference.  Residuals that are not finite or exceed
    ``BAD_RESIDUAL`` are replaced by it (so the optimiser backs off) and get zero rows.
    """
    _check_choice("loss", loss, LOSSES)
    x0 = np.asarray(x0, dtype=float)

    def safe(x):
        r = np.clip(residuals(x), -BAD_RESIDUAL, BAD_RESIDUAL)  # NaN stays NaN
        r[np.isnan(r)] = BAD_RESIDUAL
        return r

    def safe_jac(x):
        r, J = jac(x)
        clipped = ~(np.abs(r) <= BAD_RESIDUAL)
        return np.where(clipped[:, None] | ~np.isfinite(J), 0.0, J)

    res = least_squares(
        safe,
        x0,
        jac="2-point" if jac is None else safe_jac,
        bounds=bounds,
        loss=loss,
        x_scale="jac",
        max_nfev=max_nfev,
        method="trf",
    )
    n = res.fun.size
    plain_cost = 0.5 * float(np.sum(res.fun**2))
    return FitResult(
        label=label,
        names=list(names),
        x0=x0,
        x=res.x,
        se=standard_errors(res.jac, plain_cost, n),
        cost=plain_cost,
        nfev=int(res.nfev),
        converged=bool(res.status > 0),
        message=str(res.message),
        n_points=n,
        loss=loss,
    )


def _trapezoid_widths(values):
    v = np.asarray(values, dtype=float)
    if v.size <= 1:
        return np.ones(v.size)
    edges = np.concatenate([[v[0]], 0.5 * (v[1:] + v[:-1]), [v[-1]]])
    return np.diff(edges)


def surface_points(ds, weights="area"):
    """Split a surface Dataset into fit points (xi > 0), zero-load points (xi = 0) and exclusions.

    Parameters
    ----------
    ds : xarray.Dataset
        The surface (dims ``epsilon``, ``xi``; ``alpha``, ``lambda``, ``status``).
    weights : {"area", "uniform"}
        Residual weights (module docstring).

    Returns
    -------
    loaded : Points
        Valid points with xi > 0 and alpha > 0.
    unloaded : Points
        Valid points at xi = 0 (for the zero-load branch).
    excluded : Exclusions
        Points with a nonzero status, a missing alpha, or alpha = 0 (eps = 1,
        where a relative residual is undefined).
    """
    _check_choice("weights", weights, WEIGHTS)
    eps, xi = ds["epsilon"].values, ds["xi"].values
    E, X = np.meshgrid(eps, xi, indexing="ij")
    alpha = ds["alpha"].values.astype(float)
    status = ds["status"].values if "status" in ds else np.zeros(alpha.shape, dtype=int)
    lam = ds["lambda"].values if "lambda" in ds else np.full(alpha.shape, np.nan)
    reason = np.full(alpha.shape, "", dtype=object)
    reason[~np.isfinite(alpha)] = "alpha missing"
    failed = status != 0
    reason[failed] = [f"solver status {int(s)} ({STATUS.get(int(s), 'unknown')})" for s in status[failed]]
    reason[(reason == "") & (alpha <= 0)] = "alpha = 0: relative residual undefined"
    bad = reason != ""
    if weights == "area":
        pos = xi > 0
        wx = np.ones(xi.size)
        wx[pos] = _trapezoid_widths(xi[pos])
        W = np.outer(_trapezoid_widths(eps), wx)
    else:
        W = np.ones(alpha.shape)

    def pick(mask):
        w = W[mask]
        w = w / w.mean() if w.size else w
        return Points(E[mask], X[mask], alpha[mask], lam[mask], w)

    excluded = Exclusions(E[bad], X[bad], reason[bad].tolist())
    return pick(~bad & (X > 0)), pick(~bad & (X == 0)), excluded


def eq40_fit_start(reading, beta_start=None):
    """Starting constants of the Eq. 40 refit: the published values (``beta`` may be overridden)."""
    start = {k: shen.PUBLISHED[k] for k in shen.reading_constants(reading)}
    if beta_start is not None and "beta" in start:
        start["beta"] = float(beta_start)
    return start


def eq40_model(points, values, reading):
    """Eq. 40 (0 < xi < 1) at ``points`` with the constants ``values`` (others as published)."""
    c = {**shen.PUBLISHED, **values}
    first, second = shen.eq40_terms(points.eps, points.xi, c, reading)
    return first + second


def fit_eq40(
    points, reading=shen.BEST_READING, *, start=None, loss="linear", max_nfev=MAX_NFEV, jacobian="exact"
):
    """Refit every constant of Eq. 40's loaded branch under ``reading``, from ``start``.

    Parameters
    ----------
    points : Points
        Fit points (xi > 0).
    reading : str
        A key of ``shen.READINGS``.
    start : dict, optional
        Starting constants; default the published values (``eq40_fit_start``).
    loss : str
        ``least_squares`` loss.
    max_nfev : int
        Evaluation budget.
    jacobian : {"exact", "2-point"}
        ``JACOBIANS``.

    Returns
    -------
    FitResult
    """
    _check_choice("jacobian", jacobian, JACOBIANS)
    start = eq40_fit_start(reading) if start is None else dict(start)
    names = list(start)
    sw = np.sqrt(points.weight)
    lo = np.array([POSITIVE.get(k, -np.inf) for k in names])

    def residuals(x):
        with np.errstate(all="ignore"):
            return sw * (eq40_model(points, dict(zip(names, x, strict=True)), reading) / points.alpha - 1.0)

    scale = sw / points.alpha

    def jac(x):
        c = {**shen.PUBLISHED, **dict(zip(names, x, strict=True))}
        with np.errstate(all="ignore"):
            value, grad = shen.eq40_gradient(points.eps, points.xi, c, reading, names)
            return scale * value - sw, scale[:, None] * grad

    x0 = np.maximum(np.array([start[k] for k in names], dtype=float), lo)
    fit = least_squares_fit(
        residuals,
        x0,
        names,
        f"Eq. 40 ({reading})",
        bounds=(lo, np.inf),
        loss=loss,
        max_nfev=max_nfev,
        jac=jac if jacobian == "exact" else None,
    )
    fit.extra["reading"] = reading
    return fit


def fit_eq40_surface(ds, reading=shen.BEST_READING, *, weights="area", coarse_stride=COARSE_STRIDE, **opts):
    """``fit_eq40`` on a surface, by continuation: first every ``coarse_stride``-th row and column.

    Both stages start from the published constants' basin: the coarse fit starts
    at them, the full fit at the coarse optimum.  On our surface a direct fit on
    the full grid stops early (``ftol``) in a poorer local minimum.  The coarse
    stage is skipped when it would have fewer than ``COARSE_MIN_RATIO`` points
    per constant, and its result is not used if it did not converge.  ``opts``
    go to ``fit_eq40``.

    Returns
    -------
    FitResult
        The full-grid fit; ``extra["coarse"]`` describes the first stage (or None).
    """
    loaded, _, _ = surface_points(ds, weights=weights)
    start = eq40_fit_start(reading)
    coarse = None
    pts = coarse_points(ds, len(start), weights=weights, coarse_stride=coarse_stride)
    if pts is not None:
        coarse = fit_eq40(pts, reading, start=start, **opts)
        if coarse.converged:  # otherwise the full fit starts from the published values
            start = coarse.values()
    full = fit_eq40(loaded, reading, start=start, **opts)
    if coarse is not None:
        full.extra["coarse"] = {
            "points": coarse.n_points,
            "rms": coarse.rms,
            "nfev": coarse.nfev,
            "converged": coarse.converged,
            "message": coarse.message,
        }
    full.x0 = np.array([eq40_fit_start(reading)[k] for k in full.names])
    return full


def coarse_points(ds, n_constants, *, weights="area", coarse_stride=COARSE_STRIDE):
    """Fit points of every ``coarse_stride``-th row and column of ``ds``.

    None when ``coarse_stride`` is 1 or the sub-grid has fewer than ``COARSE_MIN_RATIO``
    points per constant (of ``n_constants``).
    """
    if coarse_stride <= 1:
        return None
    sub = ds.isel(epsilon=slice(None, None, coarse_stride), xi=slice(None, None, coarse_stride))
    pts, _, _ = surface_points(sub, weights=weights)
    return pts if len(pts) >= COARSE_MIN_RATIO * n_constants else None


def fit_eq40_alternative(ds, reading, main, *, weights="area", max_nfev=READING_MAX_NFEV, **opts):
    """Another reading of Eq. 40, refit on all points for comparison with the main refit ``main``.

    Only its RMS error is reported (``report.readings_markdown``).  It starts from the
    published first-term constants of ``reading`` and ``main``'s second-term constants (the
    second term is the same under every reading), with at most ``max_nfev`` evaluations
    (``READING_MAX_NFEV``); a fit that needs more is reported as not converged.  ``opts`` go
    to ``fit_eq40``.
    """
    loaded, _, _ = surface_points(ds, weights=weights)
    second = main.values()
    start = {k: second.get(k, v) if k in shen.SECOND_TERM else v for k, v in eq40_fit_start(reading).items()}
    f = fit_eq40(loaded, reading, start=start, max_nfev=max_nfev, **opts)
    f.x0 = np.array([eq40_fit_start(reading)[k] for k in f.names])
    return f


def rms_area(rel, weight):
    """Weighted RMS of the relative errors ``rel`` (NaN left out), weights as the fits'."""
    rel, weight = np.asarray(rel, dtype=float), np.asarray(weight, dtype=float)
    return float(np.sqrt(np.nansum(weight * rel**2) / np.sum(weight[np.isfinite(rel)])))


def fit_eq39_slice(eps, xi, alpha, lam, weight=None, a=SLICE_A, jacobian="exact"):
    """Eq. 39 on one xi section: tau, sigma, beta, b and eta = eta_r / eta_c, with lambda measured.

    sigma, beta and eta are fitted as logarithms, inside ``SLICE_BOUNDS``.
    Three starts (the sigma reading, the beta reading, Eq. 26) guard against
    local minima, the third only when the first two disagree (``SLICE_SAME_COST``);
    the best converged one is kept and ``extra["at_bound"]``
    names constants that ended on a bound.  ``weight`` defaults to uniform; ``jacobian``
    is one of ``JACOBIANS``.
    """
    _check_choice("jacobian", jacobian, JACOBIANS)
    eps, alpha, lam = (np.asarray(v, dtype=float) for v in (eps, alpha, lam))
    sw = np.ones_like(eps) if weight is None else np.sqrt(weight)
    names = ["tau", "sigma", "beta", "b", "eta"]
    logged = np.array([False, True, True, False, True])
    width = shen.printed_width(xi)
    tau = shen.printed_tau(xi)
    starts = ([tau, width, 1.0, 0.0, 1.0], [tau, 1.0, width, 0.0, 1.0], [0.01, 0.011, 0.113, 0.0, 1.0])

    def to_internal(v):
        v = np.array(v, dtype=float)
        v[logged] = np.log(v[logged])
        return v

    def residuals(p):
        t, s, be, b, et = np.where(logged, np.exp(p), p)
        model = shen.eq39(eps, xi, tau=t, sigma=s, beta=be, a=a, lam=lam, b=b, eta_c=1.0, eta_r=et)
        return sw * (model / alpha - 1.0)

    scale = sw / alpha

    def jac(p):
        v = np.where(logged, np.exp(p), p)
        t, s, be, b, et = v
        model, g = shen.eq39_gradient(
            eps, xi, tau=t, sigma=s, beta=be, a=a, lam=lam, b=b, eta_c=1.0, eta_r=et
        )
        # d/d ln(v) = v d/dv for the logged constants
        grad = np.column_stack([g[k] for k in ("tau", "sigma", "beta", "b", "eta_r")])
        grad *= np.where(logged, v, 1.0)
        return scale * model - sw, scale[:, None] * grad

    lo, hi = to_internal(SLICE_BOUNDS[0]), to_internal(SLICE_BOUNDS[1])
    label = f"Eq. 39 at xi = {xi:g}"
    fits: list = []
    for s in starts:
        if len(fits) == 2 and _same_minimum(*fits):
            break  # the first two starts agree: the third is not needed
        fits.append(
            least_squares_fit(
                residuals,
                np.clip(to_internal(s), lo, hi),
                names,
                label,
                bounds=(lo, hi),
                jac=jac if jacobian == "exact" else None,
            )
        )
    best = min([f for f in fits if f.converged] or fits, key=lambda f: f.cost)
    ends = np.isclose(best.x, lo) | np.isclose(best.x, hi)
    best.extra["at_bound"] = [n for n, end in zip(names, ends, strict=True) if end]
    best.x0 = np.where(logged, np.exp(best.x0), best.x0)
    best.x = np.where(logged, np.exp(best.x), best.x)
    best.se = np.where(logged, best.x * best.se, best.se)
    return best


def _same_minimum(f, g):
    return f.converged and g.converged and abs(f.cost - g.cost) <= SLICE_SAME_COST * min(f.cost, g.cost)


def fit_eq39_slices(ds, xi_values=None, jacobian="exact"):
    """Per-section fits of Eq. 39 on the xi > 0 columns of ``ds`` (or those in ``xi_values``).

    ``jacobian``: ``JACOBIANS``.

    Returns
    -------
    list of FitResult
        One per section with at least 6 valid points; ``extra`` holds ``xi``,
        ``at_bound``, ``eps_min`` and ``second_at_min`` (the second term at it).
    """
    loaded, _, _ = surface_points(ds, weights="uniform")
    xs = np.unique(loaded.xi) if xi_values is None else np.asarray(xi_values, dtype=float)
    out = []
    for x in xs:
        m = loaded.xi == x
        if np.count_nonzero(m) < 6:
            continue  # fewer points than constants: nothing to learn
        f = fit_eq39_slice(loaded.eps[m], float(x), loaded.alpha[m], loaded.lam[m], jacobian=jacobian)
        f.extra["xi"] = float(x)
        out.append(f)
    return _annotate_slices(out, loaded)


def reading_evidence(slices, share_min=0.1):
    """Which role the printed ``0.1568 xi^0.9`` plays, judged from per-section fits of Eq. 39.

    Only sections whose fit converged with no constant on a bound, and whose
    fitted first term carries at least ``share_min`` of alpha at the smallest
    eps, count.  For each role (sigma or beta) the score is the median
    ``|ln(fitted / (0.1568 xi^0.9))|``; the smaller wins.

    Returns
    -------
    dict
        ``sections`` used, ``sigma_score``, ``beta_score``, ``tau_score`` (median
        ``|tau - (1 - xi^0.05)|``), ``role`` ("sigma", "beta" or "none": no
        section counts) and ``reading`` (the ``shen.READINGS`` key it implies).
    """
    used, ls, lb, lt = [], [], [], []
    for f in slices:
        if not f.converged or f.extra.get("at_bound"):
            continue
        v, x = f.values(), f.extra["xi"]
        e0 = f.extra["eps_min"]
        first = shen.first_term(e0, v["tau"], v["sigma"], v["beta"], SLICE_A)
        if first / (first + f.extra["second_at_min"]) < share_min:
            continue
        width = shen.printed_width(x)
        used.append(x)
        ls.append(abs(np.log(v["sigma"] / width)))
        lb.append(abs(np.log(v["beta"] / width)))
        lt.append(abs(v["tau"] - shen.printed_tau(x)))
    if not used:
        nan = float("nan")
        return {"sections": [], "sigma_score": nan, "beta_score": nan, "tau_score": nan, "role": "none"}
    s, b = float(np.median(ls)), float(np.median(lb))
    role = "sigma" if s < b else "beta"
    return {
        "sections": used,
        "sigma_score": s,
        "beta_score": b,
        "tau_score": float(np.median(lt)),
        "role": role,
        "reading": f"{role}_a6",
    }


def _annotate_slices(slices, loaded):
    """Add ``eps_min`` and the second term at it to each slice fit (for ``reading_evidence``)."""
    for f in slices:
        x = f.extra["xi"]
        m = loaded.xi == x
        i = np.argmin(loaded.eps[m])
        e0, lam0 = loaded.eps[m][i], loaded.lam[m][i]
        v = f.values()
        second = shen.eq39(
            e0, x, tau=0.0, sigma=1.0, beta=np.inf, a=0.0, lam=lam0, b=v["b"], eta_c=1.0, eta_r=v["eta"]
        )
        f.extra.update(eps_min=float(e0), second_at_min=float(second))
    return slices


def slice_model(points, slices):
    """Alpha of the per-section Eq. 39 fits at ``points`` (NaN where a section has no fit)."""
    out = np.full(len(points), np.nan)
    for f in slices:
        m = points.xi == f.extra["xi"]
        v = f.values()
        out[m] = shen.eq39(
            points.eps[m], f.extra["xi"], tau=v["tau"], sigma=v["sigma"], beta=v["beta"], a=SLICE_A,
            lam=points.lam[m], b=v["b"], eta_c=1.0, eta_r=v["eta"],
        )  # fmt: skip
    return out


def fit_eq26(ds, xi=0.2, eps_max=EQ26_EPS_MAX):
    """EXP of Eq. 26 fitted to the ``xi`` section on ``eps <= eps_max``, from the published constants."""
    loaded, _, _ = surface_points(ds, weights="uniform")
    m = (loaded.xi == xi) & (loaded.eps <= eps_max)
    if np.count_nonzero(m) < 4:
        raise ValueError(
            f"the xi = {xi!r} section has {np.count_nonzero(m)} valid points with eps <= {eps_max!r}; "
            "valid: at least 4 (put xi on the surface grid, or raise eps_max)"
        )
    eps, alpha = loaded.eps[m], loaded.alpha[m]
    names = list(shen.EQ26_PUBLISHED)
    x0 = [shen.EQ26_PUBLISHED[k] for k in names]
    fit = least_squares_fit(
        lambda p: shen.eq26(eps, *p) / alpha - 1.0,
        x0,
        names,
        f"Eq. 26 at xi = {xi:g}, eps <= {eps_max:g}",
        bounds=([-np.inf, 1e-8, 1e-8], np.inf),
    )
    fit.extra.update(xi=float(xi), eps_max=float(eps_max))
    return fit


def fit_zero_load(eps):
    """Exponent p of ``3 (1 - eps) / (2 eps^p)`` fitted to the exact xi = 0 relation on ``eps``."""
    eps = np.asarray(eps, dtype=float)
    eps = eps[(eps > 0) & (eps < 1)]
    exact = alpha_exact(eps)
    return least_squares_fit(
        lambda p: shen.zero_load(eps, p[0]) / exact - 1.0,
        [shen.ZERO_LOAD_EXP],
        ["zero_load_exp"],
        "Eq. 40, xi = 0 branch, against the exact relation",
    )


def fit_s21(xi=None):
    """The factor 0.851 of Eq. 34 fitted to s1 (Eq. 31) on ``xi`` (default ``S21_XI``), relative residuals."""
    xi = S21_XI if xi is None else np.asarray(xi, dtype=float)
    target = shen.s1(xi)
    S = shen.contact_factor(xi)
    return least_squares_fit(
        lambda p: p[0] * S / target - 1.0, [shen.S21_COEF], ["s21_coef"], "Eq. 34 factor against Eq. 31"
    )


def verdicts(fit, published, k=VERDICT_K, undetermined=None):
    """Compare each fitted constant with its published value.

    Returns
    -------
    dict
        name -> ``published, refit, se, rel_change, verdict, why``; the verdict
        is ``consistent`` (within ``k`` SE), ``inconsistent``, ``undetermined``
        (the surface does not fix it: SE is NaN) or ``not printed`` (the text
        does not give it, ``undetermined`` names it).
    """
    undetermined = undetermined or {}
    out = {}
    for name, x, se in zip(fit.names, fit.x, fit.se, strict=True):
        p = float(published[name])
        rel = (x - p) / p if p != 0 else np.nan
        if name in undetermined:
            verdict, why = "not printed", undetermined[name]
        elif not np.isfinite(se):
            verdict, why = "undetermined", "the surface does not fix it (singular Jacobian or too few points)"
        elif abs(x - p) <= k * se:
            verdict, why = "consistent", f"|refit - published| = {abs(x - p):.3g} <= {k:g} SE = {k * se:.3g}"
        else:
            verdict, why = "inconsistent", f"|refit - published| = {abs(x - p):.3g} > {k:g} SE = {k * se:.3g}"
        out[name] = {
            "published": p,
            "refit": float(x),
            "se": float(se),
            "rel_change": float(rel),
            "verdict": verdict,
            "why": why,
        }
    return out


def produced_restitution(alpha_model, xi, alpha_cap=ALPHA_CAP):
    """Stronge's eps that ``alpha_model`` actually produces at ``xi``, through the impact engine.

    Returns
    -------
    eps : ndarray
        NaN where alpha is not finite, negative or above ``alpha_cap``, or the
        integration failed.
    skipped : dict
        reason -> count.
    """
    a = np.asarray(alpha_model, dtype=float)
    xi = np.broadcast_to(np.asarray(xi, dtype=float), a.shape)
    usable = np.isfinite(a) & (a >= 0) & (a <= alpha_cap)
    skipped = {
        "alpha not finite": int(np.count_nonzero(~np.isfinite(a))),
        "alpha < 0": int(np.count_nonzero(np.isfinite(a) & (a < 0))),
        f"alpha > {alpha_cap:g}": int(np.count_nonzero(np.isfinite(a) & (a > alpha_cap))),
    }
    eps = np.full(a.shape, np.nan)
    if np.any(usable):
        r = impact(a[usable], xi[usable])
        eps[usable] = r.eps
        skipped["integration failed"] = int(np.count_nonzero(~r.ok))
    return eps, {k: v for k, v in skipped.items() if v}


def error_stats(alpha_model, points, with_restitution=True):
    """Relative alpha error and restitution error of a model at ``points``.

    Returns
    -------
    dict
        ``n``, ``alpha_rel_max``, ``alpha_rel_rms``, ``alpha_rel_rms_area``
        (weighted as the fit), ``worst`` (eps, xi of the max), and with
        ``with_restitution`` ``eps_abs_max``, ``eps_abs_rms``, ``eps_abs_rms_area``
        and ``skipped`` (points not integrated, by reason).  Statistics skip NaN;
        ``n_invalid`` counts them.
    """
    a = np.asarray(alpha_model, dtype=float)
    rel = a / points.alpha - 1.0
    ok = np.isfinite(rel)
    stats = {"n": len(points), "n_invalid": int(np.count_nonzero(~ok))}
    stats.update(_summary("alpha_rel", rel, points))
    if with_restitution:
        eps, skipped = produced_restitution(a, points.xi)
        stats.update(_summary("eps_abs", eps - points.eps, points))
        stats["skipped"] = skipped
    return stats


def _summary(prefix, err, points):
    ok = np.isfinite(err)
    if not np.any(ok):
        return {f"{prefix}_max": np.nan, f"{prefix}_rms": np.nan, f"{prefix}_rms_area": np.nan}
    e, w = np.abs(err[ok]), points.weight[ok]
    i = np.argmax(e)
    return {
        f"{prefix}_max": float(e[i]),
        f"{prefix}_rms": float(np.sqrt(np.mean(e**2))),
        f"{prefix}_rms_area": float(np.sqrt(np.sum(w * e**2) / np.sum(w))),
        f"{prefix}_worst": [float(points.eps[ok][i]), float(points.xi[ok][i])],
    }
