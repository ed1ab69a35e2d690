"""Exact alpha(eps, xi) at formula speed: a quintic spline table in boundary-aligned coordinates.

What is tabulated
    ``L = ln(alpha eps / (1 - eps))``, which is finite and smooth at both
    ends: ``alpha ~ 1/eps`` for small eps without load, and
    ``alpha ~ (1 - eps) / (-deps/dalpha at alpha = 0)`` as eps -> 1.

Coordinates
    ``eta = ln(1 + xi / XI_SCALE) - ln(1 - xi)`` is 0 at xi = 0 (the exact
    column is a grid line), logarithmic through the ridge near xi ~ eps^2 ..
    eps (docs/science.md, "Shape of the surface"), and stretches xi -> 1.  ``u = ln eps``.
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
(tests/test_table.py); the build records its grid, tolerances and the SHA-256 of its
arrays, and ``load_table`` refuses a file whose format version or checksum differs, and a
file at the package's own path whose grid is not the shipped one (``SHIPPED_GRIDS``).  The one-off build
(node values, splines, writing the file) lives in ``table_build``.
"""

import hashlib
import json
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit

from contactalpha.validation import PLAIN_FLOATS, FloatOrArray, RealLike, as_real, check_range

from .bspline import eval_1d_uniform, eval_2d_uniform
from .firstcall import FirstCall, twin_rows
from .threads import flat_owned, run_rows

# Bumped whenever the meaning of the stored arrays changes.
TABLE_FORMAT_VERSION = 3
# Domain of the table: eps in [EPS_MIN, 1], xi in [0, XI_MAX].
EPS_MIN = 0.01
XI_MAX = 0.99
U_MIN = float(np.log(EPS_MIN))
# xi below which the eta coordinate is linear in xi (the ridge starts near eps^2 >= 1e-4).
XI_SCALE = 1e-10
# Spline degree in both directions.
DEGREE = 5
DEFAULT_FILE = Path(__file__).resolve().parents[1] / "data" / "alpha_table.npz"
KINEMATIC_FILE = Path(__file__).resolve().parents[1] / "data" / "alpha_table_kinematic.npz"
# The grids and tolerances the package's own tables were built with (config.yaml's models.table
# and restitution.table; tests check that they agree).  A table of another grid at the package's
# path is refused: its accuracy is not the documented one (the workflow's coarse test table misses
# by 4e-3 in alpha).
SHIPPED_GRIDS = {
    DEFAULT_FILE: {"n_eta": 277, "n_p": 101, "tol": 1e-13, "rtol": 1e-12, "atol": 1e-14},
    KINEMATIC_FILE: {"n_eta": 139, "n_q": 51, "tol": 1e-13, "rtol": 1e-12, "atol": 1e-14},
}
# Arrays stored in the table file, in the argument order of ``alpha_from_table``.
ARRAY_NAMES = ("b_t", "b_c", "s_tx", "s_ty", "s_c", "n_tx", "n_ty", "n_c", "geom")


@njit(cache=True, error_model="numpy")
def eta_of_xi(xi):
    """Load coordinate ``eta(xi)``; 0 at xi = 0."""
    return np.log1p(xi / XI_SCALE) - np.log1p(-xi)


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


# Layout of ``AlphaTable.geom``: (first node, spacing, node count) of each uniform grid,
# eta and p of region S, then eta and p of region N.
G_FIRST, G_STEP, G_COUNT = 0, 1, 2
G_S_ETA, G_S_P, G_N_ETA, G_N_P = 0, 3, 6, 9
N_GEOM = 12


@njit(cache=True, error_model="numpy")
def alpha_from_table(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g):
    """Scalar, numba-callable alpha(eps, xi) from the table arrays.

    Defined on ``EPS_MIN <= eps <= 1`` and ``0 <= xi <= XI_MAX``; NaN outside
    that domain and for NaN input, never an extrapolated number.
    """
    if not (EPS_MIN <= eps <= 1.0 and 0.0 <= xi <= XI_MAX):
        return np.nan
    if eps == 1.0:
        return 0.0
    u = np.log(eps)
    eta = eta_of_xi(xi)
    s_eta0, s_deta, s_neta = g[G_S_ETA + G_FIRST], g[G_S_ETA + G_STEP], int(g[G_S_ETA + G_COUNT])
    b = eval_1d_uniform(b_t, b_c, s_eta0, s_deta, s_neta, eta)
    if u >= b:
        p = np.sqrt(1.0 - u / b)
        s_p0, s_dp, s_np = g[G_S_P + G_FIRST], g[G_S_P + G_STEP], int(g[G_S_P + G_COUNT])
        L = eval_2d_uniform(s_tx, s_ty, s_c, s_eta0, s_deta, s_neta, s_p0, s_dp, s_np, eta, p)
    else:
        p = np.sqrt((b - u) / (b - U_MIN))
        n_eta0, n_deta, n_neta = g[G_N_ETA + G_FIRST], g[G_N_ETA + G_STEP], int(g[G_N_ETA + G_COUNT])
        n_p0, n_dp, n_np = g[G_N_P + G_FIRST], g[G_N_P + G_STEP], int(g[G_N_P + G_COUNT])
        L = eval_2d_uniform(n_tx, n_ty, n_c, n_eta0, n_deta, n_neta, n_p0, n_dp, n_np, eta, p)
    return np.exp(L) * (1.0 - eps) / eps


# The kinematic table (Newton's e_N): one region, since e_N > 0 only where the impact separates.
# Arrays in the argument order of ``kinematic_alpha_from_table``; ``k_geom`` holds the (first
# node, spacing, node count) of the eta grid, then of the q grid.
KINEMATIC_ARRAY_NAMES = ("k_tx", "k_ty", "k_c", "k_geom")
G_K_ETA, G_K_Q = 0, 3
N_K_GEOM = 6


@njit(cache=True, error_model="numpy")
def kinematic_q(e_n):
    """Coordinate of the kinematic table along e_N: ``q = ln e_N``, in [U_MIN, 0]."""
    return np.log(e_n)


@njit(cache=True, error_model="numpy")
def kinematic_alpha_from_table(e_n, xi, tx, ty, c, g):
    """Scalar, numba-callable alpha(e_N, xi) from the kinematic table's arrays.

    Tabulated: ``L = ln(alpha e_N / (1 - e_N))`` on (eta, q), as for the energetic table.
    Defined on ``EPS_MIN <= e_N <= 1``, ``0 <= xi <= XI_MAX``; NaN outside and for NaN.
    """
    if not (EPS_MIN <= e_n <= 1.0 and 0.0 <= xi <= XI_MAX):
        return np.nan
    if e_n == 1.0:
        return 0.0
    e0, de, ne = g[G_K_ETA + G_FIRST], g[G_K_ETA + G_STEP], int(g[G_K_ETA + G_COUNT])
    q0, dq, nq = g[G_K_Q + G_FIRST], g[G_K_Q + G_STEP], int(g[G_K_Q + G_COUNT])
    L = eval_2d_uniform(tx, ty, c, e0, de, ne, q0, dq, nq, eta_of_xi(xi), kinematic_q(e_n))
    return np.exp(L) * (1.0 - e_n) / e_n


@twin_rows
@njit(cache=True, nogil=True, error_model="numpy")
def alpha_from_table_rows(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g, out, start, stop):
    """``alpha_from_table`` over rows ``start .. stop - 1`` of flat arrays, into ``out``."""
    for i in range(start, stop):
        out[i] = alpha_from_table(eps[i], xi[i], b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g)


@twin_rows
@njit(cache=True, nogil=True, error_model="numpy")
def kinematic_alpha_from_table_rows(e_n, xi, tx, ty, c, g, out, start, stop):
    """``kinematic_alpha_from_table`` over rows ``start .. stop - 1`` of flat arrays, into ``out``."""
    for i in range(start, stop):
        out[i] = kinematic_alpha_from_table(e_n[i], xi[i], tx, ty, c, g)


def lookup_many(rows_kernel, values, xi, tables, threads=None):
    """A table's alpha over flat arrays by ``rows_kernel`` (``*_from_table_rows``).

    Inputs shorter than ``PARALLEL_MIN_LOOKUPS`` run in this thread (or with ``threads=1``);
    longer ones in ``threads.thread_count()`` threads.  Same bits either way.
    """
    out = np.empty(values.size)
    if values.size < PARALLEL_MIN_LOOKUPS:
        threads = 1
    run_rows(rows_kernel, values.size, values, xi, *tables, out, threads=threads)
    return out


# Below this many points one thread is faster than waking the others.
PARALLEL_MIN_LOOKUPS = 4096

# A table packed into one float64 array for the scalar path: a numba call unboxes each array
# argument (~0.7 us apiece), so nine arrays cost more than the spline itself.  Slots
# 3k, 3k+1, 3k+2 of the header hold array k's (offset, rows, columns); the data follow.
PACK_SLOTS = 3


def pack_table(arrays):
    """One contiguous float64 array holding ``arrays`` (1-D or 2-D), for ``*_from_packed``."""
    header = PACK_SLOTS * len(arrays)
    parts, offset, head = [], header, []
    for a in arrays:
        a = np.ascontiguousarray(a, dtype=np.float64)
        rows, cols = (1, a.size) if a.ndim == 1 else a.shape
        head += [offset, rows, cols]
        parts.append(a.ravel())
        offset += a.size
    return np.concatenate([np.asarray(head, dtype=np.float64), *parts])


@njit(cache=True, error_model="numpy")
def packed_vector(flat, k):
    """Array ``k`` of a packed table, 1-D (a view)."""
    start = int(flat[PACK_SLOTS * k])
    return flat[start : start + int(flat[PACK_SLOTS * k + 1]) * int(flat[PACK_SLOTS * k + 2])]


@njit(cache=True, error_model="numpy")
def packed_matrix(flat, k):
    """Array ``k`` of a packed table, 2-D (a view)."""
    rows, cols = int(flat[PACK_SLOTS * k + 1]), int(flat[PACK_SLOTS * k + 2])
    start = int(flat[PACK_SLOTS * k])
    return flat[start : start + rows * cols].reshape((rows, cols))


@njit(cache=True, error_model="numpy")
def alpha_from_packed(eps, xi, flat):
    """``alpha_from_table`` on a table packed by ``pack_table``: the same arithmetic, bit for bit."""
    # Array numbers as run-time int64, not constants: numba compiles a jitted callee once per
    # literal constant it is passed (see ``rk.rhs``).
    v, m, k = packed_vector, packed_matrix, np.int64
    return alpha_from_table(
        eps, xi, v(flat, k(0)), v(flat, k(1)), v(flat, k(2)), v(flat, k(3)), m(flat, k(4)),
        v(flat, k(5)), v(flat, k(6)), m(flat, k(7)), v(flat, k(8)),
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def kinematic_alpha_from_packed(e_n, xi, flat):
    """``kinematic_alpha_from_table`` on a table packed by ``pack_table``, bit for bit."""
    v, m, k = packed_vector, packed_matrix, np.int64  # run-time array numbers: see above
    return kinematic_alpha_from_table(e_n, xi, v(flat, k(0)), v(flat, k(1)), m(flat, k(2)), v(flat, k(3)))


def _grid_counts(path, geom, slots, n_geom):
    """Node counts of the uniform grids in ``geom`` (first, step, count per grid); raise if malformed."""
    geom = np.asarray(geom)
    if geom.shape != (n_geom,) or not np.all(np.isfinite(geom)):
        raise ValueError(
            f"exact-alpha table {path}: geometry array has shape {geom.shape} or non-finite entries; "
            f"valid: {n_geom} finite numbers"
        )
    counts = []
    for slot in slots:
        step, count = geom[slot + G_STEP], geom[slot + G_COUNT]
        if not (step > 0.0 and count >= 2 and count == int(count)):
            raise ValueError(
                f"exact-alpha table {path}: grid at geometry slot {slot} has step {step!r} and "
                f"{count!r} nodes; valid: a step > 0 and a whole number of nodes >= 2"
            )
        counts.append(int(count))
    return counts


def check_table_shapes(path, names, arrays):
    """Raise ``ValueError`` naming ``path`` unless every array has the shape its grids need.

    The jitted evaluators index the arrays by the node counts in the geometry array and numba
    does not check bounds: a file cut short would be read past its end.  A quintic spline on a
    clamped uniform grid of ``n`` nodes has ``n + 4`` coefficients and ``n + 10`` knots.
    """
    knots, coefs = DEGREE + 5, DEGREE - 1
    if tuple(names) == ARRAY_NAMES:
        s_eta, s_p, n_eta, n_p = _grid_counts(path, arrays["geom"], (G_S_ETA, G_S_P, G_N_ETA, G_N_P), N_GEOM)
        want = {
            "b_t": (s_eta + knots,),
            "b_c": (s_eta + coefs,),
            "s_tx": (s_eta + knots,),
            "s_ty": (s_p + knots,),
            "s_c": (s_eta + coefs, s_p + coefs),
            "n_tx": (n_eta + knots,),
            "n_ty": (n_p + knots,),
            "n_c": (n_eta + coefs, n_p + coefs),
        }
    elif tuple(names) == KINEMATIC_ARRAY_NAMES:
        k_eta, k_q = _grid_counts(path, arrays["k_geom"], (G_K_ETA, G_K_Q), N_K_GEOM)
        want = {"k_tx": (k_eta + knots,), "k_ty": (k_q + knots,), "k_c": (k_eta + coefs, k_q + coefs)}
    else:
        raise ValueError(
            f"names = {names!r} is not a table layout; valid: ARRAY_NAMES, KINEMATIC_ARRAY_NAMES"
        )
    for name, shape in want.items():
        got = arrays[name]
        if got.shape != shape or got.dtype != np.float64 or not np.all(np.isfinite(got)):
            raise ValueError(
                f"exact-alpha table {path}: array {name} has shape {got.shape} ({got.dtype}); "
                f"valid: finite float64 of shape {shape}, as its grid's node count says (cut short?)"
            )


def read_table_file(path, names, build_hint="`snakemake -c2 table`"):
    """``(arrays, meta)`` of a table file written by ``table_build``; refuse a different format version."""
    path = Path(path)
    if path.resolve() in SHIPPED_GRIDS:  # a table built elsewhere is not the package's: ship one
        build_hint = f"{build_hint} and `snakemake -c2 ship` (config.yaml's grid), or reinstall the package"
    if not path.exists():
        raise FileNotFoundError(f"exact-alpha table {path} not found; build it with {build_hint}")
    try:
        with np.load(path) as z:
            meta = json.loads(str(z["meta"]))
            arrays = {k: np.ascontiguousarray(z[k]) for k in names}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, json.JSONDecodeError) as err:
        raise ValueError(
            f"exact-alpha table {path} cannot be read ({type(err).__name__}: {err}): truncated or "
            f"corrupted; reinstall the package or rebuild it with {build_hint}"
        ) from None
    if not isinstance(meta, dict) or meta.get("format_version") != TABLE_FORMAT_VERSION:
        version = meta.get("format_version") if isinstance(meta, dict) else None
        raise ValueError(
            f"exact-alpha table {path} has format version {version!r}, "
            f"this package reads version {TABLE_FORMAT_VERSION}; rebuild it with {build_hint}"
        )
    check_table_shapes(path, names, arrays)
    got = checksum(arrays)
    if got != meta.get("sha256"):
        raise ValueError(
            f"exact-alpha table {path}: checksum {got[:12]}... differs from the recorded "
            f"{str(meta.get('sha256'))[:12]}...: changed or not written by table_build; "
            f"rebuild it with {build_hint}"
        )
    check_shipped_grid(path, meta)
    return arrays, meta


def checksum(arrays):
    """SHA-256 (hex) of the arrays' names, dtypes, shapes and bytes, in name order."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}:{a.dtype.str}:{a.shape};".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def check_shipped_grid(path, meta):
    """Refuse a table at one of the package's own paths whose grid or tolerances are not the shipped ones."""
    want = SHIPPED_GRIDS.get(Path(path).resolve())
    if want is None:
        return
    got = {key: meta.get(key) for key in want}
    if got != want:
        raise ValueError(
            f"exact-alpha table {path} was built with {got}, the package's table with {want}: a table "
            "of another grid does not have the documented accuracy; reinstall the package, or build one "
            "with config.yaml's grid and ship it (`snakemake -c2 ship`)"
        )


def load_table(path=DEFAULT_FILE):
    """Read the energetic table written by ``save_table``; refuse a different format version."""
    arrays, meta = read_table_file(path, ARRAY_NAMES)
    return AlphaTable(**arrays, meta=meta)


_CACHE: dict = {}


def table_arrays(path=DEFAULT_FILE):
    """The table's arrays in the argument order of ``alpha_from_table`` (read once per path)."""
    key = str(path)
    if key not in _CACHE:
        t = load_table(path)
        _CACHE[key] = tuple(getattr(t, name) for name in ARRAY_NAMES)
    return _CACHE[key]


def kinematic_table_arrays(path=KINEMATIC_FILE):
    """The kinematic table's arrays in the argument order of ``kinematic_alpha_from_table``."""
    key = ("kinematic", str(path))
    if key not in _CACHE:
        arrays, _ = read_table_file(path, KINEMATIC_ARRAY_NAMES, "`snakemake -c2 kinematic_table`")
        _CACHE[key] = tuple(arrays[name] for name in KINEMATIC_ARRAY_NAMES)
    return _CACHE[key]


@njit(cache=True, error_model="numpy")
def _first_outside(values, lo, hi):
    """Index of the first value outside [lo, hi] (NaN included), or -1."""
    for i in range(values.size):
        v = values[i]
        if not (lo <= v <= hi):
            return i
    return -1


# Its first calls on a cold numba cache run as its Python twin (``firstcall``).
_first_outside_first = FirstCall(_first_outside)


# Per restitution definition: (table file, scalar evaluator, row kernel of the array form, arrays).
def _lookup(restitution):
    if restitution == "kinematic":
        return (
            KINEMATIC_FILE,
            kinematic_alpha_from_table,
            kinematic_alpha_from_table_rows,
            kinematic_table_arrays,
        )
    if restitution == "energetic":
        return DEFAULT_FILE, alpha_from_table, alpha_from_table_rows, table_arrays
    raise ValueError(f"restitution = {restitution!r} is not one of 'energetic', 'kinematic'")


# restitution -> (packed scalar evaluator, shipped table packed once per process).
_SCALAR: dict = {}


def scalar_lookup(restitution):
    """``(f, flat)`` with ``f(eps, xi, flat)`` the shipped table's alpha of ``restitution``.

    The scalar fast path of ``alpha_tabulated`` and ``alpha(model="exact")``: plain floats in,
    NaN outside the table's domain (the caller then runs the full checks, which word the error).
    """
    fast = _SCALAR.get(restitution)
    if fast is None:
        default, _, _, arrays = _lookup(restitution)
        kernel = kinematic_alpha_from_packed if restitution == "kinematic" else alpha_from_packed
        flat = pack_table(arrays(default))

        def compiled(dispatcher):  # from then on the scalar paths call the kernel itself
            _SCALAR[restitution] = (dispatcher, flat)

        fast = _SCALAR[restitution] = (FirstCall(kernel, compiled), flat)
        if fast[0].compiled:  # NUMBA_DISABLE_JIT=1
            compiled(kernel)
    return fast


def alpha_tabulated(
    eps: RealLike, xi: RealLike, *, path: str | Path | None = None, restitution: str = "energetic"
) -> FloatOrArray:
    """Exact alpha(eps, xi) from the shipped table: ~1e-7 relative, at formula speed.

    Parameters
    ----------
    eps : array_like
        Restitution coefficient, ``EPS_MIN <= eps <= 1`` (the table's domain;
        use ``solve_alpha`` below 0.01): Stronge's eps, or Newton's e_N when
        ``restitution="kinematic"``.
    xi : array_like
        Influence factor, ``0 <= xi <= XI_MAX``.
    path : path-like, optional
        Table file; default the shipped table of the chosen definition.
    restitution : {"energetic", "kinematic"}
        Which coefficient ``eps`` is.
    """
    if not isinstance(restitution, str):
        raise ValueError(f"restitution = {restitution!r:.80} is not one of 'energetic', 'kinematic'")
    if path is None and type(eps) in PLAIN_FLOATS and type(xi) in PLAIN_FLOATS:
        fast = _SCALAR.get(restitution) or scalar_lookup(restitution)
        value = fast[0](eps, xi, fast[1])  # NaN outside the domain: then the checks below word it
        if value == value:
            return value
    default, scalar, rows, arrays = _lookup(restitution)
    tables = arrays(default if path is None else path)
    name = "e_N" if restitution == "kinematic" else "eps"
    e, x = np.broadcast_arrays(as_real(name, eps), as_real("xi", xi))
    e_flat, x_flat = flat_owned(e), flat_owned(x)
    # One jitted pass finds bad input; check_range then words the error.
    if _first_outside_first(e_flat, EPS_MIN, 1.0) >= 0:
        check_range(name, e_flat, EPS_MIN, 1.0)
    if _first_outside_first(x_flat, 0.0, XI_MAX) >= 0:
        check_range("xi", x_flat, 0.0, XI_MAX)
    out = lookup_many(rows, e_flat, x_flat, tables).reshape(e.shape)
    return out[()] if out.ndim == 0 else out


def tabulated_or_nan(values, xi, restitution="energetic"):
    """The shipped table's alpha over arrays, NaN outside its domain (and for NaN): no checks.

    For callers that have checked their own input and mark the rows outside (the batched front
    door); ``alpha_tabulated``'s numbers where it gives one.
    """
    default, _, rows, arrays = _lookup(restitution)
    v, x = np.broadcast_arrays(values, xi)
    return lookup_many(rows, flat_owned(v), flat_owned(x), arrays(default)).reshape(v.shape)


def jit_alpha_tabulated(path: str | Path | None = None, restitution: str = "energetic") -> Callable:
    """Return a numba-jitted scalar ``f(eps, xi) -> alpha`` for users' own jitted loops.

    The table arrays are frozen into the compiled function as constants.  Outside
    the table's domain ``EPS_MIN <= eps <= 1``, ``0 <= xi <= XI_MAX``, and for NaN
    input, ``f`` returns NaN (a jitted loop cannot raise a useful error);
    ``alpha_tabulated`` and ``alpha(..., model="exact")`` raise ``ValueError``
    naming the value and the range for the same inputs.  ``restitution="kinematic"``
    reads ``eps`` as Newton's e_N.
    """
    default, _, _, arrays = _lookup(restitution)
    tables = arrays(default if path is None else path)
    if restitution == "kinematic":
        tx, ty, c, g = tables

        @njit(error_model="numpy")
        def alpha_kinematic_jit(e_n, xi):
            return kinematic_alpha_from_table(e_n, xi, tx, ty, c, g)

        return alpha_kinematic_jit
    b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g = tables

    @njit(error_model="numpy")
    def alpha_exact_jit(eps, xi):
        return alpha_from_table(eps, xi, b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g)

    return alpha_exact_jit
