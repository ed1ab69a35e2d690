"""One-off build of a nonlinear law's exact-damping tables (``table.py`` holds the runtime lookup).

The tables have the layout and coordinates of the Hunt-Crossley n = 3/2 tables
(``engine/table.py``): ``L = ln(p e / (1 - e))`` on the load coordinate ``eta`` and, for Stronge's
eps, two regions cut along the law's separation boundary ``u = b(eta)`` (``u = ln eps``); for
Newton's e_N one region on ``q = ln e_N``.  So the engine's jitted evaluators read them unchanged.
The node values are the law's exact inverse (``solve.py``, the family integrator); the node at
``e = 1`` (``p = 0``) takes ``L``'s limit by Richardson extrapolation from ``e = 1 - h, 1 - 2 h``.

Build the shipped files with ``python -m contactalpha.laws.table_build`` (all tabulated laws) or
``python -m contactalpha.laws.table_build hertz_tsuji --n-eta 139 --n-p 51``.
"""

import argparse
import time
from dataclasses import asdict, dataclass

import numpy as np

from contactalpha.engine.bspline import clamp_to_uniform
from contactalpha.engine.codes import OK, SEPARATION
from contactalpha.engine.table import (
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
    N_GEOM,
    N_K_GEOM,
    U_MIN,
    XI_MAX,
    XI_SCALE,
    eta_of_xi,
)
from contactalpha.engine.table_build import XI_BOUNDARY_MIN, soft_floor, xi_of_eta

from .backends import FAMILY
from .integrate import R_EN, R_EPS2, R_STATE, R_STATUS

# Distance from e = 1 of the two solves that extrapolate L to e = 1.
RICHARDSON_H = 1e-5
# Bisection steps placing the separation boundary in ln p.
BOUNDARY_BISECTIONS = 60
# Largest damping searched for the separation boundary.
P_SEARCH_MAX = 1e8


@dataclass(frozen=True)
class LawTableSettings:
    """Grid of ``build_law_tables``; the defaults build the shipped files."""

    n_eta: int = 139
    n_p: int = 51
    refine_n: int = 2
    n_q: int = 51


def _spline2d(x, y, L):
    from scipy.interpolate import RectBivariateSpline

    r = RectBivariateSpline(x, y, L, kx=DEGREE, ky=DEGREE, s=0)
    tx, ty, c = r.tck
    c = c.reshape(len(tx) - DEGREE - 1, len(ty) - DEGREE - 1)
    tx, c = clamp_to_uniform(tx, c, DEGREE, x, axis=0)
    ty, c = clamp_to_uniform(ty, c, DEGREE, y, axis=1)
    return tx, ty, np.ascontiguousarray(c)


def _rows(law, p, xi):
    p, xi = np.broadcast_arrays(np.asarray(p, dtype=float), np.asarray(xi, dtype=float))
    pf, xf = np.ascontiguousarray(p).ravel(), np.ascontiguousarray(xi).ravel()
    A = np.atleast_1d(law.scaled_load(xf)).astype(float)
    from .integrate import ATOL, MAX_STEPS, RTOL, impact_rows

    return impact_rows(law.code, pf, A, law.impedance, law.equilibrium(A), RTOL, ATOL, MAX_STEPS)


def _solve(law, target, xi, kinematic):
    """Exact damping at flat ``target``, ``xi``; a RuntimeError names the first failure."""
    target, xi = np.broadcast_arrays(np.asarray(target, dtype=float), np.asarray(xi, dtype=float))
    target = np.ascontiguousarray(target).ravel()
    xi = np.ascontiguousarray(xi).ravel()
    A = np.atleast_1d(law.scaled_load(xi)).astype(float)
    p, status = FAMILY.damping(law, target, kinematic, A, xi)
    if np.any(status != OK):
        i = int(np.argmax(status != OK))
        raise RuntimeError(f"{law.name} table build: solve failed at e={target[i]!r}, xi={xi[i]!r}")
    return p


def node_values(law, e, xi, kinematic):
    """``L = ln(p e / (1 - e))`` at restitutions ``e`` (1 allowed) and load factors ``xi``."""
    e = np.asarray(e, dtype=float)
    xi = np.broadcast_to(np.asarray(xi, dtype=float), e.shape)
    L = np.empty(e.shape)
    one = e >= 1.0
    inner = ~one
    L[inner] = np.log(_solve(law, e[inner], xi[inner], kinematic) * e[inner] / (1.0 - e[inner]))
    if one.any():
        h = RICHARDSON_H
        l1 = np.log(_solve(law, 1.0 - h, xi[one], kinematic) * (1.0 - h) / h)
        l2 = np.log(_solve(law, 1.0 - 2.0 * h, xi[one], kinematic) * (1.0 - 2.0 * h) / (2.0 * h))
        L[one] = 2.0 * l1 - l2
    return L


def separation_boundary(law, xi):
    """``ln eps`` on the law's separation boundary at each ``xi`` (-inf where it always separates)."""
    xi = np.asarray(xi, dtype=float)
    lo = np.zeros_like(xi)
    hi = np.ones_like(xi)
    found = np.zeros(xi.shape, dtype=bool)
    while True:
        rows = _rows(law, hi, xi)
        found |= rows[:, R_STATE] != SEPARATION
        todo = ~found & (hi < P_SEARCH_MAX)
        if not todo.any():
            break
        lo = np.where(todo, hi, lo)
        hi = np.where(todo, 4.0 * hi, hi)
    for _ in range(BOUNDARY_BISECTIONS):
        mid = np.where(lo > 0.0, np.sqrt(lo * hi), 0.5 * hi)
        sep = _rows(law, mid, xi)[:, R_STATE] == SEPARATION
        lo = np.where(sep, mid, lo)
        hi = np.where(sep, hi, mid)
    rows = _rows(law, lo, xi)
    if np.any(rows[:, R_STATUS] != OK):
        raise RuntimeError(f"{law.name} table build: boundary impact failed")
    b = 0.5 * np.log(np.maximum(rows[:, R_EPS2], 0.0))
    return np.where(found, b, -np.inf)


def _geom(size, *grids):
    g = np.empty(size)
    for start, nodes in grids:
        g[start + G_FIRST] = nodes[0]
        g[start + G_STEP] = nodes[1] - nodes[0]
        g[start + G_COUNT] = nodes.size
    return g


def build_energetic(law, settings, say):
    """Arrays of the energetic table (``table.ENERGETIC_NAMES``) and the grid's meta."""
    from scipy.interpolate import make_interp_spline
    from scipy.optimize import brentq

    eta_max = float(eta_of_xi(XI_MAX))
    eta = np.linspace(0.0, eta_max, settings.n_eta)
    xi = xi_of_eta(eta)
    xi[0] = 0.0
    b = np.full(eta.size, -np.inf)
    search = xi >= XI_BOUNDARY_MIN
    b[search] = separation_boundary(law, xi[search])
    b_eff = soft_floor(b)
    bs = make_interp_spline(eta, b_eff, k=DEGREE)
    b_t, b_c = clamp_to_uniform(bs.t, bs.c, DEGREE, eta)
    say(f"{law.name}: boundary, {int(search.sum())} rows")
    p = np.linspace(0.0, 1.0, settings.n_p)
    u_s = b_eff[:, None] * (1.0 - p[None, :] ** 2)
    L_s = node_values(law, np.exp(u_s), xi[:, None], False)
    say(f"{law.name}: region S, {L_s.size} nodes")
    eta_n_min = brentq(lambda e: float(bs(e)) - U_MIN, 0.0, eta_max) if bs(eta_max) > U_MIN else 0.0
    n_rows = max(DEGREE + 2, int(round(settings.refine_n * (eta_max - eta_n_min) / (eta[1] - eta[0]))) + 1)
    eta_n = np.linspace(eta_n_min, eta_max, n_rows)
    p_n = np.linspace(0.0, 1.0, settings.refine_n * (settings.n_p - 1) + 1)
    b_n = bs(eta_n)
    u_n = b_n[:, None] - p_n[None, :] ** 2 * (b_n[:, None] - U_MIN)
    L_n = node_values(law, np.exp(np.minimum(u_n, 0.0)), xi_of_eta(eta_n)[:, None], False)
    say(f"{law.name}: region N, {L_n.size} nodes")
    s_tx, s_ty, s_c = _spline2d(eta, p, L_s)
    n_tx, n_ty, n_c = _spline2d(eta_n, p_n, L_n)
    geom = _geom(N_GEOM, (G_S_ETA, eta), (G_S_P, p), (G_N_ETA, eta_n), (G_N_P, p_n))
    arrays = (b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, geom)
    return arrays, dict(n_eta_region_n=int(n_rows), n_p_region_n=int(p_n.size))


def build_kinematic(law, settings, say):
    """Arrays of the kinematic table (``table.KINEMATIC_NAMES``)."""
    eta = np.linspace(0.0, float(eta_of_xi(XI_MAX)), settings.n_eta)
    xi = xi_of_eta(eta)
    xi[0] = 0.0
    q = np.linspace(float(np.log(EPS_MIN)), 0.0, settings.n_q)
    e_n = np.exp(q)
    e_n[-1] = 1.0
    L = node_values(law, np.broadcast_to(e_n, (eta.size, q.size)), xi[:, None], True)
    say(f"{law.name}: kinematic, {L.size} nodes")
    tx, ty, c = _spline2d(eta, q, L)
    return (tx, ty, c, _geom(N_K_GEOM, (G_K_ETA, eta), (G_K_Q, q)))


def build_law_tables(law, settings=LawTableSettings(), progress=None):
    """Both tables of ``law`` as ``(arrays by name, meta)``, ready for ``table.save_law_tables``."""
    from .table import ENERGETIC_NAMES, KINEMATIC_NAMES, TABLE_FORMAT

    say = progress or (lambda msg: None)
    t0 = time.perf_counter()
    energetic, extra = build_energetic(law, settings, say)
    kinematic = build_kinematic(law, settings, say)
    arrays = dict(zip(ENERGETIC_NAMES, energetic, strict=True))
    arrays.update(zip(KINEMATIC_NAMES, kinematic, strict=True))
    meta = dict(
        format=TABLE_FORMAT,
        law=law.name,
        eps_min=EPS_MIN,
        xi_max=XI_MAX,
        xi_scale=XI_SCALE,
        degree=DEGREE,
        richardson_h=RICHARDSON_H,
        build_seconds=round(time.perf_counter() - t0, 1),
        **asdict(settings),
        **extra,
    )
    return arrays, meta


def main(argv=None):
    """Build and write the tables of the named laws (default: every law whose ``fast`` is a table)."""
    from .law import LAWS, get_law
    from .table import LawTable, save_law_tables

    tabulated = [law.name for law in LAWS if isinstance(law.fast, LawTable)]
    ap = argparse.ArgumentParser(description="Build the exact-damping tables of the nonlinear laws.")
    ap.add_argument("laws", nargs="*", default=tabulated, help=f"default: {' '.join(tabulated)}")
    for name, value in asdict(LawTableSettings()).items():
        ap.add_argument(f"--{name.replace('_', '-')}", type=int, default=value)
    ap.add_argument("--out", help="output file (one law only); default the law's shipped file")
    args = ap.parse_args(argv)
    settings = LawTableSettings(**{k: getattr(args, k) for k in asdict(LawTableSettings())})
    for name in args.laws:
        law = get_law(name)
        arrays, meta = build_law_tables(law, settings, progress=print)
        path = save_law_tables(arrays, meta, args.out or law.fast.path)
        print(f"{law.name}: wrote {path} in {meta['build_seconds']} s")


if __name__ == "__main__":
    main()
