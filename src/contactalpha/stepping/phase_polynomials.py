"""Polynomials in the touchdown phase: their roots in an interval, and e_N integrated over a piece.

``affine_phase`` carries a drop's states as quadratics ``c0 + c1 t + c2 t^2`` in the phase ``t``;
here are the roots it cuts pieces at and the adaptive Gauss-Legendre quadrature of e_N (the
closed form ``flight.rebound_speed`` of the final state's polynomials) over one piece.
"""

import math

import numpy as np
from numba import njit

from .codes import P_MAX, P_MIN
from .flight import rebound_speed

# A root closer than this above an interval's start is not reported (the root that made the start,
# computed again); the sliver it leaves is at most this wide in phase.
ROOT_GAP = 1e-12
# Gauss-Legendre nodes of the quadrature on each interval (exact for degree 2 n - 1), and the most
# intervals one piece is split into.
GL_NODES = 8
GL_X, GL_W = np.polynomial.legendre.leggauss(GL_NODES)
MAX_SPLITS = 2000


@njit(cache=True)
def value(q: np.ndarray, t: float) -> float:
    """The quadratic with coefficients ``q`` at ``t``."""
    return q[0] + t * (q[1] + t * q[2])


@njit(cache=True)
def poly(c0: float, c1: float, c2: float, t: float) -> float:
    """``c0 + c1 t + c2 t^2``."""
    return c0 + t * (c1 + t * c2)


@njit(cache=True)
def roots_into(c0: float, c1: float, c2: float, lo: float, hi: float, buf: np.ndarray, nb: int) -> int:
    """Append the roots of ``c0 + c1 t + c2 t^2`` in ``(lo + ROOT_GAP, hi)`` to ``buf[nb:]``; new count."""
    lo = lo + ROOT_GAP
    m = 0.5 * (lo + hi)
    r = 0.5 * (hi - lo)
    if r <= 0.0 or abs(c0 + m * (c1 + m * c2)) > abs(c1 + 2.0 * c2 * m) * r + abs(c2) * r * r:
        return nb  # |change over the interval| < |value at its middle|: no root
    if c2 == 0.0:
        if c1 != 0.0 and lo < -c0 / c1 < hi:
            buf[nb] = -c0 / c1
            nb += 1
        return nb
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return nb
    q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
    if q != 0.0 and lo < c0 / q < hi:
        buf[nb] = c0 / q
        nb += 1
    if lo < q / c2 < hi:
        buf[nb] = q / c2
        nb += 1
    return nb


@njit(cache=True)
def sort_roots(buf: np.ndarray, nb: int) -> None:
    """Sort ``buf[:nb]`` in place (insertion: a handful of roots)."""
    for i in range(1, nb):
        x = buf[i]
        k = i - 1
        while k >= 0 and buf[k] > x:
            buf[k + 1] = buf[k]
            k -= 1
        buf[k + 1] = x


@njit(cache=True)
def _gl(zf, wf, accel, h, v_in, a, b, acc):
    """Gauss-Legendre on ``[a, b]`` of ``(e_N, e_N^2)``; each node folded into ``acc``'s range."""
    half = 0.5 * (b - a)
    mid = 0.5 * (a + b)
    s0 = 0.0
    s1 = 0.0
    for i in range(GL_X.size):
        t = mid + half * GL_X[i]
        e = rebound_speed(value(zf, t), value(wf, t), accel, h) / v_in
        acc[P_MIN] = min(acc[P_MIN], e)
        acc[P_MAX] = max(acc[P_MAX], e)
        s0 += GL_W[i] * e
        s1 += GL_W[i] * e * e
    return half * s0, half * s1


@njit(cache=True)
def integrate_piece(
    zf: np.ndarray,
    wf: np.ndarray,
    accel: float,
    h: float,
    v_in: float,
    lo: float,
    hi: float,
    tol: float,
    acc: np.ndarray,
) -> tuple[float, float, float, bool]:
    """Adaptive Gauss-Legendre of e_N over one separated piece: ``(int e, int e^2, error, limited)``."""
    for t in (lo, hi):  # both ends of the piece: the one-sided limits a single drop approaches
        e = rebound_speed(value(zf, t), value(wf, t), accel, h) / v_in
        acc[P_MIN] = min(acc[P_MIN], e)
        acc[P_MAX] = max(acc[P_MAX], e)
    e0, e1 = _gl(zf, wf, accel, h, v_in, lo, hi, acc)
    m = 0.5 * (lo + hi)
    l0, l1 = _gl(zf, wf, accel, h, v_in, lo, m, acc)
    r0, r1 = _gl(zf, wf, accel, h, v_in, m, hi, acc)
    d = abs(l0 + r0 - e0)
    if d <= tol * (hi - lo) or m <= lo or m >= hi:
        return l0 + r0, l1 + r1, d, False  # the usual case: no stack
    stack_a = [lo]
    stack_b = [hi]
    stack_e = [e0]
    stack_f = [e1]
    s0 = s1 = err = 0.0
    splits = 0
    limited = False
    while len(stack_a) > 0:
        a, b, q0, _ = stack_a.pop(), stack_b.pop(), stack_e.pop(), stack_f.pop()
        m = 0.5 * (a + b)
        l0, l1 = _gl(zf, wf, accel, h, v_in, a, m, acc)
        r0, r1 = _gl(zf, wf, accel, h, v_in, m, b, acc)
        d = abs(l0 + r0 - q0)
        splits += 1
        if d <= tol * (b - a) or splits >= MAX_SPLITS or m <= a or m >= b:
            s0 += l0 + r0
            s1 += l1 + r1
            err += d
            limited = limited or d > tol * (b - a)
        else:
            stack_a.append(a)
            stack_b.append(m)
            stack_e.append(l0)
            stack_f.append(l1)
            stack_a.append(m)
            stack_b.append(b)
            stack_e.append(r0)
            stack_f.append(r1)
    return s0, s1, err, limited
