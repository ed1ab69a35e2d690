"""Physical units <-> the two dimensionless numbers (paper Eqs. 1, 8, 10, 11).

Lengths are scaled by ``delta_star = (5 m_e v0^2 / (4 k))^(2/5)``, the maximum
compression of the undamped, unloaded contact, and times by
``t_star = delta_star / v0``.  The scaled load is ``A = a delta_star / v0^2``.
For the undamped loaded contact the maximum compression is
``x_m = (1 - xi)^(-2/5)`` (Eq. 11), and Eq. 10 then gives
``A = xi (1 - xi)^(-3/5) / 2``.
"""

import numpy as np

from contactalpha.validation import check_positive, check_range, check_xi


def length_scale(m_e, k, v0):
    """``delta_star`` in metres, for mass kg, stiffness N/m^1.5 and approach speed m/s."""
    m_e, k, v0 = (check_positive(n, val) for n, val in (("m_e", m_e), ("k", k), ("v0", v0)))
    return (1.25 * m_e * v0**2 / k) ** 0.4


def time_scale(m_e, k, v0):
    """``t_star = delta_star / v0`` in seconds."""
    return length_scale(m_e, k, v0) / np.asarray(v0, dtype=float)


def scaled_load(xi):
    """Scaled load ``A(xi) = xi (1 - xi)^(-3/5) / 2``; shape follows ``xi``."""
    xi = check_xi(xi)
    return 0.5 * xi * (1.0 - xi) ** -0.6


def influence_from_scaled_load(A):
    """Invert ``A(xi)`` (monotone increasing) for ``A >= 0``."""
    A = check_range("A", A, 0.0, np.inf, hi_open=True)
    # x_m of the undamped loaded contact solves (x_m^{5/2} - 1)/2 = A x_m
    # (Eq. 8 scaled); then xi = A x_m / (1/2 + A x_m) (Eq. 10).
    # (1 + 2A)^(2/3) bounds the root from above; Newton on a convex function
    # started right of its root converges monotonically.
    xm = (1.0 + 2.0 * A) ** (2.0 / 3.0)
    for _ in range(60):
        g = 0.5 * (xm**2.5 - 1.0) - A * xm
        dg = 1.25 * xm**1.5 - A
        xm = xm - g / dg
    return A * xm / (0.5 + A * xm)


def influence_factor(m_e, k, v0, a):
    """Influence factor ``xi`` of a constant relative acceleration ``a`` (Eq. 10).

    Parameters
    ----------
    m_e : float or array
        Equivalent mass, kg (> 0).
    k : float or array
        Hertz stiffness, N/m^1.5 (> 0).
    v0 : float or array
        Approach speed, m/s (> 0).
    a : float or array
        Relative acceleration from the external forces, m/s^2 (>= 0).

    Returns
    -------
    xi : float or ndarray
        In [0, 1).
    """
    a = check_range("a", a, 0.0, np.inf, hi_open=True)
    A = a * length_scale(m_e, k, v0) / np.asarray(v0, dtype=float) ** 2
    return _scalar_or_array(influence_from_scaled_load(A))


def load_for(xi, m_e, k, v0):
    """Relative acceleration ``a`` (m/s^2) that gives influence factor ``xi``."""
    A = scaled_load(xi)
    v0a = check_positive("v0", v0)
    return _scalar_or_array(A * v0a**2 / length_scale(m_e, k, v0))


def _scalar_or_array(arr):
    arr = np.asarray(arr)
    return float(arr) if arr.ndim == 0 else arr
