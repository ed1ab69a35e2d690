"""Speed against accuracy: error and cost of each alpha solver, where each fails, and scaling.

Every measurement solves the same problem, alpha for a target Stronge
restitution ``eps`` at load ``xi`` (docs/science.md, "The problem"), with one of:

- ``engine``: the adaptive DOP853 engine with sensitivities and Newton
  (``solve_alpha``, ``guess="formula"``, ``exact_at_zero=False`` so xi = 0 is
  integrated too), started like the others;
- ``engine-table``: the same with the default start from the shipped exact
  table, i.e. what ``solve_alpha`` does for a user: often one impact that
  confirms the tabulated alpha;
- ``rk4``: fixed-step classical RK4 (``fixedstep.impact_rk4``) under Brent's
  method (``reference.alpha_bracketed``);
- ``scipy-RK45``, ``scipy-DOP853``, ``scipy-Radau``, ``scipy-LSODA``:
  ``solve_ivp`` with events (``reference.impact_scipy_limited``) under Brent.

The setting of a method is its ``rtol`` (adaptive methods; ``atol = ATOL_RATIO
* rtol``) or its step ``h`` (rk4).  Error is the relative error of alpha and
the error of the eps that alpha really produces, both against a reference:
the exact relation at xi = 0, elsewhere the engine at ``REF_RTOL`` checked by
SciPy's DOP853 and by RK4 at a small step (``reference_point``).  All methods
but ``engine-table`` start from the exact unloaded alpha, and on the xi = 0
column (where that is the answer) from Hu & Guo's alpha (``unloaded_guess``).  Cost is the
wall time of one alpha solve and its right-hand-side evaluations.  Note that
one engine evaluation also advances two sensitivities.
"""

import os
import time
from contextlib import contextmanager
from dataclasses import asdict, dataclass

import numpy as np

from contactalpha.baselines.fixedstep import impact_rk4
from contactalpha.baselines.reference import alpha_bracketed, impact_scipy_limited
from contactalpha.engine.codes import (
    END_STATES,
    OK,
    SOL_ALPHA,
    SOL_IMPACTS,
    SOL_NFEV,
    SOL_STATE,
    SOL_STATUS,
    STATUS,
)
from contactalpha.engine.driver import MAX_STEPS, impact
from contactalpha.engine.exact import alpha_exact, restitution_exact
from contactalpha.engine.scaling import scaled_load
from contactalpha.engine.solver import solve_alpha, solve_kernel
from contactalpha.validation import check_eps, check_xi

# The regimes of the work-precision chart: name -> (eps, xi).
REGIMES = {
    "benign": (0.5, 0.2),
    "stiff ridge": (0.01, 0.005),
    "creep": (0.05, 0.9),
    "high load": (0.5, 0.99),
    "unloaded (exact)": (0.1, 0.0),
}
SCIPY_METHODS = ("RK45", "DOP853", "Radau", "LSODA")
METHODS = ("engine", "engine-table", "rk4") + tuple(f"scipy-{m}" for m in SCIPY_METHODS)
# atol / rtol: the ratio of the engine's defaults (1e-14 / 1e-12).
ATOL_RATIO = 1e-2
# Root tolerance (eps for Newton, relative alpha for Brent) per unit rtol, so
# the root-finder never dominates the integrator's error; floored where
# double precision cannot go further.
ROOT_RATIO = 1.0
ROOT_FLOOR = 1e-13
# Brent's tolerance for RK4, whose setting is a step, not a tolerance.
RK4_ROOT_RTOL = 1e-14
# Reference: the engine at its tightest tolerance, checked by two independent integrators.
REF_RTOL = 1e-13
REF_SCIPY_RTOL = 1e-13
REF_RK4_STEP = 1e-4
# RHS budget of one SciPy impact, its "step limit": ~10 s of Python time, and
# a few times what the stiff ridge needs at rtol = 1e-13.
SCIPY_MAX_NFEV = 1_000_000
# Relative error of alpha above which a solve counts as failed (issue 7).
FAIL_ERROR = 1e-6
# Failure categories, most serious last; a point gets the first that applies
# in the order: status failures, wrong end state, error, ok.
CATEGORIES = (
    "ok",
    "error > 1e-6",
    "wrong end state",
    "missed event",
    "step limit",
    "no root bracketed",
    "other",
)
# Timing: repeat a call until one batch lasts this long; best of BATCHES.
MIN_BATCH_SECONDS = 0.05
BATCHES = 3
# Copies of a point timed together for the engine: its per-point cost in a grid.
ENGINE_BATCH = 64


@dataclass(frozen=True)
class AlphaSolve:
    """One alpha solve by one method: the answer, how it ended, and what it cost."""

    method: str
    setting: float
    alpha: float
    state: str
    status: str
    impacts: int
    nfev: int
    seconds: float = np.nan


def root_tolerance(rtol):
    """Root tolerance used with integrator tolerance ``rtol``."""
    return max(ROOT_FLOOR, ROOT_RATIO * rtol)


def _engine_options(rtol, method="engine"):
    guess = "table" if method == "engine-table" else "formula"
    return {
        "rtol": rtol,
        "atol": ATOL_RATIO * rtol,
        "tol": root_tolerance(rtol),
        "exact_at_zero": False,
        "guess": guess,
    }


def unloaded_guess(eps):
    """Hu & Guo's alpha (paper Eq. 25), the start of every method on the xi = 0 column.

    Elsewhere every method starts from the exact unloaded alpha, but at
    xi = 0 that is the answer itself, and a loose root tolerance would return
    it untouched: the column would measure nothing.
    """
    return 1.5 * (1.0 - eps) / eps


def solve_with(method, setting, eps, xi, *, max_nfev=SCIPY_MAX_NFEV, alpha0=None):
    """Solve alpha for ``(eps, xi)`` with ``method`` at ``setting`` (rtol, or step for rk4).

    ``alpha0`` overrides the starting alpha (default: the exact unloaded
    alpha; ``engine-table`` always starts from the shipped exact table).

    Returns
    -------
    AlphaSolve
        Failures carry NaN ``alpha`` and the reason in ``status``.
    """
    eps = float(check_eps(eps))
    xi = float(check_xi(xi))
    if method == "engine" and alpha0 is not None:
        opts = _engine_options(setting)
        out = solve_kernel(
            eps, float(scaled_load(xi)), float(alpha0), opts["tol"], opts["rtol"], opts["atol"], MAX_STEPS
        )
        status = int(out[SOL_STATUS])
        alpha = float(out[SOL_ALPHA]) if status == OK else np.nan
        state = END_STATES[int(np.nan_to_num(out[SOL_STATE]))]
        return AlphaSolve(
            method, setting, alpha, state, STATUS[status], int(out[SOL_IMPACTS]), int(out[SOL_NFEV])
        )
    if method in ("engine", "engine-table"):
        s = solve_alpha(eps, xi, **_engine_options(setting, method))
        return AlphaSolve(
            method, setting, float(s.alpha), str(s.state), str(s.status), int(s.impacts), int(s.nfev)
        )
    if method == "rk4":

        def one_impact(a):
            return impact_rk4(a, xi, h=setting)

        rtol = RK4_ROOT_RTOL
    elif method.startswith("scipy-") and method[6:] in SCIPY_METHODS:

        def one_impact(a):
            return impact_scipy_limited(
                a, xi, method=method[6:], rtol=setting, atol=ATOL_RATIO * setting, max_nfev=max_nfev
            )

        rtol = max(root_tolerance(setting), 1e-14)
    else:
        raise ValueError(f"method = {method!r} is not known; valid: {', '.join(METHODS)}")
    alpha0 = float(alpha_exact(eps)) if alpha0 is None else float(alpha0)
    b = alpha_bracketed(eps, one_impact, alpha0=alpha0, rtol=rtol)
    return AlphaSolve(method, setting, b.alpha, b.state, b.status, b.impacts, b.nfev)


@contextmanager
def numba_threads(n):
    """Run the enclosed code with ``n`` numba threads, then restore the previous number."""
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(int(n))
    try:
        yield
    finally:
        numba.set_num_threads(before)


def seconds_per_call(fn):
    """Wall time of ``fn()`` and its last result: best of ``BATCHES`` batches of >= ``MIN_BATCH_SECONDS``."""
    best = np.inf
    for _ in range(BATCHES):
        n = 0
        start = time.perf_counter()
        while True:
            result = fn()
            n += 1
            elapsed = time.perf_counter() - start
            if elapsed >= MIN_BATCH_SECONDS:
                break
        best = min(best, elapsed / n)
        if elapsed > 10 * MIN_BATCH_SECONDS * BATCHES:
            break  # a slow call: one batch is precise enough, and repeats cost too much
    return best, result


def timed_solve(method, setting, eps, xi, **kwargs):
    """``solve_with`` plus its wall time per alpha solve, on one thread.

    The engine is timed on ``ENGINE_BATCH`` copies of the point in one
    ``solve_alpha`` call, divided by the copies: its cost per point of a grid,
    without the fixed cost of one Python call.  The other methods solve one
    point per call.
    """
    with numba_threads(1):
        if method.startswith("engine") and kwargs.get("alpha0") is None:
            result = solve_with(method, setting, eps, xi, **kwargs)
            batch = np.full(ENGINE_BATCH, float(eps))
            seconds, _ = seconds_per_call(lambda: solve_alpha(batch, xi, **_engine_options(setting, method)))
            seconds /= ENGINE_BATCH
        else:
            if not method.startswith("scipy-"):
                solve_with(method, setting, eps, xi, **kwargs)  # jitted: load or compile before timing
            seconds, result = seconds_per_call(lambda: solve_with(method, setting, eps, xi, **kwargs))
    return AlphaSolve(**{**asdict(result), "seconds": seconds})


def true_eps(alpha, xi):
    """The eps that ``alpha`` really produces: exact at xi = 0, else the engine at ``REF_RTOL``."""
    if not np.isfinite(alpha):
        return np.nan
    if xi == 0.0:
        return float(restitution_exact(alpha))
    return float(impact(alpha, xi, rtol=REF_RTOL, atol=ATOL_RATIO * REF_RTOL).eps)


def reference_point(eps, xi):
    """Reference alpha for ``(eps, xi)``, with its two independent confirmations.

    Returns
    -------
    dict
        ``alpha`` (exact at xi = 0, else the engine at ``REF_RTOL``),
        ``alpha_scipy`` (SciPy DOP853 at ``REF_SCIPY_RTOL``), ``alpha_rk4``
        (RK4 at step ``REF_RK4_STEP``), with their statuses, their largest
        relative deviation ``spread`` from ``alpha`` (NaN if either failed),
        and the end ``state``.
    """
    if xi == 0.0:
        alpha = float(alpha_exact(eps))
        state = "separation"
    else:
        ref = solve_with("engine-table", REF_RTOL, eps, xi)
        if ref.status != "ok":
            raise RuntimeError(f"reference engine solve failed at eps={eps}, xi={xi}: {ref.status}")
        alpha, state = ref.alpha, ref.state
    sp = solve_with("scipy-DOP853", REF_SCIPY_RTOL, eps, xi, max_nfev=SCIPY_MAX_NFEV)
    rk = solve_with("rk4", REF_RK4_STEP, eps, xi)
    dev_scipy = abs(sp.alpha / alpha - 1.0)
    dev_rk4 = abs(rk.alpha / alpha - 1.0)
    return {
        "eps": eps,
        "xi": xi,
        "alpha": alpha,
        "state": state,
        "alpha_scipy": sp.alpha,
        "status_scipy": sp.status,
        "alpha_rk4": rk.alpha,
        "status_rk4": rk.status,
        "spread": max(dev_scipy, dev_rk4) if sp.status == rk.status == "ok" else np.nan,
    }


def work_precision(eps, xi, alpha_ref, settings, **kwargs):
    """Error against cost at one ``(eps, xi)``.

    Parameters
    ----------
    eps, xi : float
        The point.
    alpha_ref : float
        Reference alpha (``reference_point``).
    settings : dict
        Method name -> sequence of settings (rtol, or step for rk4).

    Returns
    -------
    list of dict
        One row per method and setting: the ``AlphaSolve`` fields plus
        ``err_alpha`` (relative) and ``err_eps`` (absolute).
    """
    alpha0 = unloaded_guess(eps) if xi == 0.0 else None
    rows = []
    for method, values in settings.items():
        for setting in values:
            s = timed_solve(method, float(setting), eps, xi, alpha0=alpha0, **kwargs)
            err_alpha = abs(s.alpha / alpha_ref - 1.0) if np.isfinite(s.alpha) else np.nan
            err_eps = abs(true_eps(s.alpha, xi) - eps)
            rows.append({**asdict(s), "eps": eps, "xi": xi, "err_alpha": err_alpha, "err_eps": err_eps})
    return rows


def classify(status, state, alpha, alpha_ref, true_state):
    """Failure category (index into ``CATEGORIES``) of one solve.

    ``true_state`` is the end state the reference engine finds at the
    method's own ``alpha``.
    """
    if status == "missed event":
        return CATEGORIES.index("missed event")
    if status == "step limit exceeded":
        return CATEGORIES.index("step limit")
    if status == "no root bracketed":
        return CATEGORIES.index("no root bracketed")
    if status != "ok" or not np.isfinite(alpha):
        return CATEGORIES.index("other")
    if state != true_state:
        return CATEGORIES.index("wrong end state")
    if abs(alpha / alpha_ref - 1.0) > FAIL_ERROR:
        return CATEGORIES.index("error > 1e-6")
    return CATEGORIES.index("ok")


def reference_grid(eps, xi):
    """Reference alpha and state over a grid: the engine at default tolerances (exact at xi = 0)."""
    E, X = np.meshgrid(np.asarray(eps, float), np.asarray(xi, float), indexing="ij")
    s = solve_alpha(E, X)
    if not np.all(s.ok):
        raise RuntimeError(f"reference grid failed at {int((~s.ok).sum())} points")
    return s.alpha, s.state


def failure_map(method, setting, eps, xi, alpha_ref, **kwargs):
    """Solve every grid point with one method and classify each.

    Returns
    -------
    dict of ndarray, shape (len(eps), len(xi))
        ``category`` (index into ``CATEGORIES``), ``alpha``, ``err_alpha``,
        ``status``, ``state``, ``true_state`` and ``nfev``.
    """
    eps = np.asarray(eps, float)
    xi = np.asarray(xi, float)
    shape = (eps.size, xi.size)
    out = {k: np.full(shape, np.nan) for k in ("alpha", "err_alpha", "nfev")}
    out.update({k: np.empty(shape, dtype=object) for k in ("status", "state", "true_state")})
    out["category"] = np.zeros(shape, dtype=np.int8)
    for i, e in enumerate(eps):
        for j, x in enumerate(xi):
            s = solve_with(method, setting, e, x, **kwargs)
            true_state = str(impact(s.alpha, x).state) if np.isfinite(s.alpha) else "failed"
            out["alpha"][i, j] = s.alpha
            out["err_alpha"][i, j] = abs(s.alpha / alpha_ref[i, j] - 1.0)
            out["nfev"][i, j] = s.nfev
            out["status"][i, j] = s.status
            out["state"][i, j] = s.state
            out["true_state"][i, j] = true_state
            out["category"][i, j] = classify(s.status, s.state, s.alpha, alpha_ref[i, j], true_state)
    return out


def category_counts(category):
    """Number of grid points in each category, as a dict keyed by ``CATEGORIES``."""
    return {name: int(np.sum(np.asarray(category) == k)) for k, name in enumerate(CATEGORIES)}


def _best_time(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def square_grid(n):
    """An about ``n``-point (eps, xi) grid over the paper's domain, as two flat arrays."""
    side = max(2, int(round(np.sqrt(n))))
    E, X = np.meshgrid(np.linspace(0.01, 0.99, side), np.linspace(0.0, 0.99, side), indexing="ij")
    return E.ravel(), X.ravel()


def grid_timing(sizes, *, repeats=2):
    """Wall time of ``solve_alpha`` over square grids of about ``sizes`` points (all threads).

    Returns
    -------
    list of dict
        ``n`` (actual points), ``seconds`` (best of ``repeats``), ``failed`` points.
    """
    rows = []
    for n in sizes:
        E, X = square_grid(n)
        failed = int(np.sum(~solve_alpha(E, X).ok))
        rows.append(
            {
                "n": E.size,
                "seconds": _best_time(lambda E=E, X=X: solve_alpha(E, X), repeats),
                "failed": failed,
            }
        )
    return rows


def _best_wall_and_cpu(fn, repeats):
    """``(wall, cpu)`` seconds of the fastest of ``repeats`` calls; cpu counts every thread of the process."""
    best = (np.inf, np.nan)
    for _ in range(repeats):
        cpu, start = time.process_time(), time.perf_counter()
        fn()
        wall = time.perf_counter() - start
        if wall < best[0]:
            best = (wall, time.process_time() - cpu)
    return best


# Below this many busy cores a multi-threaded timing did not get its cores (other work held
# them): its speed-up says nothing about the library (``thread_timing``).
CORES_FREE_MIN = 0.75


def thread_timing(n, threads=(1, 2), *, repeats=2):
    """Wall and CPU time of an about ``n``-point grid solve with each number of numba threads.

    Each row also gives ``cores_busy = cpu / wall`` (the process's CPU time counts all its
    threads) and ``cores_free``: whether the run kept at least ``CORES_FREE_MIN`` of a core per
    thread busy.  On a machine where other work holds the cores a 2-thread run gets one core and
    its "speed-up" would be the machine's, not the library's; the report then says so.
    """
    import numba

    E, X = square_grid(n)
    before = numba.get_num_threads()
    rows = []
    try:
        for k in threads:
            numba.set_num_threads(int(k))
            wall, cpu = _best_wall_and_cpu(lambda: solve_alpha(E, X), repeats)
            rows.append(
                {
                    "threads": int(k),
                    "numba_threads": int(numba.get_num_threads()),
                    "n": E.size,
                    "seconds": wall,
                    "cpu_seconds": cpu,
                    "cores_busy": cpu / wall,
                    "cores_free": bool(cpu / wall >= CORES_FREE_MIN * k),
                    "load_average": list(os.getloadavg()),
                    "affinity": len(os.sched_getaffinity(0)),
                }
            )
    finally:
        numba.set_num_threads(before)
    return rows


def fit_power(x, y):
    """Least-squares fit ``y = c x^p`` in log-log; returns ``(p, c)``."""
    p, logc = np.polyfit(np.log(np.asarray(x, float)), np.log(np.asarray(y, float)), 1)
    return float(p), float(np.exp(logc))


def cost_vs_alpha(method, setting, xi, alphas, *, max_nfev=SCIPY_MAX_NFEV, repeats=3):
    """Cost of one impact against alpha at load ``xi``, for ``engine``, ``rk4`` or ``scipy-*``.

    Returns
    -------
    list of dict
        ``alpha``, ``nfev``, ``seconds``, ``state``, ``status`` per alpha.
    """
    if method == "engine":

        def run(a):
            return impact(a, xi, rtol=setting, atol=ATOL_RATIO * setting)
    elif method == "rk4":

        def run(a):
            return impact_rk4(a, xi, h=setting)
    else:

        def run(a):
            return impact_scipy_limited(
                a, xi, method=method[6:], rtol=setting, atol=ATOL_RATIO * setting, max_nfev=max_nfev
            )

    rows = []
    for a in alphas:
        r = run(float(a))
        seconds = _best_time(lambda a=a: run(float(a)), repeats if r.nfev < max_nfev else 1)
        rows.append(
            {
                "method": method,
                "xi": xi,
                "alpha": float(a),
                "nfev": int(r.nfev),
                "seconds": seconds,
                "state": str(r.state),
                "status": str(r.status),
            }
        )
    return rows


def ridge_share(eps, xi, *, eps_max=0.1, xi_max=0.1):
    """Share of a grid's cost spent on the ridge ``eps < eps_max, 0 < xi < xi_max``.

    Returns
    -------
    dict
        Points, RHS evaluations and wall time of the ridge and of the rest,
        and the ridge's share of each.
    """
    E, X = np.meshgrid(np.asarray(eps, float), np.asarray(xi, float), indexing="ij")
    ridge = (E < eps_max) & (X > 0.0) & (X < xi_max)
    out: dict[str, float] = {}
    for name, mask in (("ridge", ridge), ("rest", ~ridge)):
        s = solve_alpha(E[mask], X[mask])
        out[f"{name}_points"] = int(mask.sum())
        out[f"{name}_nfev"] = int(np.sum(s.nfev))
        out[f"{name}_seconds"] = _best_time(lambda mask=mask: solve_alpha(E[mask], X[mask]), 2)
    for key in ("points", "nfev", "seconds"):
        out[f"share_{key}"] = out[f"ridge_{key}"] / (out[f"ridge_{key}"] + out[f"rest_{key}"])
    return out


# --- whole studies: lists of flat rows, ready for a table -------------------------


def reference_rows(regimes=None):
    """``reference_point`` for each regime (default ``REGIMES``), with its name under ``regime``."""
    regimes = REGIMES if regimes is None else regimes
    return [{"regime": name, **reference_point(e, x)} for name, (e, x) in regimes.items()]


# Per-point fields of ``failure_map`` copied into ``failure_rows``.
FAILURE_FIELDS = ("alpha", "err_alpha", "nfev", "status", "state", "true_state")


def failure_rows(method, setting, eps, xi, **kwargs):
    """``failure_map`` of one method as flat rows (one per grid point), with ``category`` named."""
    alpha_ref, _ = reference_grid(eps, xi)
    fm = failure_map(method, setting, eps, xi, alpha_ref, **kwargs)
    rows = []
    for i, e in enumerate(eps):
        for j, x in enumerate(xi):
            row = {"method": method, "setting": float(setting), "eps": float(e), "xi": float(x)}
            row["alpha_ref"] = float(alpha_ref[i, j])
            row.update({k: fm[k][i, j] for k in FAILURE_FIELDS})
            row["category"] = CATEGORIES[fm["category"][i, j]]
            rows.append(row)
    return rows


def cost_to_reach(rows, method, target):
    """Least time per alpha solve of ``method`` among ``rows`` with ``err_alpha <= target`` (NaN if none)."""
    times = [r["seconds"] for r in rows if r["method"] == method and r["err_alpha"] <= target]
    return min(times) if times else np.nan


def scaling_study(sizes, thread_points, alpha_runs, alpha_fit_min, ridge_eps, ridge_xi):
    """Grid time against size and threads, impact cost against alpha, and the ridge's share.

    Parameters
    ----------
    sizes : sequence of int
        Approximate grid sizes (``square_grid``).
    thread_points : int
        Approximate grid size of the 1- against 2-thread timing.
    alpha_runs : dict
        Label -> ``(method, setting, xi, alphas)`` for ``cost_vs_alpha``.
    alpha_fit_min : float
        Smallest alpha in the fit of ``nfev = c alpha^p``.
    ridge_eps, ridge_xi : array_like
        The surface grid whose ridge share is measured (``ridge_share``).

    Returns
    -------
    dict
        ``grid``, ``grid_fit``, ``threads``, ``cost_vs_alpha``, ``alpha_fits``,
        ``alpha_fit_min`` and ``ridge``.
    """
    solve_alpha(np.array([0.5, 0.1]), np.array([0.2, 0.0]))  # compile / load before timing
    grid = grid_timing(sizes)
    p, c = fit_power([r["n"] for r in grid], [r["seconds"] for r in grid])
    costs = {}
    fits = {}
    for label, (method, setting, xi, alphas) in alpha_runs.items():
        with numba_threads(1):
            rows = cost_vs_alpha(method, setting, xi, alphas)
        costs[label] = rows
        use = [r for r in rows if r["status"] == "ok" and r["alpha"] >= alpha_fit_min]
        if len(use) >= 2:
            q, k = fit_power([r["alpha"] for r in use], [r["nfev"] for r in use])
            fits[label] = {"exponent": q, "prefactor": k, "points": len(use)}
    return {
        "grid": grid,
        "grid_fit": {"exponent": p, "prefactor": c},
        "threads": thread_timing(thread_points),
        "cost_vs_alpha": costs,
        "alpha_fits": fits,
        "alpha_fit_min": alpha_fit_min,
        "ridge": ridge_share(ridge_eps, ridge_xi),
    }
