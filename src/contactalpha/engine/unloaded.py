"""The exact unloaded alpha (xi = 0) without iteration: one exp or one log and a short polynomial.

``engine.exact`` solves ln((1 + a) / (1 - a eps)) = a (1 + eps) by a safeguarded Newton method.
Formulas that carry that root as a factor (``models.closed_form``) need it at the cost of a few
flops, so here it is written explicitly, exact to rounding:

- ``eps < FIXED_POINT_LIMIT``: ``1 - a eps`` is exponentially small and one fixed-point step of
  ``a = (1 - (1 + a) exp(-a (1 + eps))) / eps`` from ``a = 1/eps`` gives
  ``a = x (1 - (1 + x) exp(-(1 + x)))``, ``x = 1/eps``; its error is below 1e-18 relative there
  (the step contracts by ~(1 + x)^2 exp(-(1 + x)), below 1e-8, on an error below 1e-10).
- otherwise ``a = (1 - eps) / eps * g(eps)``, where ``g = a eps / (1 - eps)`` is smooth and
  bounded (1 at eps -> 0, 3/2 at eps = 1; analytic through eps = 1), evaluated as a polynomial
  of degree ``len(UNLOADED_POLY[0]) - 1`` on each of ``len(UNLOADED_POLY)`` equal pieces of
  ``ln eps`` over ``[ln FIXED_POINT_LIMIT, 0]``.  The factor ``1 - eps`` is exact in floating
  point, so alpha keeps its relative accuracy as eps -> 1 (where the Newton solver's series loses
  digits to ``eps^n - 1``).

``UNLOADED_POLY`` comes from ``unloaded_polynomial()`` (Chebyshev interpolation of ``g`` computed
to 50 digits with mpmath, written in monomial form of the piece's local coordinate
``t`` in [-1, 1]).  Measured against a 50-digit root at 2,300 points over
``FIXED_POINT_LIMIT <= eps < 1`` (``tests/engine/test_unloaded.py``): max relative error 6.7e-16.
"""

import numpy as np
from numba import njit

# Below this eps the explicit fixed-point step is exact to rounding (module docstring).
FIXED_POINT_LIMIT = 0.04
# Above this x = 1/eps the fixed-point correction (1 + x) exp(-(1 + x)) is below 1e-430: a = x.
PURE_INVERSE_X = 1e3
# Pieces and degree of the polynomial of g (8 x 13: max error 6.7e-16; 8 x 12: 1.1e-15, 6 x 13: 2e-15).
POLY_PIECES = 8
POLY_DEGREE = 13
# Digits of the mpmath root that ``unloaded_polynomial`` interpolates.
REFERENCE_DIGITS = 50

# Monomial coefficients (ascending powers of t) of g on each piece, from unloaded_polynomial().
UNLOADED_POLY = np.array(
    (
        (
            1.051429376679864,
            0.010878624447476368,
            0.0012067602081642563,
            9.70976593778281e-05,
            6.635272717505101e-06,
            3.955779904520531e-07,
            8.239631984173896e-09,
            -5.212542866943551e-09,
            -1.6681638296134416e-09,
            -2.9049684931297703e-10,
            -1.8280369569617405e-11,
            5.237925357770989e-12,
            1.46365151316295e-12,
            5.841178057118193e-14,
        ),
        (
            1.0789085531851579,
            0.017111684457549712,
            0.001974425365449165,
            0.0001599611178388755,
            6.748928236127973e-06,
            -1.1239696041562958e-06,
            -3.507967480362552e-07,
            -3.267697301909081e-08,
            4.588784665736958e-09,
            1.5100688206487113e-09,
            3.4486785229069473e-11,
            -4.092651618709812e-11,
            -3.974686677947093e-12,
            9.406310871290331e-13,
        ),
        (
            1.1223565853640824,
            0.02698082084308221,
            0.002914406770396669,
            0.00010954141463826892,
            -2.4873256945782153e-05,
            -3.986771719406711e-06,
            2.182876118981545e-07,
            8.736892522943252e-08,
            -4.984087397852095e-09,
            -2.2768551189266754e-09,
            1.6280706044741759e-10,
            6.199554472915696e-11,
            -5.075782311702707e-12,
            -1.563018680111627e-12,
        ),
        (
            1.1883496101749178,
            0.03891009789090089,
            0.002750506756728254,
            -0.00018204281711944154,
            -3.8194764758049314e-05,
            1.4377776902027418e-06,
            3.13977603761102e-07,
            -5.1015267262184775e-08,
            -5.69444363592471e-11,
            1.1617869004935969e-09,
            -1.2922028661898806e-10,
            -1.266159268852453e-11,
            4.1680498136310056e-12,
            -1.275659575692479e-13,
        ),
        (
            1.275164385343455,
            0.04665973642630748,
            0.0009013262992246669,
            -0.00040439069986654674,
            -1.6468885342435952e-05,
            2.162518436811267e-06,
            -5.81344033770551e-08,
            -3.6559821209852635e-10,
            1.889323671376665e-09,
            -3.0663046005914536e-10,
            1.2114066170641784e-11,
            3.36304148139138e-12,
            -6.982557677474623e-13,
            -3.491278838737311e-14,
        ),
        (
            1.368656311941327,
            0.04504833615222005,
            -0.0017593054731194736,
            -0.0004571543491687225,
            2.6720920359771895e-06,
            1.7998679495080637e-06,
            -2.7425296115348993e-11,
            2.141111213094749e-09,
            -6.413469155763787e-10,
            -1.2590256462252257e-11,
            6.822764530624719e-12,
            -9.238460927120264e-13,
            3.222718928065211e-14,
            7.788237409490925e-14,
        ),
        (
            1.448158984102721,
            0.03275505428488609,
            -0.004293826076798973,
            -0.00036372604683389894,
            2.056666697332749e-05,
            1.7052733828841986e-06,
            -3.518687423292592e-08,
            -5.967371705015775e-09,
            -2.25403172276815e-10,
            4.0076691919765105e-11,
            1.2857305723426788e-13,
            -3.5130993314794184e-13,
            1.2890875712260844e-13,
            8.459637186171177e-14,
        ),
        (
            1.4939645625098674,
            0.012000025225153744,
            -0.005858833960328292,
            -0.00014014114569971725,
            3.374678159899986e-05,
            7.614537847480059e-07,
            -1.1732164162640572e-07,
            -3.989496162446192e-09,
            4.2489022924880033e-10,
            2.413453501616575e-11,
            -2.012856530487395e-12,
            -3.3872118733518716e-13,
            0.0,
            8.795337074511303e-14,
        ),
    )
)
_S0 = float(np.log(FIXED_POINT_LIMIT))
_INV_H = POLY_PIECES / -_S0


@njit(cache=True, error_model="numpy")
def alpha_unloaded_scalar(eps):
    """The exact unloaded alpha at ``0 < eps <= 1`` (module docstring); 0 at eps = 1.

    Same root as ``engine.exact.alpha_exact_scalar`` to rounding; no domain check (the caller's).
    """
    if eps < FIXED_POINT_LIMIT:
        x = 1.0 / eps
        if x > PURE_INVERSE_X:
            return x
        return x * (1.0 - (1.0 + x) * np.exp(-(1.0 + x)))
    u = (np.log(eps) - _S0) * _INV_H
    j = min(int(u), POLY_PIECES - 1)
    t = 2.0 * (u - j) - 1.0
    c = UNLOADED_POLY[j]
    g = c[POLY_DEGREE]
    for k in range(POLY_DEGREE - 1, -1, -1):
        g = g * t + c[k]
    return (1.0 - eps) / eps * g


def reference_g(eps):
    """``g = a eps / (1 - eps)`` of the exact unloaded root to ``REFERENCE_DIGITS`` digits (mpmath)."""
    import mpmath as mp

    with mp.workdps(2 * REFERENCE_DIGITS):  # the difference of logs cancels ~2 |log10 a| digits
        e = mp.mpf(eps)
        if e == 1:
            return mp.mpf(3) / 2

        def g_of(a):  # ln((1+a)/(1-a e)) - a (1+e), divided by a^2 (a = 0 is a trivial root)
            return (mp.log1p(a) - mp.log1p(-a * e) - a * (1 + e)) / a**2

        start = 1.5 * (1 - e) / e**0.9 if e > 0.25 else (1 - (1 + 1 / e) * mp.exp(-(1 + e) / e)) / e
        # the root lies below 1/eps, where g_of has its pole; halfway from the start to it is safe
        bracket = (0.8 * start, min(1.2 * start, start + (1 / e - start) / 2))
        a = mp.findroot(g_of, bracket, solver="anderson", tol=mp.mpf(10) ** -(2 * REFERENCE_DIGITS))
        return a * e / (1 - e)


def unloaded_polynomial(pieces=POLY_PIECES, degree=POLY_DEGREE):
    """Monomial coefficients of ``g`` on ``pieces`` equal pieces of ln eps (the maintainer's generator).

    Chebyshev interpolation at ``degree + 1`` nodes of each piece of ``reference_g``, converted to
    ascending powers of the local coordinate ``t`` in [-1, 1].  Needs mpmath.
    """
    nodes = np.cos(np.pi * (np.arange(degree + 1) + 0.5) / (degree + 1))
    h = -_S0 / pieces
    out = []
    for j in range(pieces):
        s = _S0 + h * (j + 0.5 + 0.5 * nodes)
        y = np.array([float(reference_g(np.exp(x))) for x in s])
        out.append(np.polynomial.chebyshev.cheb2poly(np.polynomial.chebyshev.chebfit(nodes, y, degree)))
    return np.array(out)
