"""Closed-form impacts of the piecewise-linear laws in JAX: ``laws.closed_form`` on device arrays.

The same phases and events as ``laws/closed_form.py`` (docs/laws.md): compression to the turn of
``v``, then restitution phases ending in separation, capture, creep or a flight from the force's
floor, which may touch down again.  Each event time is an explicit formula or a root found by
the same bracketing and safeguarded Newton steps, carried without derivative; one Newton step
with the derivative, whose value is taken back out, then makes the time a differentiable
function of ``(zeta, A, d)`` with the implicit function's derivative.
The restitution is therefore differentiable wherever the sequence of phases does not change;
at a kink (a phase appearing, the separation boundary) the derivative is the one-sided
derivative of the phases taken.

The phases run as a fixed scan of ``PHASES`` restitution phases (``jax.grad`` needs a fixed trip
count); an impact that has not ended by then gives NaN and status NOT_CONVERGED, where the numba
form goes on to ``laws.closed_form.MAX_PHASES``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from contactalpha.engine.codes import CREEP, NO_RESTITUTION, NONSEPARATION, SEPARATION
from contactalpha.laws.closed_form import NEWTON_DONE, NEWTON_ITER, START_ON_ROOT

if TYPE_CHECKING:
    from jax.typing import ArrayLike

# Restitution phases (contact, flight from the floor, re-contact, ...) followed before giving up.
PHASES = 8
# Monotone pieces searched for a root's bracket, and doublings of an unbounded bracket
# (``laws.closed_form._root`` and ``_polish``).
BRACKET_PIECES = 8
DOUBLINGS = 2000
sg = jax.lax.stop_gradient


def _regimes(zeta):
    """Under-, critically and overdamped masks, with each regime's frequency (safe elsewhere)."""
    under, over = zeta < 1.0, zeta > 1.0
    zu = jnp.where(under, zeta, 0.5)
    zo = jnp.where(over, zeta, 2.0)
    return under, over, jnp.sqrt((1.0 - zu) * (1.0 + zu)), jnp.sqrt((zo - 1.0) * (zo + 1.0)), zo


def _z(zeta, P, Q, t):
    """``z(t) = e^{-zeta t} (P C + Q S)`` and ``z'(t)`` (``laws.closed_form._z``); ``t`` finite."""
    under, over, wu, wo, zo = _regimes(zeta)
    cu, su = jnp.cos(wu * t), jnp.sin(wu * t)
    ep = 0.5 * jnp.exp((wo - zo) * t)
    em = 0.5 * jnp.exp(-(wo + zo) * t)
    c = jnp.where(under, cu, jnp.where(over, ep + em, 1.0))
    s = jnp.where(under, su / wu, jnp.where(over, (ep - em) / wo, t))
    dc = jnp.where(under, -wu * su, jnp.where(over, wo * (ep - em), 0.0))
    ds = jnp.where(under, cu, jnp.where(over, ep + em, 1.0))
    val = P * c + Q * s
    der = -zeta * val + P * dc + Q * ds
    e = jnp.where(over, 1.0, jnp.exp(-jnp.where(over, 0.0, zeta) * t))
    return e * val, e * der


def _first_zero(zeta, P, Q):
    """First ``t > 0`` with ``P C(t) + Q S(t) = 0``, ``inf`` if none (``laws.closed_form._first_zero``)."""
    under, over, wu, wo, _ = _regimes(zeta)
    ang = jnp.mod(jnp.arctan2(-P * wu, Q), jnp.pi)
    t_u = jnp.where(ang <= 0.0, jnp.pi, ang) / wu
    q = jnp.where(Q != 0.0, Q, 1.0)
    r_c = -P / q
    t_c = jnp.where((Q != 0.0) & (r_c > 0.0), r_c, jnp.inf)
    r_o = -P * wo / q
    ok = (Q != 0.0) & (r_o > 0.0) & (r_o < 1.0)
    t_o = jnp.where(ok, jnp.arctanh(jnp.where(ok, r_o, 0.5)) / wo, jnp.inf)
    return jnp.where(under, t_u, jnp.where(over, t_o, t_c))


def _derivative_coefficients(zeta, P, Q):
    dz0 = Q - zeta * P
    return dz0, -P - 2.0 * zeta * dz0 + zeta * dz0


def _shift(zeta, P, Q, t0):
    z, dz = _z(zeta, P, Q, t0)
    return z, dz + zeta * z


def _bracket(zeta, P, Q, c, t_end, g0, active):
    """(found, lo, hi, g(lo), g(hi)): the first monotone piece of ``z + c`` on (0, t_end] changing sign."""
    dP, dQ = _derivative_coefficients(zeta, P, Q)

    def body(st):
        k, lo, _, _, _, _, _ = st
        sP, sQ = _shift(zeta, dP, dQ, lo)
        hi = jnp.minimum(lo + _first_zero(zeta, sP, sQ), t_end)
        fin = jnp.isfinite(hi)
        gh = jnp.where(fin, _z(zeta, P, Q, jnp.where(fin, hi, 0.0))[0], 0.0) + c
        cross = ((gh > 0.0) != (g0 > 0.0)) | (gh == 0.0)
        glo = jnp.where(lo == 0.0, g0, _z(zeta, P, Q, lo)[0] + c)
        stop = cross | (hi >= t_end)
        return k + 1, jnp.where(stop, lo, hi), stop, cross, hi, glo, gh

    z0 = jnp.zeros_like(P)
    st = (0, z0, ~active, False, z0, z0, z0)
    _, lo, _, found, hi, glo, ghi = jax.lax.while_loop(lambda s: (s[0] < BRACKET_PIECES) & ~s[2], body, st)
    return found, lo, hi, glo, ghi


def _polish(zeta, P, Q, c, lo, hi, g0, glo, ghi, active):
    """The root in [lo, hi] (``laws.closed_form._polish``): Newton steps kept inside, Illinois otherwise."""

    def grow(st):
        k, lo, hi, glo, ghi, _ = st
        g = _z(zeta, P, Q, hi)[0] + c
        out = (g > 0.0) != (g0 > 0.0)
        return k + 1, jnp.where(out, lo, hi), jnp.where(out, hi, 2.0 * hi), jnp.where(out, glo, g), g, out

    unbounded = ~jnp.isfinite(hi)
    hi0 = jnp.where(unbounded, jnp.maximum(2.0 * lo, 1.0), hi)
    _, lo, hi, glo, ghi, _ = jax.lax.while_loop(
        lambda s: (s[0] < DOUBLINGS) & ~s[5], grow, (0, lo, hi0, glo, ghi, ~unbounded | ~active)
    )
    mid = 0.5 * (lo + hi)
    t = jnp.where(ghi != glo, hi - ghi * (hi - lo) / jnp.where(ghi != glo, ghi - glo, 1.0), mid)
    t = jnp.where((lo < t) & (t < hi), t, mid)

    def step(st):
        k, t, lo, hi, glo, ghi, side, _, _ = st
        z, dz = _z(zeta, P, Q, t)
        g = z + c
        same = (g > 0.0) == (g0 > 0.0)
        ghi = jnp.where(same & (side == 1), 0.5 * ghi, ghi)
        glo = jnp.where(~same & (side == -1), 0.5 * glo, glo)
        lo, glo = jnp.where(same, t, lo), jnp.where(same, g, glo)
        hi, ghi = jnp.where(same, hi, t), jnp.where(same, ghi, g)
        side = jnp.where(same, 1, -1)
        new = jnp.where(dz != 0.0, t - g / jnp.where(dz != 0.0, dz, 1.0), lo - 1.0)
        sec = jnp.where(
            ghi != glo, hi - ghi * (hi - lo) / jnp.where(ghi != glo, ghi - glo, 1.0), 0.5 * (lo + hi)
        )
        sec = jnp.where((lo < sec) & (sec < hi), sec, 0.5 * (lo + hi))
        new = jnp.where((lo < new) & (new < hi), new, sec)
        done = (jnp.abs(new - t) <= NEWTON_DONE * t) | (hi - lo <= 4e-16 * hi)
        exact = g == 0.0
        result = jnp.where(exact, t, new)
        return k + 1, result, lo, hi, glo, ghi, side, done | exact, result

    st = (0, t, lo, hi, glo, ghi, 0, ~active, t)
    out = jax.lax.while_loop(lambda s: (s[0] < NEWTON_ITER) & ~s[7], step, st)
    return out[8]


def _root(zeta, P, Q, c, t_end, active):
    """First ``t`` in (0, t_end] with ``z(t) + c = 0`` crossing from the sign at 0 (``inf`` if none).

    Found without derivative; one Newton step with it makes ``t`` differentiable in the inputs.
    Where ``active`` is False no root is sought (``inf``): the loops of a batch stop early.
    """
    z_, P_, Q_, c_, te = sg(zeta), sg(P), sg(Q), sg(c), sg(t_end)
    g0 = P_ + c_
    g0 = jnp.where(jnp.abs(g0) <= START_ON_ROOT * (jnp.abs(P_) + jnp.abs(c_)), Q_ - z_ * P_, g0)
    found, lo, hi, glo, ghi = _bracket(z_, P_, Q_, c_, te, g0, active)
    found = found & active
    t0 = jnp.where(found, _polish(z_, P_, Q_, c_, lo, hi, g0, glo, ghi, found), jnp.inf)
    fin = jnp.isfinite(t0)
    ts = jnp.where(fin, t0, 0.0)
    z, dz = _z(zeta, P, Q, ts)
    step = (z + c) / jnp.where(dz != 0.0, dz, 1.0)
    # The value stays the numba form's root; the step contributes its derivative only.
    return jnp.where(fin, ts - (step - sg(step)), jnp.inf)


def _flight(zeta, A, x0, v0):
    """Flight ``x'' = A`` from the floor (``laws.closed_form._flight_step``): (code, x, v)."""
    pos = A > 0.0
    Ap = jnp.where(pos, A, 1.0)
    t_r = jnp.where(pos, -2.0 * (v0 + 2.0 * zeta * A) / Ap, jnp.inf)
    t_r = jnp.where(t_r > 0.0, t_r, jnp.inf)
    disc = v0 * v0 - 2.0 * A * x0
    root = jnp.where(disc > 0.0, jnp.sqrt(jnp.where(disc > 0.0, disc, 1.0)), 0.0)
    den = -v0 + root
    real = (disc >= 0.0) & (den != 0.0)
    t_s = jnp.where(real, 2.0 * x0 / jnp.where(real, den, 1.0), jnp.inf)
    t_c = jnp.where(pos, -v0 / Ap, jnp.inf)
    sep = (t_s <= t_r) & (t_s <= t_c)
    cap = ~sep & (t_c < t_r)
    tc = jnp.where(cap, t_c, 0.0)
    tr = jnp.where(~sep & ~cap, t_r, 0.0)
    ts = jnp.where(sep, t_s, 0.0)
    code = jnp.where(sep, SEPARATION, jnp.where(cap, NONSEPARATION, 0))
    x = jnp.where(sep, 0.0, jnp.where(cap, x0 + tc * (v0 + 0.5 * A * tc), x0 + tr * (v0 + 0.5 * A * tr)))
    v = jnp.where(sep, v0 + A * ts, jnp.where(cap, 0.0, v0 + A * tr))
    return code, x, v


def _impact(zeta, A, d):
    """(eps^2, e_N, end state, floors, ended) of one impact from (0, 1), scalars (``closed_form_impact``)."""
    x_eq = (1.0 - d) * A
    u = -x_eq
    t_v = _first_zero(zeta, 1.0, -(u + zeta))
    turned = jnp.isfinite(t_v)
    x_m = x_eq + _z(zeta, u, 1.0 + zeta * u, jnp.where(turned, t_v, 0.0))[0]
    x_m = jnp.where(turned, x_m, x_eq)
    energy = 0.5 + A * x_m

    def phase(st, _):
        x_now, v_now, floors, done, eps2, e_n, state = st
        # An ended impact runs on from a harmless state (no 0/0 in the discarded derivatives).
        x = jnp.where(done, x_eq + 1.0, x_now)
        v = jnp.where(done, -1.0, v_now)
        u = x - x_eq
        Pu, Qu = u, v + zeta * u
        Pv, Qv = v, -(u + zeta * v)
        t_v = _first_zero(zeta, Pv, Qv)
        live = ~done
        t_f = _root(zeta, Pu + 2.0 * zeta * Pv, Qu + 2.0 * zeta * Qv, A, t_v, live & (zeta > 0.0))
        t_end = jnp.minimum(t_v, t_f)
        fin = jnp.isfinite(t_end)
        zu, dzu = _z(zeta, Pu, Qu, jnp.where(fin, t_end, 0.0))
        zu, dzu = jnp.where(fin, zu, -x_eq), jnp.where(fin, dzu, 0.0)
        look = (x > 0.0) & ((d > 0.0) | (zeta == 0.0)) & ((x_eq + zu <= 0.0) | ~fin)
        t_s = jnp.where(
            x <= 0.0, 0.0, jnp.where(look, _root(zeta, Pu, Qu, x_eq, t_end, live & look), jnp.inf)
        )
        sep = (t_s <= t_f) & jnp.isfinite(t_s)
        v_e = _z(zeta, Pu, Qu, jnp.where(sep, t_s, 0.0))[1]
        floor = ~sep & jnp.isfinite(t_f)
        code, xf, vf = _flight(zeta, A, x_eq + zu, dzu)
        capture = ~sep & ~floor & jnp.isfinite(t_v)
        fsep, fcap = floor & (code == SEPARATION), floor & (code == NONSEPARATION)
        x_end = jnp.where(capture, x_eq + zu, jnp.where(fcap, xf, x_eq))
        ends = sep | capture | fsep | fcap | (~sep & ~floor & ~capture)
        v_out = jnp.where(sep, v_e, vf)
        new_eps2 = jnp.where(sep | fsep, 0.5 * v_out * v_out + A * x_m, A * (x_m - x_end)) / energy
        new_en = jnp.where(sep | fsep, -v_out, 0.0)
        new_state = jnp.where(sep | fsep, SEPARATION, jnp.where(capture | fcap, NONSEPARATION, CREEP))
        return (
            jnp.where(live & floor & ~ends, xf, x_now),
            jnp.where(live & floor & ~ends, vf, v_now),
            floors + (live & floor),
            done | ends,
            jnp.where(live & ends, new_eps2, eps2),
            jnp.where(live & ends, new_en, e_n),
            jnp.where(live & ends, new_state, state),
        ), None

    zero = jnp.zeros_like(x_m)
    st = (x_m, zero, 0, ~turned, zero, zero, jnp.where(turned, 0, NO_RESTITUTION))
    (_, _, floors, done, eps2, e_n, state), _ = jax.lax.scan(phase, st, None, length=PHASES)
    nan = jnp.nan
    return jnp.where(done, eps2, nan), jnp.where(done, e_n, nan), state, floors, done


def impact(
    zeta: ArrayLike, A: ArrayLike, d: ArrayLike
) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array, jax.Array]:
    """Both restitutions of impacts at damping ratio ``zeta``, scaled load ``A``, impedance ``d`` (broadcast).

    Returns
    -------
    (eps, e_N, state, floors, ended)
        NaN restitutions where the impact did not end within ``PHASES`` phases (``ended`` False).
    """
    zeta, A, d = jnp.broadcast_arrays(*(jnp.asarray(x, dtype=float) for x in (zeta, A, d)))
    eps2, e_n, state, floors, ended = jnp.vectorize(_impact)(zeta, A, d)
    pos = eps2 > 0.0
    eps = jnp.where(pos, jnp.sqrt(jnp.where(pos, eps2, 1.0)), jnp.where(jnp.isnan(eps2), jnp.nan, 0.0))
    return eps, e_n, state, floors, ended


def restitution(zeta: ArrayLike, A: ArrayLike, d: ArrayLike, kinematic: bool) -> jax.Array:
    """Restitution (``e_N`` if ``kinematic``, else eps) at ``zeta``, ``A``, ``d``; NaN if it did not end."""
    eps, e_n, _, _, _ = impact(zeta, A, d)
    return e_n if kinematic else eps
