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
)

from .firstcall import FirstCall
from .threads import flat_owned

# The public API's names of the scene's quantities (the front door's), in the order of the arguments.
SCENE_NAMES = ("mass", "stiffness", "approach_speed")

# ln(5/4), the constant of delta_star's logarithm.
LOG_5_4 = math.log(1.25)
# Beyond this logarithm exp overflows (ln of the largest double is 709.78): the value is inf.
LOG_HUGE = 709.0


def _scales(m_e, k, v0):
    """``(delta_star, t_star)`` of one contact: the direct products, or their logarithms' values.

    The direct forms are the ones used before (bit for bit); where they under- or overflow at
    extreme valid speeds (or lose digits in a subnormal), ``exp`` of the logarithm takes over,
    and returns 0.0 or inf only where the scale itself is beyond the doubles.
    """
    # A direct value counts where it agrees with its logarithm (no under- or overflow on the way).
    log_d = 0.4 * (LOG_5_4 + math.log(m_e) - math.log(k)) + 0.8 * math.log(v0)
    d = (1.25 * m_e * (v0 * v0) / k) ** 0.4
    if not (0.0 < d < math.inf and abs(math.log(d) - log_d) <= 1e-9 * max(1.0, abs(log_d))):
        d = math.exp(log_d) if log_d < LOG_HUGE else math.inf
    log_t = log_d - math.log(v0)
    t = d / v0
    if not (0.0 < t < math.inf and abs(math.log(t) - log_t) <= 1e-9 * max(1.0, abs(log_t))):
        t = math.exp(log_t) if log_t < LOG_HUGE else math.inf
    return d, t


# The same arithmetic compiled, for arrays: numpy's own SIMD power can differ from libm's pow in the
# last bit, and the scalar path (Python floats, libm) must give the array path's numbers.
_scales_jit = njit(cache=True, error_model="numpy")(_scales)
# For other modules' row kernels (the batched front door's load factor).
scales_kernel = _scales_jit


@njit(cache=True, error_model="numpy")
def _scales_rows(m_e, k, v0, d, t):
    for i in range(m_e.size):
        d[i], t[i] = _scales_jit(m_e[i], k[i], v0[i])


# Its first calls on a cold numba cache run as its Python twin (``firstcall``).
_scales_rows_first = FirstCall(_scales_rows)


def _scales_checked(m_e, k, v0):
    """``(delta_star, t_star)`` as floats (plain input) or arrays; raise where one is beyond the doubles."""
    plain = (
        type(m_e) in PLAIN_FLOATS
        and type(k) in PLAIN_FLOATS
        and type(v0) in PLAIN_FLOATS
        and 0.0 < m_e < math.inf
        and 0.0 < k < math.inf
        and 0.0 < v0 < math.inf
    )
    if plain:
        d, t = _scales(m_e, k, v0)
    else:
        m_e, k, v0 = (check_positive(n, val) for n, val in zip(SCENE_NAMES, (m_e, k, v0), strict=True))
        m_e, k, v0 = np.broadcast_arrays(m_e, k, v0)
        d, t = np.empty(m_e.shape), np.empty(m_e.shape)
        flat = [flat_owned(a) for a in (m_e, k, v0)]
        _scales_rows_first(*flat, d.reshape(-1), t.reshape(-1))
    bad = ~(
        (np.asarray(d) > 0.0) & (np.asarray(d) < np.inf) & (np.asarray(t) > 0.0) & (np.asarray(t) < np.inf)
    )
    if np.any(bad):
        m1, k1, v1 = (
            float(np.atleast_1d(np.broadcast_to(x, np.shape(d)))[np.atleast_1d(bad)][0]) for x in (m_e, k, v0)
        )
        raise ValueError(
            f"mass = {m1!r} kg, stiffness = {k1!r} N/m^1.5, approach_speed = {v1!r} m/s give a length or "
            "time scale "
            "beyond the range of double precision (delta_star = (5 m_e v0^2 / (4 k))^(2/5), "
            "t_star = delta_star / v0); valid: a scene whose scales lie between 1e-300 and 1e300"
        )
    return d, t


def length_scale(mass: RealLike, stiffness: RealLike, approach_speed: RealLike) -> FloatOrArray:
    """``delta_star`` in metres, for mass kg, stiffness N/m^1.5 and approach speed m/s.

    Formed from logarithms where the direct product under- or overflows; raises ``ValueError``
    naming the inputs where the scale itself is beyond the doubles.
    """
    return _scales_checked(mass, stiffness, approach_speed)[0]


def time_scale(mass: RealLike, stiffness: RealLike, approach_speed: RealLike) -> FloatOrArray:
    """``t_star = delta_star / approach_speed`` in seconds (from logarithms where it would not fit)."""
    return _scales_checked(mass, stiffness, approach_speed)[1]


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
    """``_xi_of_load`` of one float, the same bits, stopping where the rest of the steps are known.

    The step is a deterministic function of ``xm``: where it returns its own input every later
    step would too (a fixed point), and where it returns the value of two steps before, the
    iteration alternates between two neighbours for good (a 1-ulp cycle, about one load in ten),
    so the fixed count of steps ends on the one of the count's parity.  Either stop changes no bit.
    """
    xm = (1.0 + 2.0 * A) ** (2.0 / 3.0)
    before = math.nan
    for step in range(XI_NEWTON_STEPS):
        nxt = xi_newton_step_kernel(A, xm)
        if nxt == xm:
            break
        if nxt == before:  # x_{step+1} = x_{step-1}: the last step, XI_NEWTON_STEPS, lands on
            if (XI_NEWTON_STEPS - step) % 2 == 1:  # x_{step-1} where XI_NEWTON_STEPS - step is odd
                xm = nxt
            break
        before, xm = xm, nxt
    return A * xm / (0.5 + A * xm)


# The same iteration compiled, for the scalar fast path of ``influence_factor`` and the batched
# front door (same libm pow, same numbers as ``_xi_of_load``; tests/engine/test_scaling.py).
xi_of_load_kernel = njit(cache=True, error_model="numpy")(_xi_of_load_float)
# Called from Python: runs as the kernel's Python twin until compiled code is at hand.
xi_of_load_scalar = FirstCall(xi_of_load_kernel)


@njit(cache=True, error_model="numpy")
def _xi_of_load_rows(A, out):
    for i in range(A.size):
        out[i] = xi_of_load_kernel(A[i])


def _xi_of_load_many(A):
    """``_xi_of_load`` of an array with libm's pow, as the scalar path (numpy's SIMD pow may differ)."""
    A = np.asarray(A, dtype=float)
    out = np.empty(A.shape)
    _xi_of_load_rows(flat_owned(A), out.reshape(-1))
    return out


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
    v2 = v0 * v0  # numpy squares the same way; a float ** would raise on overflow
    if not 0.0 < v2 < math.inf:
        return None
    A = a * (1.25 * m_e * v2 / k) ** 0.4 / v2
    log_A = math.log(a) + 0.4 * (math.log(1.25) + math.log(m_e) - math.log(k)) - 1.2 * math.log(v0)
    if not (0.0 < A < A_ROUNDS_TO_ONE and abs(math.log(A) - log_A) <= 1e-9 * max(1.0, abs(log_A))):
        return None  # under- or overflow, or a load at the top: the full path's logarithms decide
    xi = xi_of_load_scalar(A)
    return xi if xi < 1.0 else None


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
    """
    xi = _influence_factor_plain(mass, stiffness, approach_speed, accel)
    if xi is not None:
        return xi
    a = check_range("accel", accel, 0.0, np.inf, hi_open=True)
    m_e, k, v0 = (
        check_positive(n, val) for n, val in zip(SCENE_NAMES, (mass, stiffness, approach_speed), strict=True)
    )
    return _influence_factor_arrays(m_e, k, v0, a)


def influence_factor_unchecked(mass, stiffness, approach_speed, accel):
    """``influence_factor`` of inputs already checked (the front doors'): the same numbers, no checks."""
    xi = _influence_factor_plain(mass, stiffness, approach_speed, accel)
    if xi is not None:
        return xi
    scene = (mass, stiffness, approach_speed, accel)
    return _influence_factor_arrays(*(np.asarray(x, dtype=float) for x in scene))


def _influence_factor_arrays(m_e, k, v0, a):
    """``influence_factor``'s array path (also plain floats at a zero load or past the plain path's reach)."""
    with np.errstate(all="ignore"):
        m_b, k_b, v_b = np.broadcast_arrays(m_e, k, v0)
        d, t = np.empty(m_b.shape), np.empty(m_b.shape)
        _scales_rows_first(flat_owned(m_b), flat_owned(k_b), flat_owned(v_b), d.reshape(-1), t.reshape(-1))
        A = a * d / v0**2
        # ln A = ln a + ln delta_star - 2 ln v0, with delta_star = (5 m_e v0^2 / (4 k))^(2/5)
        log_A = np.log(a) + 0.4 * (np.log(1.25) + np.log(m_e) - np.log(k)) - 1.2 * np.log(v0)
        # The direct product where it neither under- nor overflowed (bit-identical to before).
        direct = np.isfinite(A) & (np.abs(np.log(A) - log_A) <= 1e-9 * np.maximum(1.0, abs(log_A)))
        direct |= a == 0.0
        A = np.where(direct, A, np.exp(np.minimum(log_A, np.log(A_ROUNDS_TO_ONE))))
    xi = _xi_of_load_many(np.minimum(A, A_ROUNDS_TO_ONE))
    if np.any(xi >= 1.0):
        a1, v1, m1, k1 = (_first_rounding_to_one(v, xi) for v in (a, v0, m_e, k))
        raise _xi_rounds_to_one(
            f"accel = {a1!r} m/s^2 at approach_speed = {v1!r} m/s "
            f"(mass = {m1!r} kg, stiffness = {k1!r} N/m^1.5)"
        )
    return _scalar_or_array(xi)


def load_for(xi: RealLike, mass: RealLike, stiffness: RealLike, approach_speed: RealLike) -> FloatOrArray:
    """Relative acceleration ``accel`` (m/s^2) that gives influence factor ``xi``.

    ``a = A(xi) v0^2 / delta_star``, from logarithms where the product under- or overflows;
    raises ``ValueError`` naming the inputs where ``a`` itself is beyond the doubles.
    """
    A = scaled_load(xi)
    m_e, k, v0 = mass, stiffness, approach_speed
    v0a = check_positive("approach_speed", v0)
    d = length_scale(m_e, k, v0)
    with np.errstate(all="ignore"):
        a = A * v0a**2 / d
        log_a = np.log(A) + 2.0 * np.log(v0a) - np.log(d)
        good = (A == 0.0) | (
            (a > 0.0) & (a < np.inf) & (np.abs(np.log(a) - log_a) <= 1e-9 * np.maximum(1.0, np.abs(log_a)))
        )
        a = np.where(good, a, np.exp(np.minimum(log_a, 710.0)))
    if np.any((A > 0.0) & ~((a > 0.0) & (a < np.inf))):
        raise ValueError(
            f"xi = {xi!r}, mass = {m_e!r}, stiffness = {k!r}, approach_speed = {v0!r} need an "
            "acceleration beyond the range of double precision; valid: a scene whose load lies "
            "between 1e-300 and 1e300 m/s^2"
        )
    return _scalar_or_array(a)


def _scalar_or_array(arr):
    arr = np.asarray(arr)
    return float(arr) if arr.ndim == 0 else arr
