"""The shipped exact-damping tables as device arrays, and their inverse as a pure JAX function.

One layout serves every table (``engine/table.py`` for Hunt-Crossley, n = 3/2; ``laws/table.py``
for the other laws): the plane ``(eta, u = ln target)`` is cut along ``K`` curves
``b_1 > ... > b_K`` (quintic splines in eta) into ``K + 1`` regions, each a tensor quintic spline of
``L = ln(p e / (1 - e))`` in ``(eta, w)``: region 0 has ``w = sqrt(1 - u / b_1)`` (or
``(2/pi) asin`` of it for a table with ``root_near_one``), region K
``w = sqrt((b_K - u) / (b_K - ln 0.01))``, a region between two cuts
``w = (2/pi) asin(sqrt((b_r - u) / (b_r - b_(r+1))))``.  The n = 3/2 energetic table is the case
K = 1 (its separation boundary).  A kinematic table (Newton's e_N) has no cut and ``w = ln e_N``.

The files are read and checked by the numba side's loaders; here their arrays become ``jnp``
arrays once per process (``device_table``).  ``table_damping`` is elementwise, broadcasts, and
accepts ``jax.jit``, ``jax.vmap`` and ``jax.grad``: outside the table's domain
(``EPS_MIN <= target <= 1``, ``0 <= xi <= XI_MAX``) it returns NaN, never an extrapolated number.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, cast

import jax
import jax.numpy as jnp

from contactalpha.engine.table import (
    DEFAULT_FILE,
    EPS_MIN,
    KINEMATIC_FILE,
    U_MIN,
    XI_MAX,
    XI_SCALE,
    kinematic_table_arrays,
    table_arrays,
)
from contactalpha.laws.fast import ENGINE_TABLE
from contactalpha.laws.table import GEOM_HEAD, REGION_SLOTS, load_law_tables

from . import splines

if TYPE_CHECKING:
    from jax.typing import ArrayLike

    from contactalpha.laws.law import ContactLaw


@jax.tree_util.register_dataclass
@dataclass(frozen=True)
class DeviceTable:
    """One restitution's table on the device (see the module docstring).

    Attributes
    ----------
    curves : the cuts' 1-D splines: ``c`` (K, n + 4) on one ``grid`` (first, step, count).
    regions : stacked 2-D splines of the K + 1 regions (``splines.stack``).
    cuts : K (static).
    kinematic : True for a table in ``ln e_N`` without cuts (static).
    root : True when region 0 is square-root-like at e = 1 too (``LawTable.root_near_one``; static).
    """

    curves: dict
    regions: dict
    cuts: int = field(default=0, metadata={"static": True})
    kinematic: bool = field(default=False, metadata={"static": True})
    root: bool = field(default=False, metadata={"static": True})


def eta_of_xi(xi: ArrayLike) -> jax.Array:
    """``engine.table.eta_of_xi`` in JAX: ``ln(1 + xi / XI_SCALE) - ln(1 - xi)``."""
    x = cast(jax.Array, xi)  # a real load factor
    return jnp.log1p(x / XI_SCALE) - jnp.log1p(-x)


def _no_curves():
    return {"c": jnp.zeros((0, 1)), "grid": jnp.zeros(3)}


def _curves(t, c, grid):
    splines.check_knots(t, grid, "cut curves")
    return {"c": jnp.asarray(c), "grid": jnp.asarray(grid)}


def _kinematic(tx, ty, c, g):
    return DeviceTable(_no_curves(), splines.stack([(tx, ty, c, g)]), 0, True)


def _hertz_energetic():
    b_t, b_c, s_tx, s_ty, s_c, n_tx, n_ty, n_c, g = table_arrays(DEFAULT_FILE)
    curves = _curves(b_t, b_c[None, :], g[0:3])
    return DeviceTable(curves, splines.stack([(s_tx, s_ty, s_c, g[0:6]), (n_tx, n_ty, n_c, g[6:12])]), 1)


def _law_energetic(arrays, root):
    g = arrays["geom"]
    cuts = int(g[0])
    curves = _curves(arrays["curves_t"], arrays["curves_c"], g[1:4])
    regions = []
    for r in range(cuts + 1):
        o = GEOM_HEAD + REGION_SLOTS * r
        regions.append((arrays[f"r{r}_tx"], arrays[f"r{r}_ty"], arrays[f"r{r}_c"], g[o : o + 6]))
    return DeviceTable(curves, splines.stack(regions), cuts, root=root)


_CACHE: dict = {}


def device_table(law: ContactLaw, restitution: str = "energetic") -> DeviceTable:
    """The shipped table of ``law`` (a ``ContactLaw`` with a table) for ``restitution``, on the device.

    Hunt-Crossley, n = 3/2 reads ``alpha_table*.npz``; the other laws their ``law_table_<law>.npz``
    at the impedance it was built at.  Read, checked and converted once per process.
    """
    kinematic = restitution == "kinematic"
    key = (law.name, kinematic)
    if key not in _CACHE:
        with jax.ensure_compile_time_eval():  # concrete arrays even when first asked inside a trace
            _CACHE[key] = _build(law, kinematic)
    return _CACHE[key]


def _build(law, kinematic):
    if law.fast is ENGINE_TABLE:
        return _kinematic(*kinematic_table_arrays(KINEMATIC_FILE)) if kinematic else _hertz_energetic()
    law.fast.packed(law, kinematic)  # the numba side's checks: law, grid, cuts, impedance
    arrays, _ = load_law_tables(law.fast.path)
    if kinematic:
        return _kinematic(*(arrays[n] for n in ("k_tx", "k_ty", "k_c", "k_geom")))
    return _law_energetic(arrays, law.fast.root_near_one)


def _curve_values(curves, eta):
    """Every cut's ``b_k(eta)``, shape (..., K)."""
    j, X, n = splines._span(eta, curves["grid"])
    N = splines._basis(j, X, n)
    rows = j.astype(jnp.int32)[..., None] + jnp.arange(splines.DEGREE + 1)
    return jnp.einsum("k...j,...j->...k", curves["c"][:, rows], N)


def _column(tab, u, eta):
    """Region index and column coordinate ``w`` of ``(eta, u)``."""
    if tab.kinematic:
        return jnp.zeros(u.shape, dtype=jnp.int32), u
    K = tab.cuts
    b = _curve_values(tab.curves, eta)
    below = u[..., None] < b
    r = jnp.sum(jnp.cumprod(below, axis=-1), axis=-1)
    bb = jnp.concatenate([b, b[..., -1:]], axis=-1)  # a harmless "lower" for region K
    upper = jnp.take_along_axis(bb, jnp.maximum(r - 1, 0)[..., None], axis=-1)[..., 0]
    lower = jnp.take_along_axis(bb, r[..., None], axis=-1)[..., 0]
    # Each branch's argument is made harmless where another branch is taken (NaN-free gradients).
    a0 = jnp.where(r == 0, 1.0 - u / b[..., 0], 1.0)
    aK = jnp.where(r == K, (upper - u) / (upper - U_MIN), 1.0)
    mid = (r > 0) & (r < K)
    am = jnp.where(mid, jnp.clip((upper - u) / jnp.where(mid, upper - lower, 1.0), 0.0, 1.0), 0.5)
    if tab.root:  # square-root-like at e = 1 too (an interior point where another branch is taken)
        w0 = (2.0 / jnp.pi) * jnp.arcsin(jnp.sqrt(jnp.where(r == 0, jnp.clip(a0, 0.0, 1.0), 0.5)))
    else:
        w0 = jnp.sqrt(a0)
    w = jnp.where(r == 0, w0, jnp.where(r == K, jnp.sqrt(aK), (2.0 / jnp.pi) * jnp.arcsin(jnp.sqrt(am))))
    return r, w


def table_damping(tab: DeviceTable, target: ArrayLike, xi: ArrayLike) -> jax.Array:
    """The table's damping ``p`` at ``target`` (eps or e_N) and load factor ``xi``; NaN outside its domain.

    Elementwise with broadcasting; ``engine.table.alpha_from_table``,
    ``kinematic_alpha_from_table`` and ``laws.table.damping_from_packed`` in JAX.
    """
    target, xi = jnp.broadcast_arrays(jnp.asarray(target, dtype=float), jnp.asarray(xi, dtype=float))
    inside = (target >= EPS_MIN) & (target <= 1.0) & (xi >= 0.0) & (xi <= XI_MAX)
    interior = inside & (target < 1.0)
    e = jnp.where(interior, target, 0.5)
    x = jnp.where(interior, xi, 0.5)
    u = jnp.log(e)
    eta = eta_of_xi(x)
    r, w = _column(tab, u, eta)
    L = splines.eval_2d(tab.regions, r, eta, w)
    p = jnp.exp(L) * (1.0 - e) / e
    return jnp.where(interior, p, jnp.where(inside, 0.0, jnp.nan))


__all__ = ["DeviceTable", "device_table", "eta_of_xi", "table_damping"]
