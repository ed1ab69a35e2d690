"""The inverse of every law in JAX: the target restitution -> the law's damping, NaN where none.

A law with a closed form (``ContactLaw.piecewise_linear``: MuJoCo's soft contact at any impedance,
the spring-dashpot) is inverted exactly on it (``closed_form.py``), as ``laws.solve`` does: the
bracket from ``p = 0`` grows by 4 up to ``P_MAX``, then Illinois steps with a bisection every
``BISECT_EVERY``-th, all without derivative; one Newton step, whose value is taken back out,
then carries the implicit function's derivative ``dp = (dtarget - de/dA dA) / (de/dp)``.  The
other laws read their shipped table (``tables.py``), as the numba batch does (at ``root_lookup``'s
target for a kinematic table on ``tau(ln e)``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from contactalpha.laws.solve import BISECT_EVERY, E_TOL, MAX_ITER, P_MAX, P_RTOL, P_START
from contactalpha.laws.table import root_damping, root_lookup

from . import closed_form
from .scaling import load_factor  # noqa: F401  (the load factor's home for callers of this module)
from .tables import device_table, table_damping

if TYPE_CHECKING:
    from jax.typing import ArrayLike

    from contactalpha.laws.law import ContactLaw

sg = jax.lax.stop_gradient


def _scaled_load_of_xi(law, xi):
    """``ContactLaw.scaled_load``: ``A = W/x_m``, ``W = xi/(2 (1 - xi))``, ``x_m^(n+1) = 1 + 2(1-d) W``."""
    w = 0.5 * xi / (1.0 - xi)
    return w / (1.0 + 2.0 * (1.0 - law.impedance) * w) ** (1.0 / (law.exponent + 1.0))


def _illinois(f, target):
    """Root of ``f(p) = target`` by ``laws.solve.damping_kernel``'s bracket and Illinois steps; (p, ok)."""
    g_of = lambda p: f(p) - target  # noqa: E731

    def grow(st):
        k, lo, glo, hi, ghi = st
        nxt = jnp.where(ghi > 0.0, 4.0 * hi, hi)
        return k + 1, jnp.where(ghi > 0.0, hi, lo), jnp.where(ghi > 0.0, ghi, glo), nxt, g_of(nxt)

    lo, hi = jnp.zeros_like(target), jnp.full(target.shape, P_START)
    st = (0, lo, 1.0 - target, hi, g_of(hi))
    _, lo, glo, hi, ghi = jax.lax.while_loop(lambda s: jnp.any((s[4] > 0.0) & (s[3] <= P_MAX)), grow, st)
    bracketed = (ghi <= 0.0) & (hi <= P_MAX)

    def step(st):
        it, lo, glo, hi, ghi, last, done, p = st
        mid = hi - ghi * (hi - lo) / jnp.where(ghi != glo, ghi - glo, 1.0)
        mid = jnp.where(
            ~((lo < mid) & (mid < hi)) | (it % BISECT_EVERY == BISECT_EVERY - 1), 0.5 * (lo + hi), mid
        )
        gm = g_of(mid)
        up = gm > 0.0
        ghi = jnp.where(up & (last == 1), 0.5 * ghi, ghi)
        glo = jnp.where(~up & (last == -1), 0.5 * glo, glo)
        lo, glo = jnp.where(up, mid, lo), jnp.where(up, gm, glo)
        hi, ghi = jnp.where(up, hi, mid), jnp.where(up, ghi, gm)
        last = jnp.where(up, 1, -1)
        stop = (gm == 0.0) | (hi - lo <= P_RTOL * hi) | (jnp.abs(gm) <= E_TOL) | jnp.isnan(gm)
        keep = done  # a finished point keeps its bracket and root
        found = jnp.where(jnp.isnan(gm), jnp.nan, mid)
        return (
            it + 1, jnp.where(keep, st[1], lo), jnp.where(keep, st[2], glo), jnp.where(keep, st[3], hi),
            jnp.where(keep, st[4], ghi), last, done | stop, jnp.where(keep, p, found),
        )  # fmt: skip

    exact = ghi == 0.0
    state = (
        0,
        lo,
        glo,
        hi,
        ghi,
        jnp.zeros(target.shape, int),
        ~bracketed | exact,
        jnp.where(exact, hi, jnp.nan),
    )
    out = jax.lax.while_loop(lambda s: (s[0] < MAX_ITER) & ~jnp.all(s[6]), step, state)
    p = jnp.where(target >= 1.0, 0.0, out[7])
    return p, bracketed & jnp.isfinite(p)


def closed_form_damping(
    law: ContactLaw, target: ArrayLike, xi: ArrayLike, restitution: str = "kinematic"
) -> jax.Array:
    """The law's damping ratio for ``target`` at load factor ``xi`` by its closed form (any impedance)."""
    kinematic = restitution == "kinematic"
    target, xi = jnp.broadcast_arrays(jnp.asarray(target, dtype=float), jnp.asarray(xi, dtype=float))
    inside = (target > 0.0) & (target <= 1.0) & (xi >= 0.0) & (xi < 1.0)
    e = jnp.where(inside, target, 0.5)
    A = _scaled_load_of_xi(law, jnp.where(inside, xi, 0.0))
    d = law.impedance
    p0, ok = _illinois(lambda p: closed_form.restitution(p, sg(A), d, kinematic), sg(e))
    p0 = sg(jnp.where(ok, p0, 1.0))
    f = lambda p, A: closed_form.restitution(p, A, d, kinematic)  # noqa: E731
    value, slope = jax.jvp(lambda p: f(p, sg(A)), (p0,), (jnp.ones_like(p0),))
    slope = sg(jnp.where(slope != 0.0, slope, jnp.nan))
    step = (f(p0, A) - e) / slope
    return jnp.where(inside & ok, p0 - (step - sg(step)), jnp.nan)


def law_damping(
    law: ContactLaw, target: ArrayLike, xi: ArrayLike, restitution: str = "kinematic"
) -> jax.Array:
    """The law's damping for ``target`` at ``xi``: by its closed form where it has one, else its table."""
    if law.piecewise_linear:
        return closed_form_damping(law, target, xi, restitution)
    tab = device_table(law, restitution)
    if not (getattr(law.fast, "root_near_one", False) and restitution == "kinematic"):
        return table_damping(tab, target, xi)
    # A kinematic table on tau(ln e) (laws/table.py): read at exp(tau), the damping converted back.
    e = jnp.asarray(target, dtype=float)
    lookup = root_lookup(e, jnp)
    return root_damping(table_damping(tab, lookup, xi), e, lookup, jnp)
