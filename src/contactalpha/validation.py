"""Input checks shared by the public API: every message names the value and the valid range."""

import numpy as np


def _describe(bad):
    flat = np.atleast_1d(bad).ravel()
    shown = ", ".join(repr(float(b)) for b in flat[:3])
    more = f" (and {flat.size - 3} more)" if flat.size > 3 else ""
    return shown + more


def check_range(name, value, lo, hi, *, lo_open=False, hi_open=False):
    """Return ``value`` as a float array, or raise ``ValueError`` naming the bad entries.

    NaN and infinities are always rejected.
    """
    arr = np.asarray(value, dtype=float)
    ok = np.isfinite(arr)
    ok &= (arr > lo) if lo_open else (arr >= lo)
    ok &= (arr < hi) if hi_open else (arr <= hi)
    if not np.all(ok):
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise ValueError(f"{name} = {_describe(arr[~ok])} is outside the valid range {left}{lo}, {hi}{right}")
    return arr


def check_positive(name, value):
    """Return ``value`` as a float array, or raise unless it is finite and > 0."""
    return check_range(name, value, 0.0, np.inf, lo_open=True, hi_open=True)


def check_eps(eps):
    """Restitution coefficient: 0 <= eps <= 1."""
    return check_range("eps", eps, 0.0, 1.0)


def check_xi(xi):
    """Influence factor of the external load: 0 <= xi < 1."""
    return check_range("xi", xi, 0.0, 1.0, hi_open=True)


def check_alpha(alpha):
    """Hysteresis damping factor: alpha >= 0 and finite."""
    return check_range("alpha", alpha, 0.0, np.inf, hi_open=True)


def check_tolerances(rtol, atol):
    """Relative tolerance in (0, 0.1], absolute tolerance in (0, 1]."""
    check_range("rtol", rtol, 0.0, 0.1, lo_open=True)
    check_range("atol", atol, 0.0, 1.0, lo_open=True)
    if rtol < 1e-15:
        raise ValueError(f"rtol = {rtol!r} is below the floor 1e-15 set by double precision")
    return float(rtol), float(atol)
