"""Exact alpha(eps, xi) at formula speed: a quintic spline table in boundary-aligned coordinates.

What is tabulated
    ``L = ln(alpha eps / (1 - eps))``, which is finite and smooth at both
    ends: ``alpha ~ 1/eps`` for small eps without load, and
    ``alpha ~ (1 - eps) / (-deps/dalpha at alpha = 0)`` as eps -> 1.

Coordinates
    ``eta = ln(1 + xi / XI_SCALE) - ln(1 - xi)`` is 0 at xi = 0 (the exact
    column is a grid line), logarithmic through the ridge near xi ~ eps^2 ..
    eps (SCIENCE.md Sect. 6), and stretches xi -> 1.  ``u = ln eps``.
    alpha is continuous but not smooth across the separation boundary
    ``u = b(eta)`` (``boundary.py``), so the plane is cut along it into a
    separation region S (``u >= b``) and a non-separation region N
    (``u < b``), each mapped to ``p`` in [0, 1] and splined on its own.
    On both sides alpha behaves like ``c1 s + c2 s^{5/2} + ...`` in the
    distance ``s`` from the boundary (the Hertz force near x = 0), so ``p``
    grows like ``sqrt(s)``: in ``p`` the expansion is a polynomial.
    S: ``u = b (1 - p^2)`` (p = 1 at eps = 1); N: ``u = b - p^2 (b - U_MIN)``.
    Where the boundary leaves the domain (small xi) a smooth floor
    ``b_eff = F + s softplus((b - F)/s)`` keeps the mapping smooth in eta.

Accuracy is verified against ``solve_alpha`` at random points off the nodes
(tests/test_table.py); the build records its grid and tolerances, and
``load_table`` refuses a file whose format version differs.
"""

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit, prange

from .bspline import clamp_to_uniform, eval_1d_uniform, eval_2d_uniform

# Bumped whenever the meaning of the stored arrays changes.
TABLE_FORMAT_VERSION = 3
# Domain of the table: eps in [EPS_MIN, 1], xi in [0, XI_MAX].
EPS_MIN = 0.01
XI_MAX = 0.99
U_MIN = float(np.log(EPS_MIN))
# xi below which the eta coordinate is linear in xi (the ridge starts near eps^2 >= 1e-4).
XI_SCALE = 1e-10
# Smooth floor of the boundary position, in ln eps, and its softness.
B_FLOOR = U_MIN - 2.0
B_SOFTNESS = 0.1
# Below this xi the boundary lies far under B_FLOOR and is not searched for.
XI_BOUNDARY_MIN = 1e-6
# Spline degree in both directions.
DEGREE = 5
DEFAULT_FILE = Path(__file__).with_name("data") / "alpha_table.npz"
# Arrays stored in the table file, in the argument order of ``alpha_from_table``.
ARRAY_NAMES = ("b_t", "b_c", "s_tx", "s_ty", "s_c", "n_tx", "n_ty", "n_c", "geom")


@njit(cache=True, error_model="numpy")
def eta_of_xi(xi):
    """Load coordinate ``eta(xi)``; 0 at xi = 0."""
    return np.log1p(xi / XI_SCALE) - np.log1p(-xi)


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


@dataclass(frozen=True)
class AlphaTable:
    """Spline data of the exact table (see module docstring)."""

    b_t: np.ndarray
    b_c: np.ndarray
    s_tx: np.ndarray
    s_ty: np.ndarray
    s_c: np.ndarray
    n_tx: np.ndarray
    n_ty: np.ndarray
    n_c: np.ndarray
    geom: np.ndarray
    meta: dict


# Layout of ``AlphaTable.geom``: (first node, spacing, node count) of each uniform grid.
G_S_ETA, G_S_P, G_N_ETA, G_N_P = 0, 3, 6, 9


@njit(cache=True, error_model="numpy")
def alpha_from_table(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g):
    """Scalar, numba-callable alpha(eps, xi) from the table arrays (no range checks).

    Valid for ``EPS_MIN <= eps <= 1`` and ``0 <= xi <= XI_MAX``.
    """
    if eps >= 1.0:
        return 0.0
    u = np.log(eps)
    eta = eta_of_xi(xi)
    b = eval_1d_uniform(b_t, b_c, g[0], g[1], int(g[2]), eta)
    if u >= b:
        p = np.sqrt(1.0 - u / b)
        L = eval_2d_uniform(s_tx, s_ty, s_c, g[0], g[1], int(g[2]), g[3], g[4], int(g[5]), eta, p)
    else:
        p = np.sqrt((b - u) / (b - U_MIN))
        L = eval_2d_uniform(n_tx, n_ty, n_c, g[6], g[7], int(g[8]), g[9], g[10], int(g[11]), eta, p)
    return np.exp(L) * (1.0 - eps) / eps


@njit(cache=True, parallel=True, error_model="numpy")
def alpha_from_table_many(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g):
    """``alpha_from_table`` over flat arrays, in parallel."""
    out = np.empty(eps.size)
    for i in prange(eps.size):
        out[i] = alpha_from_table(eps[i], xi[i], b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g)
    return out


@njit(cache=True, error_model="numpy")
def alpha_from_table_serial(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g):
    """``alpha_from_table_many`` in one thread, for small inputs."""
    out = np.empty(eps.size)
    for i in range(eps.size):
        out[i] = alpha_from_table(eps[i], xi[i], b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g)
    return out


# Below this many points one thread is faster than waking the others.
PARALLEL_MIN_LOOKUPS = 4096


def _spline2d(eta, p, L):
    """Interpolating quintic tensor spline, refined so that every node is a knot."""
    from scipy.interpolate import RectBivariateSpline

    r = RectBivariateSpline(eta, p, L, kx=DEGREE, ky=DEGREE, s=0)
    tx, ty, c = r.tck
    c = c.reshape(len(tx) - DEGREE - 1, len(ty) - DEGREE - 1)
    tx, c = clamp_to_uniform(tx, c, DEGREE, eta, axis=0)
    ty, c = clamp_to_uniform(ty, c, DEGREE, p, axis=1)
    return tx, ty, np.ascontiguousarray(c)


def _node_values(eps, xi, tol, rtol, atol):
    """``L`` at nodes; eps = 1 uses the slope of eps(alpha) at alpha = 0."""
    from .impact import impact
    from .solver import solve_alpha

    eps = np.asarray(eps, dtype=float)
    xi = np.broadcast_to(np.asarray(xi, dtype=float), eps.shape)
    L = np.empty(eps.shape)
    one = eps >= 1.0
    if one.any():
        slope = impact(0.0, xi[one], rtol=rtol, atol=atol).deps_dalpha
        L[one] = np.log(-1.0 / slope)
    sol = solve_alpha(eps[~one], xi[~one], tol=tol, rtol=rtol, atol=atol, guess="formula")
    if not np.all(sol.ok):
        bad = np.argwhere(~np.asarray(sol.ok)).ravel()
        raise RuntimeError(
            f"table build: alpha solve failed at {bad.size} nodes, e.g. "
            f"eps={eps[~one][bad[0]]!r}, xi={xi[~one][bad[0]]!r}: {sol.status[bad[0]]}"
        )
    e = eps[~one]
    L[~one] = np.log(sol.alpha * e / (1.0 - e))
    return L


def build_table(n_eta=277, n_p=101, refine_n=2, *, tol=1e-13, rtol=1e-12, atol=1e-14, progress=None):
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

    from .boundary import separation_boundary

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
    geom = np.array(
        [
            eta[0],
            eta[1] - eta[0],
            eta.size,
            p[0],
            p[1] - p[0],
            p.size,
            eta_n[0],
            eta_n[1] - eta_n[0],
            eta_n.size,
            p_n[0],
            p_n[1] - p_n[0],
            p_n.size,
        ]
    )
    return AlphaTable(b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, geom, meta)


def save_table(table, path, **extra_meta):
    """Write the table to ``path`` (.npz) atomically, with its metadata as JSON."""
    import os
    import tempfile

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    meta = dict(table.meta, **extra_meta)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp.npz")
    os.close(fd)
    try:
        np.savez_compressed(
            tmp,
            b_t=table.b_t,
            b_c=table.b_c,
            s_tx=table.s_tx,
            s_ty=table.s_ty,
            s_c=table.s_c,
            n_tx=table.n_tx,
            n_ty=table.n_ty,
            n_c=table.n_c,
            geom=table.geom,
            meta=json.dumps(meta),
        )
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def load_table(path=DEFAULT_FILE):
    """Read a table written by ``save_table``; refuse a different format version."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"exact-alpha table {path} not found; build it with `snakemake -c2 table`")
    with np.load(path) as z:
        meta = json.loads(str(z["meta"]))
        if meta.get("format_version") != TABLE_FORMAT_VERSION:
            raise ValueError(
                f"exact-alpha table {path} has format version {meta.get('format_version')!r}, "
                f"this package reads version {TABLE_FORMAT_VERSION}; rebuild it with `snakemake -c2 table`"
            )
        arrays = {k: np.ascontiguousarray(z[k]) for k in ARRAY_NAMES}
        return AlphaTable(**arrays, meta=meta)


_CACHE = {}


def _arrays(path=DEFAULT_FILE):
    key = str(path)
    if key not in _CACHE:
        t = load_table(path)
        _CACHE[key] = tuple(getattr(t, name) for name in ARRAY_NAMES)
    return _CACHE[key]


@njit(cache=True, error_model="numpy")
def _first_outside(values, lo, hi):
    """Index of the first value outside [lo, hi] (NaN included), or -1."""
    for i in range(values.size):
        v = values[i]
        if not (lo <= v <= hi):
            return i
    return -1


def alpha_tabulated(eps, xi, *, path=DEFAULT_FILE):
    """Exact alpha(eps, xi) from the shipped table: ~1e-7 relative, at formula speed.

    Parameters
    ----------
    eps : array_like
        Restitution coefficient, ``EPS_MIN <= eps <= 1`` (the table's domain;
        use ``solve_alpha`` below 0.01).
    xi : array_like
        Influence factor, ``0 <= xi <= XI_MAX``.
    """
    from .validation import check_range

    e, x = np.broadcast_arrays(np.asarray(eps, dtype=float), np.asarray(xi, dtype=float))
    e_flat = np.ascontiguousarray(e).ravel()
    x_flat = np.ascontiguousarray(x).ravel()
    # One jitted pass finds bad input; check_range then words the error.
    if _first_outside(e_flat, EPS_MIN, 1.0) >= 0:
        check_range("eps", e_flat, EPS_MIN, 1.0)
    if _first_outside(x_flat, 0.0, XI_MAX) >= 0:
        check_range("xi", x_flat, 0.0, XI_MAX)
    run = alpha_from_table_many if e_flat.size >= PARALLEL_MIN_LOOKUPS else alpha_from_table_serial
    out = run(e_flat, x_flat, *_arrays(path)).reshape(e.shape)
    return out[()] if out.ndim == 0 else out


def jit_alpha_tabulated(path=DEFAULT_FILE):
    """Return a numba-jitted scalar ``f(eps, xi) -> alpha`` for users' own jitted loops.

    The table arrays are frozen into the compiled function as constants.  No
    range checks inside: keep ``EPS_MIN <= eps <= 1`` and ``0 <= xi <= XI_MAX``.
    """
    b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g = _arrays(path)

    @njit(error_model="numpy")
    def alpha_exact_jit(eps, xi):
        return alpha_from_table(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g)

    return alpha_exact_jit


def random_points(n, seed):
    """``n`` random (eps, xi) in the table's domain: half log-uniform in xi (the ridge), half uniform."""
    rng = np.random.default_rng(seed)
    eps = np.exp(rng.uniform(U_MIN, 0.0, n))
    xi = np.where(
        rng.random(n) < 0.5, np.exp(rng.uniform(np.log(1e-9), np.log(XI_MAX), n)), rng.uniform(0.0, XI_MAX, n)
    )
    return eps, xi


def check_table(path, *, n=2000, seed=0, shipped=DEFAULT_FILE):
    """Accuracy of the table at ``path`` against ``solve_alpha``, and its distance to the shipped table.

    Returns
    -------
    dict
        ``max_rel_err``, ``median_rel_err``, ``worst`` (eps, xi), ``n``, and
        ``max_rel_diff_shipped`` (NaN when no shipped table can be read).
    """
    from .solver import solve_alpha

    eps, xi = random_points(n, seed)
    ref = solve_alpha(eps, xi, tol=1e-13, guess="formula")
    if not np.all(ref.ok):
        raise RuntimeError(f"check_table: {int((~np.asarray(ref.ok)).sum())} reference solves failed")
    got = alpha_tabulated(eps, xi, path=path)
    rel = np.abs(got / ref.alpha - 1.0)
    i = int(np.argmax(rel))
    try:
        diff = float(np.max(np.abs(alpha_tabulated(eps, xi, path=shipped) / got - 1.0)))
    except (FileNotFoundError, ValueError):
        diff = float("nan")
    return dict(
        n=n,
        max_rel_err=float(rel.max()),
        median_rel_err=float(np.median(rel)),
        worst=(float(eps[i]), float(xi[i])),
        max_rel_diff_shipped=diff,
    )
