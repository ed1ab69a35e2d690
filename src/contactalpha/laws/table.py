"""Shipped exact-damping tables of the nonlinear laws: loaded, checked, evaluated at formula speed.

A law's file (``data/law_table_<law>.npz``, built by ``table_build.py``) holds two quintic
spline tables of ``L = ln(p e / (1 - e))`` (``p`` the law's damping), on the load coordinate
``eta`` of the Hunt-Crossley n = 3/2 tables (``engine/table.py``: 0 at xi = 0, logarithmic
near it):

- Stronge's eps: the plane ``(eta, u = ln eps)`` is cut along ``K`` curves ``b_1 > ... > b_K``
  where eps(p) has kinks (``LawTable.cuts``: the separation boundary, the last reach of the
  force's floor, the onset of creep), each a quintic spline in eta.  Region 0 (above ``b_1``)
  has the column coordinate ``w = sqrt(1 - u / b_1)``, region r between ``b_r`` and ``b_(r+1)``
  ``w = (2/pi) asin(sqrt((b_r - u) / (b_r - b_(r+1))))`` and region K (below ``b_K``)
  ``w = sqrt((b_K - u) / (b_K - ln 0.01))``: square-root-like at every cut, as L is.  With one
  cut this is the n = 3/2 table's layout.
- Newton's e_N: one region on ``(eta, q = ln e_N)``, the n = 3/2 kinematic table's layout, read
  by its evaluator ``kinematic_alpha_from_table``.
- A law whose ``L`` has a ``(1 - e)^{3/2}`` term at ``e -> 1`` (``LawTable.root_near_one``: Hertz
  with sqrt(delta) damping, whose floor and pull enter at ``kappa^{5/2}``) has columns like a square
  root at e = 1 too: region 0 takes ``w = (2/pi) asin(sqrt(1 - u / b_1))``, and the kinematic table
  is on ``tau(ln e) = -sqrt(ln(0.01) ln e)`` in place of ``ln e`` (``root_lookup``: 0 at e = 1 and
  ln 0.01 at e = 0.01).  ``L`` is smooth in both.

On load every array's shape is checked against its grid and the SHA-256 of the arrays against
the one the file records: a changed or truncated file is refused, never evaluated.
"""

import json
import zipfile
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numba import njit

from contactalpha.engine.bspline import eval_1d_uniform, eval_2d_uniform
from contactalpha.engine.codes import NOT_CONVERGED, OK
from contactalpha.engine.firstcall import twin_rows
from contactalpha.engine.table import (
    EPS_MIN,
    G_COUNT,
    G_K_ETA,
    G_K_Q,
    U_MIN,
    XI_MAX,
    checksum,
    eta_of_xi,
    kinematic_alpha_from_packed,
    pack_table,
    packed_matrix,
    packed_vector,
)
from contactalpha.engine.threads import run_rows
from contactalpha.io import json_text, write_atomic

DATA = Path(__file__).parents[1] / "data"
# Bumped whenever the meaning of the stored arrays changes.
TABLE_FORMAT = "law-table-2"
BUILD_COMMAND = "python -m contactalpha.laws.table_build"
KINEMATIC_NAMES = ("k_tx", "k_ty", "k_c", "k_geom")
# Layout of the energetic ``geom``: K, then (first node, spacing, count) of the curves' eta grid,
# then per region (first, spacing, count) of its eta grid and of its w grid.
GEOM_HEAD = 4
REGION_SLOTS = 6
# Largest miss of a table's damping, checked through the law's forward map (``LawTable.forward``),
# before the forward map is inverted instead.
CHECK_TOL = 1e-9
# Relative and absolute first step, and steps, of the secant that polishes a table's miss.
SECANT_STEP = 1e-6
SECANT_ITER = 3
# Below this many points one thread is faster than waking the others.
PARALLEL_MIN = 4096


def root_coordinate(u, xp=np):
    """``tau(u) = -sqrt(U_MIN u)`` of ``u = ln e <= 0``: the tables' coordinate for ``root_near_one``."""
    return -xp.sqrt(U_MIN * u)


def root_coordinate_inverse(t):
    """``u = ln e`` of the coordinate ``t = tau(u)`` (``root_coordinate`` inverted): ``t^2 / U_MIN``."""
    return t * t / U_MIN


def root_lookup(e, xp=np):
    """Where a ``root_near_one`` kinematic table is read for target ``e``: ``exp(tau(ln e))`` inside.

    Inside ``EPS_MIN <= e < 1`` it stays there (clipped against rounding at the ends); elsewhere
    ``e`` passes (1 is 1; the table gives NaN outside).  ``xp``: numpy or jax.numpy (the branch not
    taken is evaluated at 0.5, so that its gradient is finite).
    """
    inside = (e >= EPS_MIN) & (e < 1.0)
    safe = xp.where(inside, e, 0.5)
    t = xp.clip(xp.exp(root_coordinate(xp.log(safe), xp)), EPS_MIN, 1.0)
    return xp.where(inside, t, e)


def root_damping(p_lookup, e, lookup, xp=np):
    """The damping at target ``e`` from the table's ``p_lookup = exp(L) (1 - lookup) / lookup``."""
    below = lookup < 1.0
    ratio = xp.where(below, lookup / xp.where(below, 1.0 - lookup, 1.0), 0.0) * (1.0 - e) / e
    return xp.where(below, p_lookup * ratio, p_lookup)


def energetic_names(cuts):
    """Array names of an energetic table with ``cuts`` curves, in packing order."""
    regions = [f"r{r}_{part}" for r in range(cuts + 1) for part in ("tx", "ty", "c")]
    return ("geom", "curves_t", "curves_c", *regions)


@njit(cache=True, error_model="numpy")
def damping_from_packed(e, xi, flat):
    """Scalar, numba-callable ``p(eps, xi)`` of an energetic table packed by ``pack_table``.

    NaN outside ``EPS_MIN <= eps <= 1``, ``0 <= xi <= XI_MAX`` and for NaN input.
    """
    return damping_from_packed_as(e, xi, flat, False)


@njit(cache=True, error_model="numpy")
def damping_from_packed_as(e, xi, flat, root):
    """``damping_from_packed`` of a table whose region 0 is ``root_near_one`` (``root``) or not."""
    if not (EPS_MIN <= e <= 1.0 and 0.0 <= xi <= XI_MAX):
        return np.nan
    if e == 1.0:
        return 0.0
    k = np.int64  # run-time array numbers (see engine.table.alpha_from_packed)
    g = packed_vector(flat, k(0))
    t = packed_vector(flat, k(1))
    curves = packed_matrix(flat, k(2))
    cuts = int(g[0])
    u = np.log(e)
    eta = eta_of_xi(xi)
    e0, de, ne = g[1], g[2], int(g[3])
    upper = 0.0
    r = 0
    b = eval_1d_uniform(t, curves[0], e0, de, ne, eta)
    while r < cuts and u < b:
        r += 1
        upper = b
        if r < cuts:
            b = eval_1d_uniform(t, curves[r], e0, de, ne, eta)
    if r == 0 and root:
        w = (2.0 / np.pi) * np.arcsin(np.sqrt(min(max(1.0 - u / b, 0.0), 1.0)))
    elif r == 0:
        w = np.sqrt(1.0 - u / b)
    elif r == cuts:
        w = np.sqrt((upper - u) / (upper - U_MIN))
    else:
        s = (upper - u) / (upper - b)
        w = (2.0 / np.pi) * np.arcsin(np.sqrt(min(max(s, 0.0), 1.0)))
    o = GEOM_HEAD + REGION_SLOTS * r
    tx = packed_vector(flat, k(3 + 3 * r))
    ty = packed_vector(flat, k(4 + 3 * r))
    c = packed_matrix(flat, k(5 + 3 * r))
    L = eval_2d_uniform(tx, ty, c, g[o], g[o + 1], int(g[o + 2]), g[o + 3], g[o + 4], int(g[o + 5]), eta, w)
    return np.exp(L) * (1.0 - e) / e


@twin_rows
@njit(cache=True, nogil=True, error_model="numpy")
def damping_rows(e, xi, flat, kinematic, root, out, start, stop):
    """The packed table's ``p`` over rows ``start .. stop - 1`` of flat arrays, into ``out``.

    ``root``: the energetic table's region 0 is ``root_near_one`` (the kinematic table's targets
    come converted, ``root_lookup``).
    """
    for i in range(start, stop):
        if kinematic:
            out[i] = kinematic_alpha_from_packed(e[i], xi[i], flat)
        else:
            out[i] = damping_from_packed_as(e[i], xi[i], flat, root)


def _expected_shapes(a, cuts):
    """Shape each array must have, from the node counts in its grid (quintic, clamped uniform knots)."""
    g, kg = a["geom"], a["k_geom"]
    n_eta = int(g[3])
    want = {
        "geom": (GEOM_HEAD + REGION_SLOTS * (cuts + 1),),
        "curves_t": (n_eta + 10,),
        "curves_c": (cuts, n_eta + 4),
        "k_geom": kg.shape,
        "k_tx": (int(kg[G_K_ETA + G_COUNT]) + 10,),
        "k_ty": (int(kg[G_K_Q + G_COUNT]) + 10,),
        "k_c": (int(kg[G_K_ETA + G_COUNT]) + 4, int(kg[G_K_Q + G_COUNT]) + 4),
    }
    if g.size != want["geom"][0]:
        return want
    for r in range(cuts + 1):
        o = GEOM_HEAD + REGION_SLOTS * r
        nx, nw = int(g[o + 2]), int(g[o + 5])
        want |= {f"r{r}_tx": (nx + 10,), f"r{r}_ty": (nw + 10,), f"r{r}_c": (nx + 4, nw + 4)}
    return want


def check_arrays(arrays, meta, path):
    """Refuse tables whose format, shapes or checksum differ from what their file records."""
    hint = f"rebuild it with `{BUILD_COMMAND} {meta.get('law', '')}`"
    if meta.get("format") != TABLE_FORMAT:
        raise ValueError(
            f"law table {path} has format {meta.get('format')!r}, expected {TABLE_FORMAT}; {hint}"
        )
    for name, shape in _expected_shapes(arrays, len(meta["cuts"])).items():
        if arrays[name].shape != shape:
            raise ValueError(
                f"law table {path}: array {name} has shape {arrays[name].shape}, expected {shape}"
            )
    for name, a in arrays.items():
        if a.dtype != np.float64 or not np.all(np.isfinite(a)):
            raise ValueError(f"law table {path}: array {name} is not finite float64; {hint}")
    got = checksum(arrays)
    if got != meta.get("sha256"):
        raise ValueError(f"law table {path}: checksum {got[:12]}... differs from the recorded one; {hint}")


def save_law_tables(arrays, meta, path):
    """Write a law's tables and their meta (with the arrays' checksum) to ``path`` atomically."""
    meta = dict(meta, sha256=checksum(arrays))

    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays, meta=json_text(meta))

    return write_atomic(Path(path), write)


def load_law_tables(path):
    """``(arrays by name, meta)`` of a law's table file, checked (``check_arrays``)."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"law table {path} not found; build it with `{BUILD_COMMAND}`")
    try:
        with np.load(path) as z:
            meta = json.loads(str(z["meta"]))
            names = (*energetic_names(len(meta.get("cuts", ()))), *KINEMATIC_NAMES)
            missing = [n for n in names if n not in z.files]
            if missing:
                raise KeyError(f"arrays {missing} missing")
            arrays = {k: np.ascontiguousarray(z[k]) for k in names}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as err:
        raise ValueError(
            f"law table {path} cannot be read ({type(err).__name__}: {err}): truncated or not a law "
            f"table; rebuild it with `{BUILD_COMMAND}`"
        ) from err
    check_arrays(arrays, meta, path)
    return arrays, meta


@dataclass(frozen=True)
class LawTableSettings:
    """Grid of a law's tables (``table_build.py``).

    The energetic table's region 0 has ``n_eta`` rows and ``n_p`` columns, every region below a
    cut ``refine_n`` times as many of each (over its own span); the kinematic table ``n_eta`` rows
    and ``n_q`` columns in ln e_N.
    """

    n_eta: int = 199
    n_p: int = 51
    refine_n: int = 4
    n_q: int = 101


_PACKED: dict = {}


@dataclass(frozen=True)
class LawTable:
    """A law's shipped exact-damping tables (``file`` in the package's data): the inverse only.

    ``cuts`` names the curves its energetic table is cut along, top to bottom
    (``table_build.CUTS``: where eps(p) has kinks); ``settings`` is the grid of the shipped file.
    ``damping`` returns the law's ``p`` for 0.01 <= target <= 1 and 0 <= xi <= 0.99, and NaN with
    status NOT_CONVERGED outside (never an extrapolated number).
    ``impedance`` is the law's impedance the file was built at (0 for laws without one): a law
    with another impedance is served by ``forward``, as is the forward map (``forward`` None:
    neither is offered).  With a ``forward``, each damping is checked through it and, where it
    misses its target by more than ``CHECK_TOL``, found by inverting it; NaN (NOT_CONVERGED) where
    that misses too.
    """

    file: str
    cuts: tuple = ("separation",)
    settings: LawTableSettings = LawTableSettings()
    impedance: float = 0.0
    forward: Any = None  # a forward evaluator (``fast.ClosedForm``-like) or None
    root_near_one: bool = False  # square-root columns at e = 1 (module docstring); the file records it
    name: str = "law table"

    @property
    def exact_inverse(self):
        """The evaluator whose inverse is exact (``forward``, root finding on it), or None."""
        return self.forward

    def covers(self, law):
        """True when the table holds ``law``'s inverse (``law.impedance`` is the table's)."""
        return law.impedance == self.impedance

    @property
    def path(self):
        """The shipped file."""
        return DATA / self.file

    def packed(self, law, kinematic):
        """The checked table of one restitution of ``law``, packed (``engine.table.pack_table``), once.

        Refused by name where the file holds another law, another grid (``settings``), other cuts
        or another impedance than this table stands for.
        """
        key = (str(self.path), kinematic)
        if key not in _PACKED:
            arrays, meta = load_law_tables(self.path)
            if meta.get("law") != law.name:
                raise ValueError(
                    f"law table {self.path} holds law {meta.get('law')!r}, expected {law.name!r}; "
                    f"rebuild it with `{BUILD_COMMAND} {law.name}`"
                )
            grid = {name: meta.get(name) for name in asdict(self.settings)}
            if grid != asdict(self.settings):
                raise ValueError(
                    f"law table {self.path} has grid {grid}, expected {asdict(self.settings)}; "
                    f"rebuild it with `{BUILD_COMMAND} {law.name}`"
                )
            if tuple(meta["cuts"]) != tuple(self.cuts):
                raise ValueError(
                    f"law table {self.path} is cut along {meta['cuts']}, expected {list(self.cuts)}"
                )
            if meta.get("root_near_one", False) != self.root_near_one:
                raise ValueError(
                    f"law table {self.path} has root_near_one = {meta.get('root_near_one', False)}, "
                    f"expected {self.root_near_one}; rebuild it with `{BUILD_COMMAND} {law.name}`"
                )
            if meta.get("impedance", 0.0) != self.impedance:
                raise ValueError(
                    f"law table {self.path} was built at impedance {meta.get('impedance', 0.0)}, "
                    f"expected {self.impedance}; rebuild it with `{BUILD_COMMAND} {meta.get('law', '')}`"
                )
            for kind, names in ((False, energetic_names(len(self.cuts))), (True, KINEMATIC_NAMES)):
                _PACKED[(str(self.path), kind)] = pack_table([arrays[n] for n in names])
        return _PACKED[key]

    def restitution(self, law, p, A, xi, kinematic):
        """Restitution of flat ``p``, ``A`` by ``forward`` (None: not offered; the table is an inverse)."""
        if self.forward is None:
            raise ValueError(f"law {law.name!r} has no fast forward map; law.impact(p, xi) computes it")
        return self.forward.restitution(law, p, A, xi, kinematic)

    def damping(self, law, target, kinematic, A, xi):
        """(p, status code) from the table at flat ``target``, ``xi`` (by ``forward`` off its impedance)."""
        if not self.covers(law):
            if self.forward is None:
                raise ValueError(
                    f"law {law.name!r} at impedance {law.impedance} has no fast inverse; its table holds "
                    f"impedance {self.impedance}; law.damping_for computes it exactly"
                )
            return self.forward.damping(law, target, kinematic, A, xi)
        flat = self.packed(law, kinematic)
        out = np.empty(target.size)
        threads = None if target.size >= PARALLEL_MIN else 1
        converted = self.root_near_one and kinematic
        lookup = root_lookup(target) if converted else target
        root = self.root_near_one and not kinematic
        run_rows(damping_rows, target.size, lookup, xi, flat, kinematic, root, out, threads=threads)
        if converted:
            out = root_damping(out, target, lookup)
        status = np.where(np.isfinite(out), OK, NOT_CONVERGED)
        if self.forward is not None:
            self._polish(law, out, status, target, kinematic, A, xi)
        return out, status

    def _polish(self, law, out, status, target, kinematic, A, xi):
        """Check the table's ``out`` through ``forward``; where it misses, secant steps, then root finding.

        The secant starts at the table's damping; where it still misses (eps(p) jumps for the
        linear laws under small loads, as floor flights come and go) ``forward`` is inverted, and
        where that misses too the damping is NaN (NOT_CONVERGED).
        """

        def miss_of(p, rows):
            return self.forward.restitution(law, p, A[rows], xi[rows], kinematic) - target[rows]

        rows = np.flatnonzero(status == OK)
        f = miss_of(out[rows], rows)
        bad = ~(np.abs(f) <= CHECK_TOL)
        rows, p, f = rows[bad], out[rows][bad], f[bad]
        q = p * (1.0 + SECANT_STEP) + SECANT_STEP
        for _ in range(SECANT_ITER):
            if rows.size == 0:
                return
            g = miss_of(q, rows)
            done = np.abs(g) <= CHECK_TOL
            out[rows[done]] = q[done]
            with np.errstate(divide="ignore", invalid="ignore"):
                nxt = np.maximum(q - g * (q - p) / (g - f), 0.0)
            keep = ~done & np.isfinite(nxt)
            lost = ~done & ~keep
            rows, p, f, q = np.concatenate([rows[keep], rows[lost]]), q[keep], g[keep], nxt[keep]
            p = np.concatenate([p, out[rows[p.size :]]])
            f = np.concatenate([f, np.zeros(rows.size - f.size)])
            q = np.concatenate([q, out[rows[q.size :]]])
        if rows.size == 0:
            return
        root, st = self.forward.damping(law, target[rows], kinematic, A[rows], xi[rows])
        far = np.abs(miss_of(root, rows))
        st = np.where((st == OK) & ~(far <= CHECK_TOL), NOT_CONVERGED, st)
        out[rows], status[rows] = np.where(st == OK, root, np.nan), st
