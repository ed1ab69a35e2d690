"""The exact relation between alpha and Stronge's epsilon when there is no load (xi = 0).

With ``A = 0`` the phase-plane equation of the scaled impact separates and
gives (Carvalho & Martins 2019; docs/science.md, "The exact unloaded relation")

    ln((1 + alpha) / (1 - alpha eps)) = alpha (1 + eps).

``alpha = 0`` is always a (trivial) root, so ``alpha_exact`` solves
``G(alpha) = H(alpha) / alpha^2 = 0`` with ``H`` the difference of the two
sides.  For ``alpha <= SERIES_LIMIT`` ``G`` is summed as its power series
``sum_{n>=2} ((-1)^{n+1} + eps^n) / n * alpha^(n-2)``, which avoids the
cancellation of the closed form near ``eps -> 1``.
"""

import numpy as np
from numba import njit, vectorize

from contactalpha.validation import FloatOrArray, RealLike

# Below this alpha the series form of G is used (terms shrink like alpha^n).
SERIES_LIMIT = 0.5
# Terms of the series; 0.5^60 is far below double precision.
SERIES_TERMS = 64
# Newton iterations before giving up (bisection keeps each one safe).
MAX_ITER = 200


@njit(cache=True, error_model="numpy")
def _g_and_slopes(alpha, eps, limit=SERIES_LIMIT, terms=SERIES_TERMS):
    """``G(alpha, eps) = H / alpha^2`` and its partial derivatives ``dG/dalpha``, ``dG/deps``.

    The series (``terms`` terms) is used for ``alpha <= limit``, the closed form above.
    """
    if alpha <= limit:
        g = 0.0
        ga = 0.0
        ge = 0.0
        apow = 1.0  # alpha^(n-2)
        epow = eps  # eps^(n-1) on entry to each term
        sign = -1.0  # (-1)^(n+1) for n = 2
        for n in range(2, terms):
            ge += epow * apow
            epow *= eps
            c = (sign + epow) / n
            g += c * apow
            if n >= 3:
                ga += (n - 2) * c * apow / alpha
            apow *= alpha
            sign = -sign
        return g, ga, ge
    h = np.log1p(alpha) - np.log1p(-alpha * eps) - alpha * (1.0 + eps)
    dh = 1.0 / (1.0 + alpha) + eps / (1.0 - alpha * eps) - (1.0 + eps)
    a2 = alpha * alpha
    return h / a2, dh / a2 - 2.0 * h / (a2 * alpha), (alpha / (1.0 - alpha * eps) - alpha) / a2


@njit(cache=True, error_model="numpy")
def _safeguarded_newton(g, slope, x, lo, hi):
    """One step of Newton's method kept inside the bracket ``(lo, hi)``."""
    new = x - g / slope if slope != 0.0 else np.inf
    if not (lo < new < hi):
        new = 0.5 * (lo + hi) if np.isfinite(hi) else 2.0 * x
    return new


@njit(cache=True, error_model="numpy")
def alpha_exact_scalar(eps):
    """Damping factor that gives restitution ``eps`` at ``xi = 0`` (0 < eps <= 1)."""
    if eps >= 1.0:
        return 0.0
    lo = 0.0
    hi = 1.0 / eps
    # Start near the asymptotes: 3(1 - eps)/2 near eps = 1, 1/eps near 0.
    alpha = min(1.5 * (1.0 - eps) / eps, 0.5 * hi)
    for _ in range(MAX_ITER):
        g, ga, _ = _g_and_slopes(alpha, eps)
        if g < 0.0:
            lo = alpha
        else:
            hi = alpha
        new = _safeguarded_newton(g, ga, alpha, lo, hi)
        if abs(new - alpha) <= 2e-16 * alpha or new == lo or new == hi:
            return new
        alpha = new
    return alpha


@njit(cache=True, error_model="numpy")
def restitution_exact_scalar(alpha):
    """Stronge's epsilon at ``xi = 0`` for damping ``alpha >= 0`` (inverse of ``alpha_exact``)."""
    if alpha == 0.0:
        return 1.0
    lo = 0.0
    hi = min(1.0, 1.0 / alpha)
    eps = 0.5 * (lo + hi)
    for _ in range(MAX_ITER):
        g, _, ge = _g_and_slopes(alpha, eps)  # G increases with eps
        if g < 0.0:
            lo = eps
        else:
            hi = eps
        new = _safeguarded_newton(g, ge, eps, lo, hi)
        if abs(new - eps) <= 2e-16 * eps or new == lo or new == hi:
            return new
        eps = new
    return eps


@njit(cache=True, error_model="numpy")
def max_compression_exact(alpha):
    """Scaled maximum compression at ``xi = 0``: ``x_m^{5/2} = 2 (alpha - ln(1 + alpha)) / alpha^2``."""
    if alpha <= SERIES_LIMIT:
        # (alpha - ln(1+alpha)) / alpha^2 = sum_{n>=2} (-1)^n alpha^(n-2) / n
        acc = 0.0
        apow = 1.0
        sign = 1.0
        for n in range(2, SERIES_TERMS):
            acc += sign * apow / n
            apow *= alpha
            sign = -sign
    else:
        acc = (alpha - np.log1p(alpha)) / (alpha * alpha)
    return (2.0 * acc) ** 0.4


@vectorize(cache=True)  # typed on first call: an explicit signature compiles at import (~0.5 s)
def _alpha_exact_ufunc(eps):
    return alpha_exact_scalar(eps)


@vectorize(cache=True)  # typed on first call: an explicit signature compiles at import (~0.5 s)
def _restitution_exact_ufunc(alpha):
    return restitution_exact_scalar(alpha)


def alpha_exact(eps: RealLike) -> FloatOrArray:
    """Exact damping factor at ``xi = 0`` for restitution ``eps`` in (0, 1].

    ``eps = 0`` cannot be reached without a load (alpha -> infinity) and raises.
    """
    from contactalpha.validation import check_range

    e = check_range("eps", eps, 0.0, 1.0, lo_open=True)
    return _alpha_exact_ufunc(e)[()]


def restitution_exact(alpha: RealLike) -> FloatOrArray:
    """Exact Stronge restitution at ``xi = 0`` for damping ``alpha >= 0``."""
    from contactalpha.validation import check_alpha

    return _restitution_exact_ufunc(check_alpha(alpha))[()]
