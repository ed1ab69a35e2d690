"""The separation / non-separation boundary of the (eps, xi) plane.

For a load ``xi > 0`` there is one damping ``alpha_b(xi)`` at which the
impact ends exactly at ``x = 0`` with ``v = 0``: lighter damping separates,
heavier damping does not.  On it Stronge's coefficient is
``eps_b = sqrt(A x_m / (1/2 + A x_m))`` (the restitution identity of docs/science.md with
``v_e = x_e = 0``).

``alpha(eps, xi)`` is continuous across the boundary but not smooth: near it
the two end states differ by terms of order ``|alpha - alpha_b|^{5/2}`` (the
Hertz force near ``x = 0``), which is why the exact table (``table.py``) puts
the boundary on a grid line instead of interpolating across it.
"""

import numpy as np
from numba import njit

from .codes import (
    BND_ALPHA,
    BND_EPS,
    BND_STATUS,
    N_BND_OUT,
    N_REC,
    NO_BRACKET,
    OK,
    OUT_STATE,
    OUT_STATUS,
    OUT_X_MAX,
    SEPARATION,
)
from .kernel import impact_kernel
from .threads import run_rows

# The separation boundary's exact limits (docs/science.md), on which its compact fit
# (``scene.threshold``) and the closed form's boundary coordinate (``models.closed_form``) are
# built: A_b ~ c eps^(3/2) as eps -> 0 (the boundary's x_m -> const, eps_b^2 ~ 2 A x_m) and
# A_b ~ 2^(-3/5) / 2 (1 - eps)^(-3/5) as eps -> 1 (Eq. 10).
LIMIT_EPS_POWER = 1.5
LIMIT_ONE_MINUS_EPS_POWER = 0.6
LOG_LIMIT_AT_ONE = -1.6 * float(np.log(2.0))  # ln(2^(-3/5) / 2)

# Bisection stops when the bracket is this narrow, relative.
BOUNDARY_RTOL = 1e-14
# Upper end of the search in alpha; beyond it the boundary is reported missing.
ALPHA_SEARCH_MAX = 1e8


@njit(cache=True, error_model="numpy")
def boundary_kernel(A, rtol, atol, max_steps):
    """Return ``(alpha_b, eps_b, status)`` for scaled load ``A > 0`` by bisection on the end state."""
    rec = np.empty((0, N_REC))
    lo = 0.0  # separates
    hi = 1.0
    while True:
        res, _ = impact_kernel(hi, A, rtol, atol, max_steps, rec, np.inf)
        if res[OUT_STATUS] != OK:
            return np.nan, np.nan, int(res[OUT_STATUS])
        if res[OUT_STATE] != SEPARATION:
            break
        lo = hi
        hi *= 4.0
        if hi > ALPHA_SEARCH_MAX:
            return np.nan, np.nan, NO_BRACKET
    x_m = np.nan
    while hi - lo > BOUNDARY_RTOL * hi:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        res, _ = impact_kernel(mid, A, rtol, atol, max_steps, rec, np.inf)
        if res[OUT_STATUS] != OK:
            return np.nan, np.nan, int(res[OUT_STATUS])
        if res[OUT_STATE] == SEPARATION:
            lo = mid
            x_m = res[OUT_X_MAX]
        else:
            hi = mid
    if not np.isfinite(x_m):
        res, _ = impact_kernel(lo, A, rtol, atol, max_steps, rec, np.inf)
        x_m = res[OUT_X_MAX]
    return lo, np.sqrt(A * x_m / (0.5 + A * x_m)), OK


@njit(cache=True, nogil=True, error_model="numpy")
def boundary_rows(A, rtol, atol, max_steps, out, start, stop):
    """``boundary_kernel`` over rows ``start .. stop - 1`` of an array of loads, into ``out``."""
    for i in range(start, stop):
        a, e, s = boundary_kernel(A[i], rtol, atol, max_steps)
        out[i, BND_ALPHA] = a
        out[i, BND_EPS] = e
        out[i, BND_STATUS] = s


def boundary_many(A, rtol, atol, max_steps, threads=None):
    """``boundary_kernel`` over an array of loads; returns shape (n, N_BND_OUT)."""
    out = np.empty((A.size, N_BND_OUT))
    run_rows(boundary_rows, A.size, A, rtol, atol, max_steps, out, threads=threads)
    return out


def separation_boundary(xi, *, rtol=1e-12, atol=1e-14, max_steps=2_000_000):
    """Damping ``alpha_b`` and restitution ``eps_b`` on the separation boundary at load ``xi``.

    Parameters
    ----------
    xi : array_like
        Influence factor, 0 < xi < 1.

    Returns
    -------
    alpha_b, eps_b : ndarray
        NaN where the search failed (see the status codes of ``codes.STATUS``).
    status : ndarray of int
    """
    from contactalpha.validation import check_max_steps, check_range, check_tolerances

    from .scaling import scaled_load

    xi = check_range("xi", xi, 0.0, 1.0, lo_open=True, hi_open=True)
    A = np.ascontiguousarray(np.atleast_1d(scaled_load(xi)).ravel())
    rtol, atol = check_tolerances(rtol, atol)
    out = boundary_many(A, rtol, atol, check_max_steps(max_steps))
    shape = np.shape(xi)
    return (
        out[:, BND_ALPHA].reshape(shape),
        out[:, BND_EPS].reshape(shape),
        out[:, BND_STATUS].astype(int).reshape(shape),
    )
