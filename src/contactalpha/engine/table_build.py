"""One-off build of the exact-alpha table (``table.py`` holds the runtime lookup).

The node values are Newton solves of the engine at every node of the two
boundary-aligned grids described in ``table.py``; the splines are SciPy's
interpolating quintic tensor splines, re-expressed on uniform knots so that the
jitted evaluator needs no knot search.
"""

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contactalpha.io import json_text, write_atomic

from .boundary import separation_boundary
from .bspline import clamp_to_uniform
from .codes import OUT_DE_N, OUT_STATUS
from .driver import ATOL, MAX_STEPS, RTOL, impact, impact_many
from .scaling import scaled_load
from .solver import solve_alpha
from .table import (
    ARRAY_NAMES,
    DEFAULT_FILE,
    DEGREE,
    EPS_MIN,
    G_COUNT,
    G_FIRST,
    G_K_ETA,
    G_K_Q,
    G_N_ETA,
    G_N_P,
    G_S_ETA,
    G_S_P,
    G_STEP,
    KINEMATIC_ARRAY_NAMES,
    KINEMATIC_FILE,
    N_GEOM,
    N_K_GEOM,
    TABLE_FORMAT_VERSION,
    U_MIN,
    XI_MAX,
    XI_SCALE,
    AlphaTable,
    alpha_tabulated,
    checksum,
    eta_of_xi,
    kinematic_q,
)

# Smooth floor of the boundary position, in ln eps, and its softness.
B_FLOOR = U_MIN - 2.0
B_SOFTNESS = 0.1
# Below this xi the boundary lies far under B_FLOOR and is not searched for.
XI_BOUNDARY_MIN = 1e-6


@dataclass(frozen=True)
class TableSettings:
    """Grid and solver settings of ``build_table``; the defaults build the shipped table.

    They are the defaults of the workflow's ``models.table`` section
    (``workflow/schemas/config.schema.yaml``; tests/workflow/test_settings.py diffs the two).
    """

    n_eta: int = 277
    n_p: int = 101
    refine_n: int = 3
    tol: float = 1e-13
    rtol: float = 1e-12
    atol: float = 1e-14


@dataclass(frozen=True)
class TableCheckSettings:
    """Settings of the table check (``check_table``); defaults of the ``models.check`` section."""

    points: int = 2000
    seed: int = 0
    max_rel_err: float = 1e-6


@dataclass(frozen=True)
class KinematicTableSettings:
    """Grid and solver settings of ``build_kinematic_table``; the defaults build the shipped table.

    One region on a uniform (eta, q = ln e_N) grid: e_N > 0 only where the impact separates, so
    the kinematic alpha has no kink inside the domain (EPS_MIN <= e_N <= 1) to align a grid with.
    """

    # 139 x 51 nodes meet 2e-8 relative at 1000 random points (70 x 26: 1.7e-6).
    n_eta: int = 139
    n_q: int = 51
    tol: float = 1e-13
    rtol: float = 1e-12
    atol: float = 1e-14


def xi_of_eta(eta):
    """Inverse of ``eta_of_xi`` (bisection in log space; build time only)."""
    eta = np.asarray(eta, dtype=float)
    lo = np.zeros_like(eta)
    hi = np.full_like(eta, XI_MAX + 0.5 * (1 - XI_MAX))
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        below = np.log1p(mid / XI_SCALE) - np.log1p(-mid) < eta
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def soft_floor(b):
    """``B_FLOOR + s softplus((b - B_FLOOR)/s)``; -inf maps to B_FLOOR."""
    z = (np.asarray(b, dtype=float) - B_FLOOR) / B_SOFTNESS
    return B_FLOOR + B_SOFTNESS * np.logaddexp(0.0, z)


def _spline2d(eta, p, L):
    """Interpolating quintic tensor spline, refined so that every node is a knot."""
    from scipy.interpolate import RectBivariateSpline

    r = RectBivariateSpline(eta, p, L, kx=DEGREE, ky=DEGREE, s=0)
    tx, ty, c = r.tck
    c = c.reshape(len(tx) - DEGREE - 1, len(ty) - DEGREE - 1)
    tx, c = clamp_to_uniform(tx, c, DEGREE, eta, axis=0)
    ty, c = clamp_to_uniform(ty, c, DEGREE, p, axis=1)
    return tx, ty, np.ascontiguousarray(c)


def kinematic_slope_at_zero(xi, rtol=RTOL, atol=ATOL):
    """``d e_N / d alpha`` at ``alpha = 0`` (where e_N = 1), from the impact's sensitivities."""
    A = np.ascontiguousarray(np.atleast_1d(scaled_load(xi)), dtype=float).ravel()
    out = impact_many(np.zeros_like(A), A, float(rtol), float(atol), MAX_STEPS, threads=1)
    if np.any(out[:, OUT_STATUS] != 0):
        raise RuntimeError(f"table build: impact at alpha = 0 failed for xi = {np.asarray(xi)}")
    return out[:, OUT_DE_N].reshape(np.shape(xi))


def _node_values(eps, xi, tol, rtol, atol, restitution="energetic"):
    """``L`` at nodes; eps = 1 uses the slope of eps(alpha) (or e_N(alpha)) at alpha = 0."""
    eps = np.asarray(eps, dtype=float)
    xi = np.broadcast_to(np.asarray(xi, dtype=float), eps.shape)
    L = np.empty(eps.shape)
    one = eps >= 1.0
    if one.any():
        if restitution == "kinematic":
            slope = kinematic_slope_at_zero(xi[one], rtol, atol)
        else:
            slope = impact(0.0, xi[one], rtol=rtol, atol=atol).deps_dalpha
        L[one] = np.log(-1.0 / slope)
    sol = solve_alpha(
        eps[~one], xi[~one], tol=tol, rtol=rtol, atol=atol, guess="formula", restitution=restitution
    )
    if not np.all(sol.ok):
        bad = np.argwhere(~np.asarray(sol.ok)).ravel()
        raise RuntimeError(
            f"table build: alpha solve failed at {bad.size} nodes, e.g. "
            f"eps={eps[~one][bad[0]]!r}, xi={xi[~one][bad[0]]!r}: {sol.status[bad[0]]}"
        )
    e = eps[~one]
    L[~one] = np.log(sol.alpha * e / (1.0 - e))
    return L


def build_table(
    n_eta=TableSettings.n_eta,
    n_p=TableSettings.n_p,
    refine_n=TableSettings.refine_n,
    *,
    tol=TableSettings.tol,
    rtol=TableSettings.rtol,
    atol=TableSettings.atol,
    progress=None,
):
    """Compute the table: boundary, region S and region N node values, splines.

    Parameters
    ----------
    n_eta : int
        Rows in eta over [0, eta(XI_MAX)] (region S; region N gets as many
        rows per unit eta over its own range).
    n_p : int
        Columns in p over [0, 1] in region S.
    refine_n : int
        Region N gets ``refine_n`` times the row density and ``refine_n (n_p - 1) + 1``
        columns: on its non-separation side alpha turns on like ``exp(-C / sqrt(s))``
        past the creep boundary, which needs the finer spacing.
    tol, rtol, atol : float
        Solver settings for the node values.
    progress : callable or None
        Called with a message string after each stage.

    Returns
    -------
    AlphaTable
    """
    from scipy.interpolate import make_interp_spline
    from scipy.optimize import brentq

    say = progress or (lambda msg: None)
    eta_max = float(eta_of_xi(XI_MAX))
    eta = np.linspace(0.0, eta_max, n_eta)
    xi = xi_of_eta(eta)
    xi[0] = 0.0
    b = np.full(n_eta, -np.inf)
    search = xi >= XI_BOUNDARY_MIN
    _, eps_b, status = separation_boundary(xi[search], rtol=rtol, atol=atol)
    if np.any(status != 0):
        raise RuntimeError(f"table build: boundary search failed at xi = {xi[search][status != 0]}")
    b[search] = np.log(eps_b)
    b_eff = soft_floor(b)
    bs = make_interp_spline(eta, b_eff, k=DEGREE)
    b_t, b_c = clamp_to_uniform(bs.t, bs.c, DEGREE, eta)
    say(f"boundary: {search.sum()} rows searched")

    p = np.linspace(0.0, 1.0, n_p)
    u_s = b_eff[:, None] * (1.0 - p[None, :] ** 2)
    L_s = _node_values(np.exp(u_s), xi[:, None], tol, rtol, atol)
    say(f"region S: {L_s.size} nodes")

    eta_n_min = brentq(lambda e: float(bs(e)) - U_MIN, 0.0, eta_max)
    n_rows = max(DEGREE + 2, int(round(refine_n * (eta_max - eta_n_min) / (eta[1] - eta[0]))) + 1)
    eta_n = np.linspace(eta_n_min, eta_max, n_rows)
    p_n = np.linspace(0.0, 1.0, refine_n * (n_p - 1) + 1)
    xi_n = xi_of_eta(eta_n)
    b_n = bs(eta_n)
    u_n = b_n[:, None] - p_n[None, :] ** 2 * (b_n[:, None] - U_MIN)
    L_n = _node_values(np.exp(u_n), xi_n[:, None], tol, rtol, atol)
    say(f"region N: {L_n.size} nodes")

    s_tx, s_ty, s_c = _spline2d(eta, p, L_s)
    n_tx, n_ty, n_c = _spline2d(eta_n, p_n, L_n)
    meta = dict(
        format_version=TABLE_FORMAT_VERSION,
        eps_min=EPS_MIN,
        xi_max=XI_MAX,
        xi_scale=XI_SCALE,
        degree=DEGREE,
        n_eta=n_eta,
        n_p=n_p,
        n_eta_region_n=n_rows,
        n_p_region_n=len(p_n),
        tol=tol,
        rtol=rtol,
        atol=atol,
    )
    geom = np.empty(N_GEOM)
    for start, nodes in ((G_S_ETA, eta), (G_S_P, p), (G_N_ETA, eta_n), (G_N_P, p_n)):
        geom[start + G_FIRST] = nodes[0]
        geom[start + G_STEP] = nodes[1] - nodes[0]
        geom[start + G_COUNT] = nodes.size
    return AlphaTable(b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, geom, meta)


def build_kinematic_table(
    n_eta=KinematicTableSettings.n_eta,
    n_q=KinematicTableSettings.n_q,
    *,
    tol=KinematicTableSettings.tol,
    rtol=KinematicTableSettings.rtol,
    atol=KinematicTableSettings.atol,
    progress=None,
):
    """Compute the kinematic table: alpha(e_N, xi) node values on (eta, q = ln e_N) and their spline.

    Returns
    -------
    dict
        The arrays ``table.KINEMATIC_ARRAY_NAMES`` and ``meta``.
    """
    say = progress or (lambda msg: None)
    eta = np.linspace(0.0, float(eta_of_xi(XI_MAX)), n_eta)
    xi = xi_of_eta(eta)
    xi[0] = 0.0
    q = np.linspace(float(kinematic_q(EPS_MIN)), 0.0, n_q)
    e_n = np.exp(q)
    e_n[-1] = 1.0
    L = _node_values(np.broadcast_to(e_n, (n_eta, n_q)), xi[:, None], tol, rtol, atol, "kinematic")
    say(f"kinematic: {L.size} nodes")
    tx, ty, c = _spline2d(eta, q, L)
    geom = np.empty(N_K_GEOM)
    for start, nodes in ((G_K_ETA, eta), (G_K_Q, q)):
        geom[start + G_FIRST] = nodes[0]
        geom[start + G_STEP] = nodes[1] - nodes[0]
        geom[start + G_COUNT] = nodes.size
    meta = dict(
        format_version=TABLE_FORMAT_VERSION,
        restitution="kinematic",
        eps_min=EPS_MIN,
        xi_max=XI_MAX,
        xi_scale=XI_SCALE,
        degree=DEGREE,
        n_eta=n_eta,
        n_q=n_q,
        tol=tol,
        rtol=rtol,
        atol=atol,
    )
    return dict(zip(KINEMATIC_ARRAY_NAMES, (tx, ty, c, geom), strict=True), meta=meta)


def save_kinematic_table(table, path=KINEMATIC_FILE, **extra_meta):
    """Write the kinematic table (``build_kinematic_table``'s dict) to ``path`` (.npz) atomically."""
    arrays = {name: table[name] for name in KINEMATIC_ARRAY_NAMES}
    meta = dict(table["meta"], **extra_meta, sha256=checksum(arrays))

    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays, meta=json_text(meta))

    return write_atomic(Path(path), write)


def save_table(table, path, **extra_meta):
    """Write the table to ``path`` (.npz) atomically, with its metadata as JSON."""
    arrays = {name: getattr(table, name) for name in ARRAY_NAMES}
    meta = dict(table.meta, **extra_meta, sha256=checksum(arrays))

    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays, meta=json_text(meta))

    return write_atomic(Path(path), write)


def built_with(path, settings):
    """Whether the table file at ``path`` records every key of ``settings`` (grid, tolerances) as given.

    False for a missing or unreadable file: the workflow then builds a table with ``settings``.
    """
    try:
        with np.load(path) as z:
            meta = json.loads(str(z["meta"]))
    except (OSError, KeyError, ValueError):
        return False
    return all(meta.get(k) == v for k, v in settings.items())


def random_points(n, seed):
    """``n`` random (eps, xi) in the table's domain: half log-uniform in xi (the ridge), half uniform."""
    rng = np.random.default_rng(seed)
    eps = np.exp(rng.uniform(U_MIN, 0.0, n))
    xi = np.where(
        rng.random(n) < 0.5, np.exp(rng.uniform(np.log(1e-9), np.log(XI_MAX), n)), rng.uniform(0.0, XI_MAX, n)
    )
    return eps, xi


def check_table(
    path,
    *,
    n=TableCheckSettings.points,
    seed=TableCheckSettings.seed,
    shipped=None,
    restitution="energetic",
):
    """Accuracy of the table at ``path`` against ``solve_alpha``, and its distance to the shipped table.

    ``restitution="kinematic"`` checks a kinematic table (the random points' eps read as e_N);
    ``shipped`` defaults to the package's table of that definition.

    Returns
    -------
    dict
        ``max_rel_err``, ``median_rel_err``, ``worst`` (eps, xi), ``n``, and
        ``max_rel_diff_shipped`` (NaN when no shipped table can be read).
    """
    if shipped is None:
        shipped = KINEMATIC_FILE if restitution == "kinematic" else DEFAULT_FILE
    eps, xi = random_points(n, seed)
    ref = solve_alpha(eps, xi, tol=1e-13, guess="formula", restitution=restitution)
    if not np.all(ref.ok):
        raise RuntimeError(f"check_table: {int((~np.asarray(ref.ok)).sum())} reference solves failed")
    got = alpha_tabulated(eps, xi, path=path, restitution=restitution)
    rel = np.abs(got / ref.alpha - 1.0)
    i = int(np.argmax(rel))
    try:
        diff = float(
            np.max(np.abs(alpha_tabulated(eps, xi, path=shipped, restitution=restitution) / got - 1.0))
        )
    except (FileNotFoundError, ValueError):
        diff = float("nan")
    return dict(
        n=n,
        max_rel_err=float(rel.max()),
        median_rel_err=float(np.median(rel)),
        worst=(float(eps[i]), float(xi[i])),
        max_rel_diff_shipped=diff,
    )
