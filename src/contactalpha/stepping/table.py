"""An engine's step table and the batch inverse at its step, at formula speed.

``table_build`` tabulates the phase-mean e_N of an engine's map on a uniform grid of the step
``x = omega h``, the law's load factor ``xi`` and the law's dimensionless damping ``c`` (module
docstring there).  ``batch_inverse`` answers many scenes at once: for each, the damping whose
phase-mean e_N is the target.

Per scene (numba, rows in parallel): cubic Lagrange weights in ``x`` and in ``xi`` (the four
nearest nodes) give the squared phase mean at every damping node (the square: near capture the
mean falls like a square root of the damping, its square linearly); the first node from zero
damping upwards whose mean is below the target brackets the root (as ``inverse.damping_for``'s
ladder does; a target above the mean at zero damping is out of reach, and one that no node
brackets is left to the exact inverse); the cubic through the four nearest damping nodes is
solved there by bisection.
The same weights give the range a single drop sees (linear in the damping) and the steps in
contact (the outermost of the eight nearest nodes).

**Its own accuracy.**  The mean is a continuous but not a smooth function of the step (it
ripples where the steps in contact change), so the table cannot be exact.  Each row carries an
estimate (``O_ERROR``): the largest change of the mean at the root when one of the three
four-node stencils (damping, step, load) is shifted by one node either way.  A row whose
estimate exceeds ``ERROR_TOL``, or that lies outside the grid, gets the status ``INACCURATE``
or ``OUTSIDE`` and no number: the front door solves those rows exactly
(``inverse.damping_for``).  The estimate is not a bound (kinks between nodes hide from it);
what the rows it accepts deliver is checked against the map's exact phase mean at random scenes
in ``tests/stepping/test_step_table.py``.

A table file is refused, never evaluated, when its format, grid or SHA-256 differ from what it
records (``load_step_table``).
"""

import json
import math
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit, prange

from contactalpha.engine.table import checksum
from contactalpha.laws.table import save_law_tables

DATA = Path(__file__).parents[1] / "data"
TABLE_FORMAT = "step-table-1"
BUILD_COMMAND = "python -m contactalpha.stepping.table_build"
# Fields of a table cell: phase mean, minimum and maximum of e_N; fewest and most steps in contact.
F_MEAN, F_MIN, F_MAX, F_STEPS_MIN, F_STEPS_MAX = range(5)
N_FIELDS = 5
# A drop flies a step before touchdown only if A x <= 2 (v >= a h / 2); cells past this are NaN.
MAX_LOAD_STEP = 1.9
# Columns of a batch row: the damping, the mean, the range, steps, the error estimate, status.
O_DAMPING, O_MEAN, O_MIN, O_MAX, O_STEPS_MIN, O_STEPS_MAX, O_ERROR, O_STATUS, O_NEAREST = range(9)
N_OUT = 9
# Row status.
OK, UNREACHABLE, OUTSIDE, INACCURATE = range(4)
ROW_STATUS = {OK: "ok", UNREACHABLE: "unreachable", OUTSIDE: "outside the table", INACCURATE: "inaccurate"}
# A row whose error estimate (in e_N) exceeds this is left to the exact inverse.
ERROR_TOL = 1e-4
# Bisection steps on the damping cubic (halves the bracket to the double's resolution).
BISECTIONS = 60


@dataclass(frozen=True)
class StepTableGrid:
    """A step table's uniform grid, and the quadrature tolerance of each phase mean.

    ``n_x`` steps of ``x_max / n_x`` from 0 (the continuous law), ``n_xi`` load factors from 0 to
    ``xi_max``, ``n_c`` dampings from 0 to ``c_max``.
    """

    x_max: float
    n_x: int
    xi_max: float
    n_xi: int
    c_max: float
    n_c: int
    quad_tol: float = 1e-9

    def steps(self):
        """The step nodes ``x = omega h``."""
        return np.linspace(0.0, self.x_max, self.n_x + 1)

    def loads(self):
        """The load-factor nodes ``xi``."""
        return np.linspace(0.0, self.xi_max, self.n_xi + 1)

    def dampings(self):
        """The law's damping nodes."""
        return np.linspace(0.0, self.c_max, self.n_c + 1)


@dataclass(frozen=True)
class StepTableSpec:
    """What a stepper's table is: its law, grid, unit parameters and stability limit.

    ``law`` is the law of its scaling; ``unit_params(c)`` the map's ``p`` at mass 1 and stiffness 1
    (so omega = 1) with the law's damping ``c`` at speed 1; ``stable_damping(x)`` the law damping
    past which the step ``x`` is unstable (None: none).
    """

    law: str
    grid: StepTableGrid
    unit_params: object
    stable_damping: object = None


def table_path(engine):
    """The shipped step table of ``engine``."""
    return DATA / f"step_table_{engine}.npz"


def save_step_table(arrays, meta, path):
    """Write a step table with its meta (and the arrays' SHA-256) to ``path`` atomically.

    The laws' table writer (``laws.table.save_law_tables``): one format for every shipped table.
    """
    return save_law_tables(arrays, meta, path)


def load_step_table(path, grid):
    """``(table, meta)`` of a step table file, refused unless its format, ``grid`` and checksum hold."""
    path = Path(path)
    hint = f"rebuild it with `{BUILD_COMMAND}`"
    if not path.exists():
        raise FileNotFoundError(f"step table {path} not found; build it with `{BUILD_COMMAND}`")
    try:
        with np.load(path) as z:
            meta = json.loads(str(z["meta"]))
            table = np.ascontiguousarray(z["table"])
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as err:
        raise ValueError(f"step table {path} cannot be read ({type(err).__name__}: {err}); {hint}") from err
    if meta.get("format") != TABLE_FORMAT:
        raise ValueError(
            f"step table {path} has format {meta.get('format')!r}, expected {TABLE_FORMAT}; {hint}"
        )
    shape = (grid.n_x + 1, grid.n_xi + 1, grid.n_c + 1, N_FIELDS)
    if table.shape != shape or table.dtype != np.float64:
        raise ValueError(
            f"step table {path}: shape {table.shape} {table.dtype}, expected {shape} float64; {hint}"
        )
    if checksum({"table": table}) != meta.get("sha256"):
        raise ValueError(f"step table {path}: its checksum differs from the recorded one; {hint}")
    return table, meta


@njit(cache=True)
def _weights(u, n, shift=0):
    """First node and cubic Lagrange weights at grid coordinate ``u`` (nodes 0..n-1, n >= 4).

    ``shift`` moves the four-node stencil by that many nodes (kept inside the grid).
    """
    b = min(max(int(math.floor(u)) - 1 + shift, 0), n - 4)
    t = u - b
    w = np.empty(4)
    w[0] = -(t - 1.0) * (t - 2.0) * (t - 3.0) / 6.0
    w[1] = t * (t - 2.0) * (t - 3.0) / 2.0
    w[2] = -t * (t - 1.0) * (t - 3.0) / 2.0
    w[3] = t * (t - 1.0) * (t - 2.0) / 6.0
    return b, w


@njit(cache=True)
def _cubic(u, b, ys):
    """The cubic through ``ys[b..b+3]`` (at nodes b..b+3) at coordinate ``u``."""
    t = u - b
    w0 = -(t - 1.0) * (t - 2.0) * (t - 3.0) / 6.0
    w1 = t * (t - 2.0) * (t - 3.0) / 2.0
    w2 = -t * (t - 1.0) * (t - 3.0) / 2.0
    w3 = t * (t - 1.0) * (t - 2.0) / 6.0
    return ys[b] * w0 + ys[b + 1] * w1 + ys[b + 2] * w2 + ys[b + 3] * w3


@njit(cache=True)
def _stencil(ux, uxi, nx, nxi, sx=0, sl=0):
    """``(inside, bx, wx, bl, wl)``: cubic stencils in ``x`` and ``xi`` (shifted by ``sx``, ``sl``)."""
    if not (0.0 <= ux <= nx - 1 and 0.0 <= uxi <= nxi - 1):
        return False, 0, np.empty(4), 0, np.empty(4)
    bx, wx = _weights(ux, nx, sx)
    bl, wl = _weights(uxi, nxi, sl)
    return True, bx, wx, bl, wl


@njit(cache=True)
def _fill(sq, bx, wx, bl, wl, g, j0, j1):
    """``g[j0:j1]``: the squared phase mean at those damping nodes, cubic in ``x`` and ``xi``.

    A node that any of the 16 neighbouring columns lacks (a column ends where ``table_build``
    stopped it) is NaN.
    """
    for j in range(j0, j1):
        acc = 0.0
        for a in range(4):
            for b in range(4):
                acc += wx[a] * wl[b] * sq[bx + a, bl + b, j]
        g[j] = acc


@njit(cache=True)
def _finite(g, j0, j1):
    for j in range(j0, j1):
        if not math.isfinite(g[j]):
            return False
    return True


@njit(cache=True)
def _range_at(tab, bx, wx, bl, wl, j, f):
    """The range one drop sees at damping coordinate ``j - 1 + f``: linear between nodes j-1, j."""
    lo_e = hi_e = 0.0
    for a in range(4):
        for b in range(4):
            wab = wx[a] * wl[b]
            lo_e += wab * ((1.0 - f) * tab[bx + a, bl + b, j - 1, F_MIN] + f * tab[bx + a, bl + b, j, F_MIN])
            hi_e += wab * ((1.0 - f) * tab[bx + a, bl + b, j - 1, F_MAX] + f * tab[bx + a, bl + b, j, F_MAX])
    return lo_e, hi_e


@njit(cache=True)
def _steps_at(tab, ux, uxi, j):
    """Fewest and most steps in contact over the eight nearest nodes (NaN at x = 0 only)."""
    nx, nxi = tab.shape[0], tab.shape[1]
    i0, k0 = min(int(ux), nx - 2), min(int(uxi), nxi - 2)
    s_lo, s_hi = math.inf, -math.inf
    for a in range(2):
        for b in range(2):
            for c in range(2):
                if tab[i0 + a, k0 + b, j - 1 + c, F_STEPS_MIN] >= 0.0:  # -1 at x = 0: no steps
                    s_lo = min(s_lo, tab[i0 + a, k0 + b, j - 1 + c, F_STEPS_MIN])
                    s_hi = max(s_hi, tab[i0 + a, k0 + b, j - 1 + c, F_STEPS_MAX])
    if s_lo > s_hi:
        return math.nan, math.nan
    return s_lo, s_hi


@njit(cache=True)
def _row(tab, sq, dx, dxi, dc, x, xi, target, tol, out):
    """One scene's inverse into ``out`` (``O_*`` slots); ``sq`` is the table's squared means."""
    nx, nxi, nc = tab.shape[0], tab.shape[1], tab.shape[2]
    out[:] = math.nan
    out[O_STATUS] = OUTSIDE
    if not (0.0 < target < 1.0):
        return
    ux, uxi = x / dx, xi / dxi
    inside, bx, wx, bl, wl = _stencil(ux, uxi, nx, nxi)
    if not inside:
        return
    g = np.empty(nc)
    _fill(sq, bx, wx, bl, wl, g, 0, 1)
    if not math.isfinite(g[0]):
        return
    t2 = target * target
    if g[0] < t2:
        out[O_STATUS] = UNREACHABLE
        out[O_NEAREST] = math.sqrt(g[0]) if g[0] > 0.0 else 0.0
        return
    # The first node from zero damping upwards below the target (nodes filled as the scan goes).
    j, filled = 1, 1
    while True:
        if j == filled and filled < nc:
            end = min(filled + 8, nc)
            _fill(sq, bx, wx, bl, wl, g, filled, end)
            filled = end
        if j == nc or not math.isfinite(g[j]):
            return  # more damping than the table holds (or an unstable step): the exact inverse decides
        if g[j] < t2:
            break
        j += 1
    end = min(j + 3, nc)
    if filled < end:
        _fill(sq, bx, wx, bl, wl, g, filled, end)
    nv = j + 1
    while nv < end and math.isfinite(g[nv]):
        nv += 1
    if nv < 4:
        return
    # The cubic through the four nearest damping nodes, solved on [j - 1, j] by bisection.
    bc = min(max(j - 2, 0), nv - 4)
    lo, hi = j - 1.0, float(j)
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        if _cubic(mid, bc, g) >= t2:
            lo = mid
        else:
            hi = mid
    u = 0.5 * (lo + hi)
    f = u - (j - 1)
    # The error estimate: how far the mean at the root moves when any one of the three stencils
    # shifts by a node (in the damping, then in the step and in the load, each both ways).
    alt = bc + 1 if bc + 4 < nv else bc - 1
    err = abs(math.sqrt(max(_cubic(u, alt, g), 0.0)) - target) if alt >= 0 else math.inf
    h = np.empty(nc)
    for sx, sl in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        _, hx, hwx, hl, hwl = _stencil(ux, uxi, nx, nxi, sx, sl)
        _fill(sq, hx, hwx, hl, hwl, h, bc, bc + 4)
        if not _finite(h, bc, bc + 4):
            err = math.inf
            break
        err = max(err, abs(math.sqrt(max(_cubic(u, bc, h), 0.0)) - target))
    lo_e, hi_e = _range_at(tab, bx, wx, bl, wl, j, f)
    out[O_ERROR] = err
    out[O_STEPS_MIN], out[O_STEPS_MAX] = _steps_at(tab, ux, uxi, j)
    if out[O_ERROR] > tol:
        out[O_STATUS] = INACCURATE
        return
    out[O_STATUS] = OK
    out[O_DAMPING] = u * dc
    out[O_MEAN] = target
    out[O_MIN] = min(lo_e, target)
    out[O_MAX] = max(hi_e, target)


@njit(cache=True)
def _forward_row(tab, sq, dx, dxi, dc, x, xi, c, out):
    """What damping ``c`` delivers: mean, minimum and maximum e_N into ``out[0:3]`` (NaN outside)."""
    nx, nxi, nc = tab.shape[0], tab.shape[1], tab.shape[2]
    out[:] = math.nan
    ux, uxi, uc = x / dx, xi / dxi, c / dc
    inside, bx, wx, bl, wl = _stencil(ux, uxi, nx, nxi)
    if not inside or not (0.0 <= uc <= nc - 1):
        return
    j = min(max(int(math.floor(uc)), 0), nc - 2) + 1
    bc = min(max(j - 2, 0), nc - 4)
    g = np.empty(nc)
    _fill(sq, bx, wx, bl, wl, g, bc, bc + 4)
    if not _finite(g, bc, bc + 4):
        return
    mean = math.sqrt(max(_cubic(uc, bc, g), 0.0))
    lo_e, hi_e = _range_at(tab, bx, wx, bl, wl, j, uc - (j - 1))
    out[0], out[1], out[2] = mean, min(lo_e, mean), max(hi_e, mean)


@njit(cache=True, parallel=True)
def _rows(tab, sq, dx, dxi, dc, x, xi, target, tol, out):
    for i in prange(x.size):
        _row(tab, sq, dx, dxi, dc, x[i], xi[i], target[i], tol, out[i])


@njit(cache=True, parallel=True)
def _forward_rows(tab, sq, dx, dxi, dc, x, xi, c, out):
    for i in prange(x.size):
        _forward_row(tab, sq, dx, dxi, dc, x[i], xi[i], c[i], out[i])


class StepTable:
    """A loaded, checked step table (``table``, ``meta``, ``grid``) and its batch inverse."""

    def __init__(self, path, grid):
        self.table, self.meta = load_step_table(path, grid)
        self.grid = grid
        self.squares = self.table[:, :, :, F_MEAN] ** 2

    def inverse(self, x, xi, target, tol=ERROR_TOL):
        """Rows of ``O_*`` columns for steps ``x = omega h``, load factors ``xi`` and e_N targets (1-D).

        A row whose error estimate exceeds ``tol`` is ``INACCURATE``, with no numbers.
        """
        x, xi, target = (
            np.ascontiguousarray(v, dtype=float).ravel() for v in np.broadcast_arrays(x, xi, target)
        )
        out = np.empty((x.size, N_OUT))
        _rows(self.table, self.squares, *self._spacing(), x, xi, target, float(tol), out)
        return out

    def forward(self, x, xi, c):
        """Rows ``(mean, minimum, maximum)`` of e_N that the law's damping ``c`` delivers (1-D)."""
        x, xi, c = (np.ascontiguousarray(v, dtype=float).ravel() for v in np.broadcast_arrays(x, xi, c))
        out = np.empty((x.size, 3))
        _forward_rows(self.table, self.squares, *self._spacing(), x, xi, c, out)
        return out

    def _spacing(self):
        g = self.grid
        return g.x_max / g.n_x, g.xi_max / g.n_xi, g.c_max / g.n_c


_LOADED: dict = {}


def step_table(engine, spec):
    """The shipped step table of ``engine`` (``spec``: its ``StepTableSpec``), loaded once."""
    if engine not in _LOADED:
        _LOADED[engine] = StepTable(table_path(engine), spec.grid)
    return _LOADED[engine]
