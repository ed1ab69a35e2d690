"""One-off build of a nonlinear law's exact-damping tables (``table.py`` holds the runtime lookup).

``table.py`` describes the tables: ``L = ln(p e / (1 - e))`` on the load coordinate ``eta`` and,
for Stronge's eps, regions cut along curves where eps(p) has kinks (found here by bisection on the
end state of the law's impact, ``CUTS``); for Newton's e_N one region on ``q = ln e_N``.
The node values are the law's exact inverse (``solve.py``: the family integrator, or for the
piecewise-linear laws root finding on their closed form); the node at
``e = 1`` (``p = 0``) takes ``L``'s limit by Richardson extrapolation from ``e = 1 - h, 1 - 2 h``.

Build the shipped files with ``python -m contactalpha.laws.table_build`` (all tabulated laws) or
``python -m contactalpha.laws.table_build hertz_tsuji --n-eta 139 --n-p 51``.
"""

import argparse
import time
from dataclasses import asdict, replace

import numpy as np

from contactalpha.engine.bspline import clamp_to_uniform
from contactalpha.engine.codes import CREEP, NO_RESTITUTION, NOT_CONVERGED, OK, SEPARATION
from contactalpha.engine.table import (
    DEGREE,
    EPS_MIN,
    G_COUNT,
    G_FIRST,
    G_K_ETA,
    G_K_Q,
    G_STEP,
    N_K_GEOM,
    U_MIN,
    XI_MAX,
    XI_SCALE,
    eta_of_xi,
)
from contactalpha.engine.table_build import XI_BOUNDARY_MIN, soft_floor, xi_of_eta

from .backends import FAMILY
from .integrate import R_EN, R_EPS2, R_FLOORS, R_STATE, R_STATUS

# Distance from e = 1 of the two solves that extrapolate L to e = 1.
RICHARDSON_H = 1e-5
# Bisection steps placing the separation boundary in ln p.
BOUNDARY_BISECTIONS = 60
# Largest miss of a bisected root, in restitution.
ROOT_CHECK = 1e-12
# Relative steps back from a cut where the impact on it fails.
BOUNDARY_BACKOFF = (1e-12, 1e-10, 1e-8)
# Largest damping searched for the separation boundary.
P_SEARCH_MAX = 1e8


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
    if law.piecewise_linear:
        return _closed_form_rows(law, pf, A)
    from .integrate import ATOL, MAX_STEPS, RTOL, impact_rows

    return impact_rows(law.code, pf, A, law.impedance, law.equilibrium(A), RTOL, ATOL, MAX_STEPS)


def _closed_form_rows(law, p, A):
    """The integrator's rows (the columns the build reads) from the closed form (``closed_form.py``).

    The integrator needs millions of steps at the large dampings the cuts of the linear laws reach
    under small loads; the closed form does not.
    """
    from .closed_form import closed_form_states
    from .integrate import N_ROW

    got = np.empty((p.size, 4))
    closed_form_states(p, A, law.impedance, got)
    rows = np.full((p.size, N_ROW), np.nan)
    rows[:, R_EPS2], rows[:, R_EN], rows[:, R_STATE], rows[:, R_FLOORS] = got.T
    rows[:, R_STATUS] = np.where(np.isfinite(got[:, 0]), OK, NOT_CONVERGED)
    return rows


def _solve(law, target, xi, kinematic):
    """Exact damping at ``target``, ``xi`` (broadcast, flattened); a RuntimeError names a failure.

    Where the family's solver fails (its Illinois steps can land where the integrator hits its
    step limit, next to the no-restitution boundary: eps -> 0 there), ``_bisect`` finds the root;
    NaN where it finds none below the domain (``target < EPS_MIN``).
    """
    target, xi = np.broadcast_arrays(np.asarray(target, dtype=float), np.asarray(xi, dtype=float))
    target = np.ascontiguousarray(target).ravel()
    xi = np.ascontiguousarray(xi).ravel()
    A = np.atleast_1d(law.scaled_load(xi)).astype(float)
    # The piecewise-linear laws: root finding on their closed form (``fast.exact_inverse``).
    inverse = getattr(law.fast, "exact_inverse", None) or FAMILY
    p, status = inverse.damping(law, target, kinematic, A, xi)
    bad = status != OK
    if bad.any():
        p[bad] = _bisect(law, target[bad], xi[bad], kinematic)
    return p


def _restitution(law, p, xi, kinematic):
    rows = _rows(law, p, xi)
    e = rows[:, R_EN] if kinematic else np.sqrt(np.maximum(rows[:, R_EPS2], 0.0))
    return np.where(rows[:, R_STATUS] == OK, e, np.nan)


def _bisect(law, target, xi, kinematic):
    """Bisection in ``p`` that reads a failed impact as ``e < target``; the root is then checked."""
    lo = np.zeros_like(target)
    hi = np.ones_like(target)
    for _ in range(40):
        over = _restitution(law, hi, xi, kinematic) > target
        if not over.any():
            break
        lo = np.where(over, hi, lo)
        hi = np.where(over, 4.0 * hi, hi)
    for _ in range(BOUNDARY_BISECTIONS):
        mid = 0.5 * (lo + hi)
        over = _restitution(law, mid, xi, kinematic) > target
        lo = np.where(over, mid, lo)
        hi = np.where(over, hi, mid)
    miss = np.abs(_restitution(law, lo, xi, kinematic) - target)
    found = miss <= ROOT_CHECK
    if not np.all(found | (target < EPS_MIN)):
        i = int(np.argmax(~found & (target >= EPS_MIN)))
        raise RuntimeError(f"{law.name} table build: no root at e={target[i]!r}, xi={xi[i]!r}")
    # Below the domain (nodes that only support the spline) a missing root is NaN: ``_fill_rows``.
    return np.where(found, lo, np.nan)


def _fill_rows(L, w):
    """Fill NaN nodes (below the domain, ``_bisect``) of each row by a cubic through its 4 nearest nodes."""
    for row in L:
        bad = np.isnan(row)
        if bad.any():
            good = np.flatnonzero(~bad)
            near = good[np.argsort(np.abs(good[:, None] - np.flatnonzero(bad)[None, :]).min(axis=1))[:4]]
            row[bad] = np.polyval(np.polyfit(w[near], row[near], 3), w[bad])
    return L


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


def _past_separation(rows):
    """Past the separation boundary: the impact no longer separates."""
    return rows[:, R_STATE] != SEPARATION


def _past_last_floor(rows):
    """Past the last floor: the impact neither separates nor reaches the force's floor."""
    return (rows[:, R_STATE] != SEPARATION) & (rows[:, R_FLOORS] == 0)


def _past_creep_onset(rows):
    """Past the onset of creep: the impact creeps to the equilibrium (or never turns)."""
    return (rows[:, R_STATE] == CREEP) | (rows[:, R_STATE] == NO_RESTITUTION)


def _past_first(rows):
    """Past the first of the last floor and the onset of creep (they cross for Tsuji's law)."""
    return _past_last_floor(rows) | _past_creep_onset(rows)


def _past_both(rows):
    """Past both the last floor and the onset of creep."""
    return _past_last_floor(rows) & _past_creep_onset(rows)


# The curves a law's energetic table can be cut along (``LawTable.cuts``): a test on impact rows
# that turns from False to True once as the damping grows at a fixed load.
CUTS = {
    "separation": _past_separation,
    "last_floor": _past_last_floor,
    "creep_onset": _past_creep_onset,
    "first_of_floor_creep": _past_first,
    "both_floor_creep": _past_both,
}


def cut_curve(law, xi, cut):
    """``ln eps`` on the curve ``cut`` (``CUTS``) at each ``xi`` (-inf where it is never crossed)."""
    past = CUTS[cut]
    xi = np.asarray(xi, dtype=float)
    lo = np.zeros_like(xi)
    hi = np.ones_like(xi)
    found = np.zeros(xi.shape, dtype=bool)
    while True:
        found |= past(_rows(law, hi, xi))
        todo = ~found & (hi < P_SEARCH_MAX)
        if not todo.any():
            break
        lo = np.where(todo, hi, lo)
        hi = np.where(todo, 4.0 * hi, hi)
    for _ in range(BOUNDARY_BISECTIONS):
        mid = np.where(lo > 0.0, np.sqrt(lo * hi), 0.5 * hi)
        over = past(_rows(law, mid, xi))
        lo = np.where(over, lo, mid)
        hi = np.where(over, mid, hi)
    rows = _rows(law, lo, xi)
    # Next to the critical damping the integrator can hit its step limit: step back from the cut.
    for back in BOUNDARY_BACKOFF:
        failed = rows[:, R_STATUS] != OK
        if not failed.any():
            break
        rows[failed] = _rows(law, lo[failed] * (1.0 - back), xi[failed])
    if np.any(rows[:, R_STATUS] != OK):
        raise RuntimeError(
            f"{law.name} table build: boundary impact failed at xi = {xi[rows[:, R_STATUS] != OK]}"
        )
    with np.errstate(divide="ignore"):  # eps = 0 on a cut into no restitution: -inf, floored later
        b = 0.5 * np.log(np.maximum(rows[:, R_EPS2], 0.0))
    return np.where(found, b, -np.inf)


def _geom(size, *grids):
    g = np.empty(size)
    for start, nodes in grids:
        g[start + G_FIRST] = nodes[0]
        g[start + G_STEP] = nodes[1] - nodes[0]
        g[start + G_COUNT] = nodes.size
    return g


def _target_of(law, u):
    """The e_N at kinematic table coordinate ``u``: ``exp(u)``, or ``exp(tau^-1(u))`` (``root_near_one``)."""
    from .table import root_coordinate_inverse

    return np.exp(root_coordinate_inverse(u) if law.fast.root_near_one else u)


def build_energetic(law, settings, say):
    """Arrays of the energetic table by name (``table.energetic_names``), cut along ``law.fast.cuts``."""
    from scipy.interpolate import make_interp_spline

    cuts = law.fast.cuts
    root = law.fast.root_near_one
    eta_max = float(eta_of_xi(XI_MAX))
    eta = np.linspace(0.0, eta_max, settings.n_eta)
    deta = eta[1] - eta[0]
    xi = xi_of_eta(eta)
    xi[0] = 0.0
    search = xi >= XI_BOUNDARY_MIN
    splines, coefs, knots = [], [], None
    above = np.full(eta.size, np.inf)
    for cut in cuts:
        b = np.full(eta.size, -np.inf)
        b[search] = cut_curve(law, xi[search], cut)
        # Below the domain eps(p) need not fall monotonically (the spring-dashpot under small loads:
        # creep restitutes more than a floor flight just before it), and a cut can then lie above
        # the one before: there it is put on that one, outside the table's reach.
        b = np.where((b > above) & (above < U_MIN), above, b)
        above = b
        bs = make_interp_spline(eta, soft_floor(b), k=DEGREE)
        knots, c = clamp_to_uniform(bs.t, bs.c, DEGREE, eta)
        splines.append(bs)
        coefs.append(c)
        say(f"{law.name}: cut {cut}, {int(search.sum())} rows")
    if np.any(np.diff(np.array([soft_floor(s(eta)) for s in splines]), axis=0) > 1e-12):
        raise RuntimeError(f"{law.name} table build: cuts {cuts} are not ordered top to bottom")
    arrays = {"curves_t": knots, "curves_c": np.ascontiguousarray(np.array(coefs))}
    geom = [float(len(cuts)), eta[0], deta, float(eta.size)]
    for r in range(len(cuts) + 1):
        if r == 0:
            eta_r = eta
            w = np.linspace(0.0, 1.0, settings.n_p)
        else:
            # The region spans the rows where its upper cut is inside the domain, and one more each side.
            inside = np.flatnonzero(splines[r - 1](eta) > U_MIN)
            if inside.size == 0:
                raise RuntimeError(f"{law.name} table build: cut {cuts[r - 1]} never enters the domain")
            lo, hi = eta[max(inside[0] - 1, 0)], eta[min(inside[-1] + 1, eta.size - 1)]
            rows = max(DEGREE + 2, int(round(settings.refine_n * (hi - lo) / deta)) + 1)
            eta_r = np.linspace(lo, hi, rows)
            w = np.linspace(0.0, 1.0, settings.refine_n * (settings.n_p - 1) + 1)
        u = region_u(splines, r, eta_r[:, None], w[None, :], root)
        L = node_values(
            law, np.exp(np.minimum(u, 0.0)), xi_of_eta(eta_r)[:, None] if r else xi[:, None], False
        )
        filled = int(np.isnan(L).sum())
        L = _fill_rows(L, w)
        say(f"{law.name}: region {r}, {L.size} nodes ({filled} below the domain extrapolated)")
        tx, ty, c = _spline2d(eta_r, w, L)
        arrays |= {f"r{r}_tx": tx, f"r{r}_ty": ty, f"r{r}_c": c}
        geom += [eta_r[0], eta_r[1] - eta_r[0], float(eta_r.size), w[0], w[1] - w[0], float(w.size)]
    arrays["geom"] = np.array(geom)
    return arrays


def region_u(splines, r, eta, w, root=False):
    """``u = ln eps`` at column coordinate ``w`` of region ``r`` (``table.py``'s maps, inverted).

    ``root``: region 0 is square-root-like at e = 1 too (``LawTable.root_near_one``).
    """
    cuts = len(splines)
    if r == 0 and root:
        return splines[0](eta) * np.cos(0.5 * np.pi * w) ** 2
    if r == 0:
        return splines[0](eta) * (1.0 - w**2)
    upper = splines[r - 1](eta)
    if r == cuts:
        return upper - w**2 * (upper - U_MIN)
    return upper - np.sin(0.5 * np.pi * w) ** 2 * (upper - splines[r](eta))


def build_kinematic(law, settings, say):
    """Arrays of the kinematic table (``table.KINEMATIC_NAMES``)."""
    eta = np.linspace(0.0, float(eta_of_xi(XI_MAX)), settings.n_eta)
    xi = xi_of_eta(eta)
    xi[0] = 0.0
    q = np.linspace(float(np.log(EPS_MIN)), 0.0, settings.n_q)
    e_n = _target_of(law, q)
    e_n[-1] = 1.0
    L = node_values(law, np.broadcast_to(e_n, (eta.size, q.size)), xi[:, None], True)
    say(f"{law.name}: kinematic, {L.size} nodes")
    tx, ty, c = _spline2d(eta, q, L)
    return (tx, ty, c, _geom(N_K_GEOM, (G_K_ETA, eta), (G_K_Q, q)))


def build_law_tables(law, settings=None, progress=None):
    """Both tables of ``law`` as ``(arrays by name, meta)``, ready for ``table.save_law_tables``."""
    from .table import KINEMATIC_NAMES, TABLE_FORMAT

    say = progress or (lambda msg: None)
    settings = law.fast.settings if settings is None else settings
    t0 = time.perf_counter()
    arrays = build_energetic(law, settings, say)
    arrays.update(zip(KINEMATIC_NAMES, build_kinematic(law, settings, say), strict=True))
    meta = dict(
        format=TABLE_FORMAT,
        law=law.name,
        eps_min=EPS_MIN,
        xi_max=XI_MAX,
        xi_scale=XI_SCALE,
        degree=DEGREE,
        richardson_h=RICHARDSON_H,
        build_seconds=round(time.perf_counter() - t0, 1),
        cuts=list(law.fast.cuts),
        impedance=law.impedance,
        root_near_one=law.fast.root_near_one,
        **asdict(settings),
    )
    return arrays, meta


def main(argv=None):
    """Build and write the tables of the named laws (default: every law whose ``fast`` is a table)."""
    from .law import LAWS, get_law
    from .table import LawTable, LawTableSettings, save_law_tables

    tabulated = [law.name for law in LAWS if isinstance(law.fast, LawTable)]
    ap = argparse.ArgumentParser(description="Build the exact-damping tables of the nonlinear laws.")
    ap.add_argument("laws", nargs="*", default=tabulated, help=f"default: {' '.join(tabulated)}")
    for name in asdict(LawTableSettings()):
        ap.add_argument(f"--{name.replace('_', '-')}", type=int, help="default: the law's LawTable.settings")
    ap.add_argument("--out", help="output file (one law only); default the law's shipped file")
    args = ap.parse_args(argv)
    given = {k: getattr(args, k) for k in asdict(LawTableSettings()) if getattr(args, k) is not None}
    for name in args.laws:
        law = get_law(name)
        arrays, meta = build_law_tables(law, replace(law.fast.settings, **given), progress=print)
        path = save_law_tables(arrays, meta, args.out or law.fast.path)
        print(f"{law.name}: wrote {path} in {meta['build_seconds']} s")


if __name__ == "__main__":
    main()
