"""Physical units <-> the two dimensionless numbers (paper Eqs. 1, 8, 10, 11).

Lengths are scaled by ``delta_star = (5 m_e v0^2 / (4 k))^(2/5)``, the maximum
compression of the undamped, unloaded contact, and times by
``t_star = delta_star / v0``.  The scaled load is ``A = a delta_star / v0^2``.
For the undamped loaded contact the maximum compression is
``x_m = (1 - xi)^(-2/5)`` (Eq. 11), and Eq. 10 then gives
``A = xi (1 - xi)^(-3/5) / 2``.
"""

import math

import numpy as np
from numba import njit

from contactalpha.validation import (
    PLAIN_FLOATS,
    FloatOrArray,
    RealLike,
    check_positive,
    check_range,
    check_xi,
    renamed_keywords,
)

from .firstcall import FirstCall

# The public API's names of the scene's quantities (the front door's), and their old names here.
OLD_NAMES = {"m_e": "mass", "k": "stiffness", "v0": "approach_speed"}


@renamed_keywords(**OLD_NAMES)
def length_scale(mass: RealLike, stiffness: RealLike, approach_speed: RealLike) -> FloatOrArray:
    """``delta_star`` in metres, for mass kg, stiffness N/m^1.5 and approach speed m/s."""
    m_e, k, v0 = mass, stiffness, approach_speed
    if (
        type(m_e) in PLAIN_FLOATS
        and type(k) in PLAIN_FLOATS
        and type(v0) in PLAIN_FLOATS
        and 0.0 < m_e < math.inf
        and 0.0 < k < math.inf
        and 0.0 < v0 < math.inf
    ):
        # Scalar fast path, no array checks: numpy squares v0 as v0 * v0 and powers with the same libm.
        return (1.25 * m_e * (v0 * v0) / k) ** 0.4
    m_e, k, v0 = (check_positive(n, val) for n, val in zip(OLD_NAMES.values(), (m_e, k, v0), strict=True))
    arrays = [np.ascontiguousarray(x, dtype=float).ravel() for x in np.broadcast_arrays(m_e, k, v0)]
    out = np.empty(arrays[0].size)
    _length_rows(*arrays, out)
    out = out.reshape(np.broadcast_shapes(*(np.shape(x) for x in (m_e, k, v0))))
    return out[()] if out.ndim == 0 else out


@njit(cache=True, error_model="numpy")
def _length_rows(m_e, k, v0, out):
    # libm's pow element by element, as the scalar path: numpy's SIMD pow (AVX-512) may differ from
    # libm in the last bit, and an array's delta_star would then not be its scalars' delta_star.
    for i in range(out.size):
        out[i] = (1.25 * m_e[i] * (v0[i] * v0[i]) / k[i]) ** 0.4


@renamed_keywords(**OLD_NAMES)
def time_scale(mass: RealLike, stiffness: RealLike, approach_speed: RealLike) -> FloatOrArray:
    """``t_star = delta_star / approach_speed`` in seconds."""
    return length_scale(mass, stiffness, approach_speed) / np.asarray(approach_speed, dtype=float)


def scaled_load(xi: RealLike) -> FloatOrArray:
    """Scaled load ``A(xi) = xi (1 - xi)^(-3/5) / 2``; shape follows ``xi``."""
    return scaled_load_unchecked(check_xi(xi))


def scaled_load_unchecked(xi):
    """``scaled_load`` of a float or float array already checked to lie in [0, 1)."""
    return 0.5 * xi * (1.0 - xi) ** -0.6


# Scaled load beyond which xi rounds to 1 for certain (1 - xi ~ (2A)^(-5/3) < 1e-50); capping A
# there also keeps x_m^(5/2) in the Newton iteration far from overflow (near A ~ 1e185).
A_ROUNDS_TO_ONE = 1e30
# Newton steps of Eq. 10's x_m solve: a fixed count (no data-dependent exit, so the compiled, the
# Python and the exported C forms take the same steps); converged long before for every A <= 1e30.
XI_NEWTON_STEPS = 60


def _xi_newton_step(A, xm):
    """One Newton step on ``(x_m^{5/2} - 1)/2 = A x_m`` (Eq. 8 scaled), floats or arrays."""
    g = 0.5 * (xm**2.5 - 1.0) - A * xm
    dg = 1.25 * xm**1.5 - A
    return xm - g / dg


def _xi_of_load(A):
    """Eq. 10 for finite ``0 <= A <= A_ROUNDS_TO_ONE`` (may round to 1.0 near the top)."""
    # x_m of the undamped loaded contact solves (x_m^{5/2} - 1)/2 = A x_m
    # (Eq. 8 scaled); then xi = A x_m / (1/2 + A x_m) (Eq. 10).
    # (1 + 2A)^(2/3) bounds the root from above; Newton on a convex function
    # started right of its root converges monotonically.
    xm = (1.0 + 2.0 * A) ** (2.0 / 3.0)
    for _ in range(XI_NEWTON_STEPS):
        xm = _xi_newton_step(A, xm)
    return A * xm / (0.5 + A * xm)


xi_newton_step_kernel = njit(cache=True, error_model="numpy", inline="always")(_xi_newton_step)


def _xi_of_load_float(A):
    """``_xi_of_load`` of one float, the same bits, stopping where a step returns its own input.

    Every later step would return that input again (a fixed point of a deterministic step), so
    the early stop changes no bit; a 1-ulp cycle runs all ``XI_NEWTON_STEPS`` as before.
    """
    xm = (1.0 + 2.0 * A) ** (2.0 / 3.0)
    for _ in range(XI_NEWTON_STEPS):
        nxt = xi_newton_step_kernel(A, xm)
        if nxt == xm:
            break
        xm = nxt
    return A * xm / (0.5 + A * xm)


# The same iteration compiled, for the scalar fast path of ``influence_factor`` and the batched
# front door (same libm pow, same numbers as ``_xi_of_load``; tests/engine/test_scaling.py).
xi_of_load_kernel = njit(cache=True, error_model="numpy")(_xi_of_load_float)
# Called from Python: runs as the kernel's Python twin until compiled code is at hand.
xi_of_load_scalar = FirstCall(xi_of_load_kernel)


def _plain_xi(m_e, k, v0, a):
    """Eq. 10 of positive finite floats by the direct product, or NaN where the full path must decide."""
    v2 = v0 * v0  # numpy squares the same way; a float ** would raise on overflow
    if not 0.0 < v2 < math.inf:
        return math.nan
    A = a * (1.25 * m_e * v2 / k) ** 0.4 / v2
    log_A = math.log(a) + 0.4 * (math.log(1.25) + math.log(m_e) - math.log(k)) - 1.2 * math.log(v0)
    if not (0.0 < A < A_ROUNDS_TO_ONE and abs(math.log(A) - log_A) <= 1e-9 * max(1.0, abs(log_A))):
        return math.nan  # under- or overflow, or a load at the top: the full path's logarithms decide
    xi = xi_of_load_kernel(A)
    return xi if xi < 1.0 else math.nan


plain_xi_kernel = njit(cache=True, error_model="numpy")(_plain_xi)
plain_xi_scalar = FirstCall(plain_xi_kernel)


@njit(cache=True, error_model="numpy")
def _plain_xi_rows(m_e, k, v0, a, out):
    # The scalar fast path's arithmetic (libm's pow and log) over arrays: numpy's SIMD pow may
    # differ from libm in the last bit, so an array's xi would not be its scalars' xi.
    for i in range(out.size):
        out[i] = plain_xi_kernel(m_e[i], k[i], v0[i], a[i])


def _influence_factor_plain(m_e, k, v0, a):
    """``influence_factor`` of plain floats, or None where the full path must decide (or raise)."""
    if not (
        type(m_e) in PLAIN_FLOATS
        and type(k) in PLAIN_FLOATS
        and type(v0) in PLAIN_FLOATS
        and type(a) in PLAIN_FLOATS
        and 0.0 < m_e < math.inf
        and 0.0 < k < math.inf
        and 0.0 < v0 < math.inf
        and 0.0 < a < math.inf
    ):
        return None
    xi = plain_xi_scalar(float(m_e), float(k), float(v0), float(a))
    return None if xi != xi else xi


def _first_rounding_to_one(value, xi):
    """The first entry of ``value`` where ``xi`` rounded to 1.0, or None."""
    bad = np.atleast_1d(xi >= 1.0)
    return float(np.atleast_1d(np.broadcast_to(value, np.shape(xi)))[bad][0]) if bad.any() else None


def _xi_rounds_to_one(what):
    return ValueError(
        f"{what} gives an influence factor within 1.1e-16 of 1: xi rounds to 1.0, outside the valid "
        "range [0.0, 1.0); the load is too large for the approach speed"
    )


def influence_from_scaled_load(A):
    """Invert ``A(xi)`` (monotone increasing) for ``A >= 0``; raise where ``xi`` rounds to 1."""
    A = check_range("A", A, 0.0, np.inf, hi_open=True)
    xi = _xi_of_load(np.minimum(A, A_ROUNDS_TO_ONE))
    if np.any(xi >= 1.0):
        raise _xi_rounds_to_one(f"A = {_first_rounding_to_one(A, xi)!r}")
    return xi


@renamed_keywords(**OLD_NAMES, a="accel")
def influence_factor(
    mass: RealLike, stiffness: RealLike, approach_speed: RealLike, accel: RealLike
) -> FloatOrArray:
    """Influence factor ``xi`` of a constant relative acceleration ``a`` (Eq. 10).

    The scaled load ``A = a delta_star / v0^2`` is also formed from logarithms, which
    take over where the direct product under- or overflows (extreme speeds); a load
    so large that ``xi`` rounds to 1 raises a ``ValueError`` naming ``accel`` and ``approach_speed``.

    Parameters
    ----------
    mass : float or array
        Equivalent mass m_e, kg (> 0).
    stiffness : float or array
        Hertz stiffness k, N/m^1.5 (> 0).
    approach_speed : float or array
        Approach speed v0, m/s (> 0).
    accel : float or array
        Relative acceleration a from the external forces, m/s^2 (>= 0).

    Returns
    -------
    xi : float or ndarray
        In [0, 1).

    Notes
    -----
    The old keyword names ``m_e``, ``k``, ``v0``, ``a`` still work, with a DeprecationWarning.
    """
    xi = _influence_factor_plain(mass, stiffness, approach_speed, accel)
    if xi is not None:
        return xi
    a = check_range("accel", accel, 0.0, np.inf, hi_open=True)
    m_e, k, v0 = (
        check_positive(n, val)
        for n, val in zip(OLD_NAMES.values(), (mass, stiffness, approach_speed), strict=True)
    )
    # Where the scalar path would answer, the same arithmetic element by element (same bits).
    arrays = [np.ascontiguousarray(x, dtype=float).ravel() for x in np.broadcast_arrays(m_e, k, v0, a)]
    plain = np.empty(arrays[0].size)
    _plain_xi_rows(*arrays, plain)
    plain = plain.reshape(np.broadcast_shapes(*(np.shape(x) for x in (m_e, k, v0, a))))
    with np.errstate(all="ignore"):
        A = a * length_scale(m_e, k, v0) / v0**2
        # ln A = ln a + ln delta_star - 2 ln v0, with delta_star = (5 m_e v0^2 / (4 k))^(2/5)
        log_A = np.log(a) + 0.4 * (np.log(1.25) + np.log(m_e) - np.log(k)) - 1.2 * np.log(v0)
        # The direct product where it neither under- nor overflowed (bit-identical to before).
        direct = np.isfinite(A) & (np.abs(np.log(A) - log_A) <= 1e-9 * np.maximum(1.0, abs(log_A)))
        direct |= a == 0.0
        A = np.where(direct, A, np.exp(np.minimum(log_A, np.log(A_ROUNDS_TO_ONE))))
    xi = _xi_of_load(np.minimum(A, A_ROUNDS_TO_ONE))
    xi = np.where(plain == plain, plain, xi)
    if np.any(xi >= 1.0):
        a1, v1, m1, k1 = (_first_rounding_to_one(v, xi) for v in (a, v0, m_e, k))
        raise _xi_rounds_to_one(
            f"accel = {a1!r} m/s^2 at approach_speed = {v1!r} m/s "
            f"(mass = {m1!r} kg, stiffness = {k1!r} N/m^1.5)"
        )
    return _scalar_or_array(xi)


@renamed_keywords(**OLD_NAMES)
def load_for(xi: RealLike, mass: RealLike, stiffness: RealLike, approach_speed: RealLike) -> FloatOrArray:
    """Relative acceleration ``accel`` (m/s^2) that gives influence factor ``xi``."""
    A = scaled_load(xi)
    v0a = check_positive("approach_speed", approach_speed)
    return _scalar_or_array(A * v0a**2 / length_scale(mass, stiffness, approach_speed))


def _scalar_or_array(arr):
    arr = np.asarray(arr)
    return float(arr) if arr.ndim == 0 else arr
