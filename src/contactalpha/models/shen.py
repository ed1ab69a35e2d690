"""Shen et al.'s closed form for alpha(eps, xi) (Sect. 5, Eqs. 26 and 31-40) and its building blocks.

Eq. 40 reaches us through OCR, and its first term is damaged (docs/science.md, "Reading the
damaged equations").
The printed digits are ``e^{-(eps + 1 - xi^0.05)^2}``, ``0.1568 xi^0.9`` and a
duplicated ``(1 - eps)^6``; Eq. 39's generic form of the term is
``e^{-(eps + tau)^2 / sigma} (1 - eps)^a / beta``.  Each way of mapping the digits
onto (tau, sigma, a, beta) is a *reading* (``READINGS``).  ``BEST_READING`` is the
one that the per-xi fits of Eq. 39 support (``fit.fit_eq39_slices``; the evidence
is in ``results/fit/eq40_readings.md``): ``0.1568 xi^0.9`` is the width sigma.
Under that reading, beta is not printed at all.  It is named ``beta``, set to 1
("as printed") in ``PUBLISHED`` and refit, never invented.

The dissipation ratios of Eqs. 36-37 come from exact energy identities of the
scaled equation ``x'' = A - (5/4) x^{3/2} (1 + alpha x')`` (docs/science.md, "The restitution identity").
With ``D_c``, ``D_r`` the damping work of compression and restitution (unit
``m_e v0^2``), ``x_m`` the maximum and ``x_e`` the end compression, and
``lambda = x_e / x_m``:

    D_c = 1/2 + A x_m - x_m^{5/2} / 2,
    D_r = x_m^{5/2} / 2 - x_e^{5/2} / 2 - A (x_m - x_e) - v_e^2 / 2,
    v_e^2 / 2 = eps^2 (1/2 + A x_m) - A (x_m - x_e),
    s_a = D_c / ((5/4) alpha x_m^{5/2}),
    eta_c = s_a / (0.851 S),   eta_r = D_r / ((5/4) alpha x_m^{5/2} 0.851 S (1 - lambda^{5/2})).

With these, Eq. 38 holds exactly (``eq38``), since ``0.47 = 0.4 / 0.851``.
"""

from dataclasses import dataclass
from functools import lru_cache
from importlib.resources import files

import numpy as np
from numba import njit

from contactalpha.engine.scaling import scaled_load
from contactalpha.engine.threads import flat_owned
from contactalpha.io import read_json
from contactalpha.validation import check_eps, check_xi

# Eq. 32/34: the published factor between s1 (Eq. 31) and sqrt(s2 / 2) (Eq. 33).
S21_COEF = 0.851
# Eq. 38: 0.4 / 0.851 rounded, as printed.
ENERGY_COEF = 0.47
# Eq. 40, xi = 0 branch: alpha = 3 (1 - eps) / (2 eps^0.89).
ZERO_LOAD_EXP = 0.89
# Eq. 26 at xi = 0.2 (the paper's Fig. 5).
EQ26_PUBLISHED = {"tau": 0.01, "sigma": 0.011, "beta": 0.113}
# Absolute tolerance of the s1 quadrature (Eq. 31); s1 is about 0.2.
S1_QUAD_EPSABS = 1e-13

# Refit constants shipped with the package: the workflow refits them (rule fit_refit, results/ only)
# and `snakemake -c2 ship_fit` copies them here.
REFIT_FILE = "shen_refit.json"

# Every numeric constant of Eq. 40 (0 < xi < 1), as printed, with its role.
PUBLISHED = {
    "tau_one": 1.0,  # tau = tau_one - xi^tau_exp
    "tau_exp": 0.05,
    "width_coef": 0.1568,  # 0.1568 xi^0.9: sigma or beta, by reading
    "width_exp": 0.9,
    "a": 6.0,  # (1 - eps)^a
    "beta": 1.0,  # beta of the sigma readings: not printed, so 1 "as printed"
    "energy_coef": ENERGY_COEF,  # 0.47 = 0.4 / 0.851
    "b_xi_exp": 1.3,  # eps^-(eps^(xi^1.3) + 0.1 xi - 0.97)
    "b_xi_coef": 0.1,
    "b_const": 0.97,
    "eta_const": 0.86,  # eta = eps^(0.86 + 2.6 xi + xi^3.5 - 1.5 eps xi)
    "eta_xi": 2.6,
    "eta_xi_exp": 3.5,
    "eta_eps_xi": 1.5,
    "lam_xi_exp": 0.59,  # lambda = 1 - (eps / xi^0.59)^(1 + xi^0.3 [1 - eps (1 - xi)])
    "lam_xi_pow": 0.3,
}
# Constants of the second term of Eq. 40 and of its S, eta and lambda (read cleanly).
SECOND_TERM = [
    "energy_coef",
    "b_xi_exp",
    "b_xi_coef",
    "b_const",
    "eta_const",
    "eta_xi",
    "eta_xi_exp",
    "eta_eps_xi",
    "lam_xi_exp",
    "lam_xi_pow",
]
# Constants the printed text does not determine (refit, never invented).
UNDETERMINED = {"beta": "beta of Eq. 39 is not printed in Eq. 40 under the sigma readings (OCR loss)"}

# Readings of Eq. 40's damaged first term, as (role of 0.1568 xi^0.9, exponent a used?).
READINGS = {
    "sigma_a6": "e^{-(eps+tau)^2/(0.1568 xi^0.9)} (1-eps)^6 / beta, tau = 1 - xi^0.05, beta lost",
    "sigma_a0": "e^{-(eps+tau)^2/(0.1568 xi^0.9)} / beta, tau = 1 - xi^0.05, beta lost, the (1-eps)^6 cancel",
    "beta_a6": "e^{-(eps+tau)^2} (1-eps)^6 / (0.1568 xi^0.9), tau = 1 - xi^0.05, sigma = 1",
    "beta_a0": "e^{-(eps+tau)^2} / (0.1568 xi^0.9), tau = 1 - xi^0.05, sigma = 1, the (1-eps)^6 cancel",
    "none": "first term dropped: the second term of Eq. 40 alone",
}
# The reading the per-xi fits of Eq. 39 support (see the module docstring).
BEST_READING = "sigma_a6"


def check_reading(reading):
    """``reading`` if it is a key of ``READINGS``; ValueError naming the valid ones otherwise."""
    if reading not in READINGS:
        raise ValueError(f"reading = {reading!r} is not one of the valid readings {sorted(READINGS)}")
    return reading


def reading_constants(reading=BEST_READING):
    """Names of the ``PUBLISHED`` constants that enter Eq. 40 under ``reading``."""
    first = {
        "sigma_a6": ["tau_one", "tau_exp", "width_coef", "width_exp", "a", "beta"],
        "sigma_a0": ["tau_one", "tau_exp", "width_coef", "width_exp", "beta"],
        "beta_a6": ["tau_one", "tau_exp", "width_coef", "width_exp", "a"],
        "beta_a0": ["tau_one", "tau_exp", "width_coef", "width_exp"],
        "none": [],
    }[check_reading(reading)]
    return first + SECOND_TERM


def contact_factor(xi):
    """S = sqrt((7 - 4 xi) / (70 (1 - xi))) of Eqs. 34-40 (equals sqrt(s2 / 2), Eq. 33)."""
    xi = np.asarray(xi, dtype=float)
    return np.sqrt((7.0 - 4.0 * xi) / (70.0 * (1.0 - xi)))


def _s1_scalar(xi):
    from scipy.integrate import quad  # lazy: 0.2-0.7 s of import in every job

    r = xi / (1.0 - xi)
    # sqrt(g) = sqrt(1 - x) sqrt(g / (1 - x)): the endpoint singularity goes to quad's weight.
    slope = 2.5 + 1.5 * r  # -g'(1), the limit of g / (1 - x)

    def smooth(x):
        if x >= 1.0:
            return slope
        g = 1.0 - x**2.5 + r * (x - x**2.5)
        return x**1.5 * np.sqrt(max(g / (1.0 - x), 0.0))

    val, _ = quad(
        smooth, 0.0, 1.0, weight="alg", wvar=(0.0, 0.5), epsabs=S1_QUAD_EPSABS, epsrel=S1_QUAD_EPSABS
    )
    return val


def s1(xi):
    """Compression damping integral of the undamped motion, Eq. 31, by adaptive quadrature.

    Parameters
    ----------
    xi : float or array_like
        Influence factor, 0 <= xi < 1.

    Returns
    -------
    float or ndarray
        ``int_0^1 x^{3/2} sqrt(1 - x^{5/2} + xi/(1-xi) (x - x^{5/2})) dx``.
    """
    xi = check_xi(xi)
    out = np.vectorize(_s1_scalar, otypes=[float])(xi)
    return out[()] if out.ndim == 0 else out


def s21(xi, coef=S21_COEF):
    """The paper's approximation of s1, Eq. 34: ``coef * S``."""
    return coef * contact_factor(check_xi(xi))


def lambda_eq40(eps, xi, c=PUBLISHED):
    """End-to-maximum compression ratio of Eq. 40, clipped at 0 (0 at xi = 0)."""
    eps, xi = np.asarray(eps, dtype=float), np.asarray(xi, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        power = 1.0 + xi ** c["lam_xi_pow"] * (1.0 - eps * (1.0 - xi))
        lam = 1.0 - (eps / xi ** c["lam_xi_exp"]) ** power
    return np.where(xi > 0, np.clip(np.nan_to_num(lam, nan=0.0, neginf=0.0), 0.0, None), 0.0)


def eta_eq40(eps, xi, c=PUBLISHED):
    """Eta of Eq. 40: ``eps^(0.86 + 2.6 xi + xi^3.5 - 1.5 eps xi)``."""
    eps, xi = np.asarray(eps, dtype=float), np.asarray(xi, dtype=float)
    return eps ** (c["eta_const"] + c["eta_xi"] * xi + xi ** c["eta_xi_exp"] - c["eta_eps_xi"] * eps * xi)


def exponent_b(eps, xi, c=PUBLISHED):
    """Exponent b of eps in Eq. 39's second term, as Eq. 40 sets it: ``-(eps^(xi^1.3) + 0.1 xi - 0.97)``."""
    eps, xi = np.asarray(eps, dtype=float), np.asarray(xi, dtype=float)
    return -(eps ** (xi ** c["b_xi_exp"]) + c["b_xi_coef"] * xi - c["b_const"])


def eq25(eps):
    """Eq. 25, Hu & Guo's alpha (the paper's alpha_initial): ``3 (1 - eps) / (2 eps)``."""
    eps = np.asarray(eps, dtype=float)
    return 1.5 * (1.0 - eps) / eps


def eq26(eps, tau, sigma, beta):
    """EXP of Eq. 26: ``exp(-(eps + tau)^2 / sigma) / beta``."""
    return np.exp(-((np.asarray(eps, dtype=float) + tau) ** 2) / sigma) / beta


def first_term(eps, tau, sigma, beta, a):
    """Eq. 39's first term: ``exp(-(eps + tau)^2 / sigma) (1 - eps)^a / beta`` (Eq. 26 times (1 - eps)^a)."""
    eps = np.asarray(eps, dtype=float)
    return np.exp(-((eps + tau) ** 2) / sigma) * (1.0 - eps) ** a / beta


def printed_tau(xi, c=PUBLISHED):
    """Tau of Eq. 40's first term as printed: ``1 - xi^0.05``."""
    return c["tau_one"] - np.asarray(xi, dtype=float) ** c["tau_exp"]


def printed_width(xi, c=PUBLISHED):
    """The printed ``0.1568 xi^0.9`` of Eq. 40's first term (sigma or beta, by reading)."""
    return c["width_coef"] * np.asarray(xi, dtype=float) ** c["width_exp"]


def eq39(eps, xi, *, tau, sigma, beta, a, lam, b, eta_c, eta_r, energy_coef=ENERGY_COEF):
    """The generic closed form, Eq. 39 (all arguments broadcast).

    ``alpha = exp(-(eps+tau)^2/sigma) (1-eps)^a / beta
    + energy_coef (1 - eps^2 - lam^{5/2}) eps^b / (S [eta_c eps^2 + eta_r (1 - lam^{5/2})])``.
    """
    eps = np.asarray(eps, dtype=float)
    l25 = np.asarray(lam, dtype=float) ** 2.5
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        first = first_term(eps, tau, sigma, beta, a)
        second = (
            energy_coef
            * (1.0 - eps**2 - l25)
            * eps**b
            / (contact_factor(xi) * (eta_c * eps**2 + eta_r * (1.0 - l25)))
        )
    return first + second


def first_term_params(xi, c=PUBLISHED, reading=BEST_READING):
    """(tau, sigma, beta, a) of Eq. 39's first term under a reading of Eq. 40."""
    tau = printed_tau(xi, c)
    width = printed_width(xi, c)
    if reading.startswith("sigma"):
        return tau, width, c["beta"], c["a"] if reading == "sigma_a6" else 0.0
    return tau, 1.0, width, c["a"] if reading == "beta_a6" else 0.0


def eq40_terms(eps, xi, c=PUBLISHED, reading=BEST_READING):
    """The two terms of Eq. 40 for 0 < xi < 1, without validation: ``(first, second)``."""
    check_reading(reading)
    eps, xi = np.broadcast_arrays(np.asarray(eps, dtype=float), np.asarray(xi, dtype=float))
    lam = lambda_eq40(eps, xi, c)
    second = eq39(
        eps,
        xi,
        tau=0.0,
        sigma=1.0,
        beta=np.inf,
        a=0.0,
        lam=lam,
        b=exponent_b(eps, xi, c),
        eta_c=1.0,
        eta_r=eta_eq40(eps, xi, c),
        energy_coef=c["energy_coef"],
    )
    if reading == "none":
        return np.zeros_like(second), second
    tau, sigma, beta, a = first_term_params(xi, c, reading)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        first = first_term(eps, tau, sigma, beta, a)
    return first, second


def eq39_gradient(eps, xi, *, tau, sigma, beta, a, lam, b, eta_c, eta_r, energy_coef=ENERGY_COEF):
    """Eq. 39 (``eq39``) and its exact partial derivatives, for least-squares fits.

    Arguments as ``eq39``'s (they broadcast).  ``d/d lam`` is 0 where ``lam = 0``
    (``lam^{5/2}`` has zero slope there), and ``d/d sigma``, ``d/d beta`` and ``d/d a`` are
    0 where the first term is off (``beta = inf``).

    Returns
    -------
    value : ndarray
        ``eq39(...)``.
    grad : dict
        ``d value / d v`` for v in ``tau, sigma, beta, a, b, eta_r, lam, energy_coef``.
    """
    value = eq39(
        eps, xi, tau=tau, sigma=sigma, beta=beta, a=a, lam=lam, b=b, eta_c=eta_c, eta_r=eta_r,
        energy_coef=energy_coef,
    )  # fmt: skip
    eps, lam = np.asarray(eps, dtype=float), np.asarray(lam, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        first = first_term(eps, tau, sigma, beta, a)
        ln_eps, l25 = np.log(eps), lam**2.5
        # Second term G = energy_coef K N, K = eps^b / (S D), N = 1 - eps^2 - L,
        # D = eta_c eps^2 + eta_r (1 - L).
        den = eta_c * eps**2 + eta_r * (1.0 - l25)
        k = eps**b / (contact_factor(xi) * den)
        num = 1.0 - eps**2 - l25
        second = energy_coef * k * num
        u = eps + tau
        grad = {
            "tau": -2.0 * first * u / sigma,
            "sigma": first * u**2 / sigma**2,
            "beta": -first / beta,
            "a": first * np.log1p(-eps),
            "b": second * ln_eps,
            "eta_r": -second * (1.0 - l25) / den,
            "lam": energy_coef * k * (eta_r * num / den - 1.0) * 2.5 * lam**1.5,
            "energy_coef": k * num,
        }
    return value, grad


def eq40_gradient(eps, xi, c=PUBLISHED, reading=BEST_READING, names=None):
    """Eq. 40 (0 < xi < 1) and its exact derivatives with respect to the constants ``names``.

    For the least-squares refit (``fit.fit_eq40``): one jitted pass (``_eq40_gradient_kernel``)
    costs about one numpy evaluation of Eq. 40, where a finite-difference Jacobian costs one
    per constant.  The value agrees with ``eq40_terms`` to rounding (tested); the fits take
    their residuals from ``eq40_terms`` and only the Jacobian from here.

    Parameters
    ----------
    eps, xi : array_like
        Points, 0 < eps < 1 and 0 < xi < 1 (not validated; they broadcast).
    c : dict
        Constants named as in ``PUBLISHED``.
    reading : str
        A key of ``READINGS``.
    names : list of str, optional
        Constants to differentiate by; default ``reading_constants(reading)``.  A name that
        does not enter Eq. 40 under ``reading`` gets a zero column.

    Returns
    -------
    value : ndarray
        ``first + second`` of ``eq40_terms``, flattened.
    jac : ndarray, shape (value.size, len(names))
        ``d value / d c[name]`` per column.
    """
    check_reading(reading)
    names = reading_constants(reading) if names is None else list(names)
    unknown = [n for n in names if n not in PUBLISHED]
    if unknown:
        raise ValueError(f"constants {unknown} are not constants of Eq. 40; valid: {sorted(PUBLISHED)}")
    eps, xi = np.broadcast_arrays(np.asarray(eps, dtype=float).ravel(), np.asarray(xi, dtype=float).ravel())
    constants = np.array([c[k] for k in PUBLISHED], dtype=float)
    value = np.empty(eps.size)
    full = np.zeros((eps.size, len(PUBLISHED)))
    _eq40_gradient_kernel(
        flat_owned(eps),
        flat_owned(xi),
        constants,
        list(READINGS).index(reading),
        value,
        full,
    )
    order = list(PUBLISHED)
    return value, full[:, [order.index(n) for n in names]]


@njit(cache=True, error_model="numpy")
def _eq40_gradient_kernel(eps, xi, c, reading, value, jac):
    """Eq. 40 at each point into ``value`` and its derivatives into ``jac`` (columns: ``PUBLISHED``).

    ``c`` holds the constants in ``PUBLISHED``'s order, ``reading`` is the index in ``READINGS``
    (sigma_a6, sigma_a0, beta_a6, beta_a0, none).  Columns of constants that do not enter
    Eq. 40 under ``reading`` are left as they are (zeros from the caller).
    """
    for i in range(eps.size):
        e, x = eps[i], xi[i]
        ln_e, ln_x = np.log(e), np.log(x)
        # lambda = 1 - r^q clipped at 0, r = eps / xi^lam_xi_exp, q = 1 + xi^lam_xi_pow (1 - eps (1 - xi))
        x_q = x ** c[15]
        q = 1.0 + x_q * (1.0 - e * (1.0 - x))
        ln_r = ln_e - c[14] * ln_x
        r_q = np.exp(q * ln_r)
        lam = 1.0 - r_q
        live = lam > 0.0
        if not live:
            lam = 0.0
        l15 = lam**1.5
        l25 = l15 * lam
        # eta = eps^p, p = eta_const + eta_xi xi + xi^eta_xi_exp - eta_eps_xi eps xi
        x_eta = x ** c[12]
        eta = np.exp((c[10] + c[11] * x + x_eta - c[13] * e * x) * ln_e)
        # b = -(eps^(xi^b_xi_exp) + b_xi_coef xi - b_const)
        x_b = x ** c[7]
        e_xb = np.exp(x_b * ln_e)
        b = -(e_xb + c[8] * x - c[9])
        # second term G = energy_coef K N, K = eps^b / (S D), N = 1 - eps^2 - L, D = eps^2 + eta (1 - L)
        s_factor = np.sqrt((7.0 - 4.0 * x) / (70.0 * (1.0 - x)))
        den = e * e + eta * (1.0 - l25)
        k = np.exp(b * ln_e) / (s_factor * den)
        num = 1.0 - e * e - l25
        g = c[6] * k * num
        d_b = g * ln_e
        d_p = -g * (1.0 - l25) / den * eta * ln_e
        jac[i, 6] = k * num
        jac[i, 7] = -d_b * e_xb * ln_e * x_b * ln_x
        jac[i, 8] = -d_b * x
        jac[i, 9] = d_b
        jac[i, 10] = d_p
        jac[i, 11] = d_p * x
        jac[i, 12] = d_p * x_eta * ln_x
        jac[i, 13] = -d_p * e * x
        if live:  # L = lambda^{5/2} has zero slope at the clip
            d_lam = c[6] * k * (eta * num / den - 1.0) * 2.5 * l15
            jac[i, 14] = d_lam * q * r_q * ln_x
            jac[i, 15] = -d_lam * r_q * ln_r * x_q * ln_x * (1.0 - e * (1.0 - x))
        else:
            jac[i, 14] = 0.0
            jac[i, 15] = 0.0
        first = 0.0
        if reading < 4:
            # first term F = exp(-(eps + tau)^2 / sigma) (1 - eps)^a / beta, tau = tau_one - xi^tau_exp;
            # the width 0.1568 xi^0.9 is sigma (sigma readings) or beta (beta readings)
            x_tau = x ** c[1]
            u = e + c[0] - x_tau
            x_w = x ** c[3]
            width = c[2] * x_w
            sigma, beta = (width, c[5]) if reading < 2 else (1.0, width)
            a = c[4] if reading % 2 == 0 else 0.0
            first = np.exp(-u * u / sigma) * (1.0 - e) ** a / beta
            d_tau = -2.0 * first * u / sigma
            d_width = first * u * u / (sigma * sigma) if reading < 2 else -first / beta
            jac[i, 0] = d_tau
            jac[i, 1] = -d_tau * x_tau * ln_x
            jac[i, 2] = d_width * x_w
            jac[i, 3] = d_width * width * ln_x
            if reading % 2 == 0:
                jac[i, 4] = first * np.log1p(-e)
            if reading < 2:
                jac[i, 5] = -first / beta
        value[i] = first + g


def zero_load(eps, exponent=ZERO_LOAD_EXP):
    """Eq. 40 at xi = 0: ``3 (1 - eps) / (2 eps^exponent)``."""
    eps = np.asarray(eps, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.5 * (1.0 - eps) / eps**exponent


def eq40(eps, xi, c=PUBLISHED, reading=BEST_READING, zero_load_exp=ZERO_LOAD_EXP):
    """alpha(eps, xi) of Eq. 40, both branches.

    Parameters
    ----------
    eps : array_like
        Restitution coefficient, 0 < eps <= 1.
    xi : array_like
        Influence factor, 0 <= xi < 1; ``xi = 0`` takes the zero-load branch.
    c : dict
        Constants named as in ``PUBLISHED`` (default: as printed).
    reading : str
        A key of ``READINGS``: how the damaged first term is read.
    zero_load_exp : float
        Exponent of the xi = 0 branch (printed: 0.89).

    Returns
    -------
    float or ndarray
    """
    eps = check_eps(eps)
    xi = check_xi(xi)
    if np.any(eps == 0.0):
        raise ValueError("eps = 0.0 is outside the valid range (0.0, 1.0] of Eq. 40")
    first, second = eq40_terms(eps, np.where(xi > 0, xi, 0.5), c, reading)
    out = np.where(xi > 0, first + second, zero_load(eps, zero_load_exp))
    return out[()] if out.ndim == 0 else out


@dataclass(frozen=True)
class Dissipation:
    """Damping work and the paper's ratios, from the end state of computed impacts (arrays).

    Attributes
    ----------
    d_c, d_r : damping work of compression and restitution (Eqs. 28-29), unit m_e v0^2.
    s_a : damped counterpart of s1 (Eq. 30 with the actual motion).
    eta_c, eta_r : the ratios of Eqs. 36 and 37 (NaN for eta_r where lambda = 1).
    lam : x_end / x_max.
    """

    d_c: np.ndarray
    d_r: np.ndarray
    s_a: np.ndarray
    eta_c: np.ndarray
    eta_r: np.ndarray
    lam: np.ndarray


def dissipation(eps, xi, alpha, x_max, x_end):
    """s_a, eta_c and eta_r implied by impacts that end at (x_max, x_end) with restitution eps.

    Exact energy identities (module docstring); inputs broadcast, scaled as in
    ``impact``.  Where ``alpha`` is 0 the ratios are NaN.
    """
    eps, xi, alpha, x_m, x_e = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (eps, xi, alpha, x_max, x_end))
    )
    A = scaled_load(np.clip(xi, 0.0, None))
    d_c = 0.5 + A * x_m - 0.5 * x_m**2.5
    half_ve2 = eps**2 * (0.5 + A * x_m) - A * (x_m - x_e)
    d_r = 0.5 * x_m**2.5 - 0.5 * x_e**2.5 - A * (x_m - x_e) - half_ve2
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = x_e / x_m
        unit = 1.25 * alpha * x_m**2.5
        s_a = d_c / unit
        ref = S21_COEF * contact_factor(xi)
        eta_c = s_a / ref
        eta_r = d_r / (unit * ref * (1.0 - lam**2.5))
    return Dissipation(d_c=d_c, d_r=d_r, s_a=s_a, eta_c=eta_c, eta_r=eta_r, lam=lam)


def eq38(eps, xi, lam, eta_c, eta_r):
    """Alpha of Eq. 38 from lambda, eta_c and eta_r (exact with the measured ratios)."""
    l25 = np.asarray(lam, dtype=float) ** 2.5
    eps = np.asarray(eps, dtype=float)
    return (0.4 / S21_COEF) * (1 - eps**2 - l25) / (contact_factor(xi) * (eta_c * eps**2 + eta_r * (1 - l25)))


def compression_work_path(path, alpha):
    """Damping work of compression by trapezoidal quadrature along a recorded trajectory.

    Parameters
    ----------
    path : ndarray, shape (n, 3)
        ``(t, x, v)`` rows from ``impact.trajectory`` (scaled).
    alpha : float
        Damping factor of the run.

    Returns
    -------
    float
        ``int (5/4) alpha x^{3/2} v dx`` over the compression phase (v > 0),
        as ``int (5/4) alpha x^{3/2} v^2 dt``.
    """
    t, x, v = path[:, 0], path[:, 1], path[:, 2]
    stop = np.flatnonzero(v <= 0.0)
    n = stop[0] + 1 if stop.size else len(t)
    power = 1.25 * alpha * np.clip(x[:n], 0.0, None) ** 1.5 * np.clip(v[:n], 0.0, None) ** 2
    return float(np.trapezoid(power, t[:n]))


@lru_cache(maxsize=1)
def load_refit():
    """The refit constants shipped in ``contactalpha/data/shen_refit.json`` (a dict).

    Raises
    ------
    FileNotFoundError
        If the package was built without the file (``snakemake -c2 ship_fit`` ships it).
    """
    path = files("contactalpha") / "data" / REFIT_FILE
    if not path.is_file():
        raise FileNotFoundError(
            f"{path} is missing: run `snakemake -c2 ship_fit` to refit and ship the constants"
        )
    d = read_json(path, "refit constants")
    if not isinstance(d, dict) or not isinstance(d.get("constants"), dict):
        raise ValueError(f"refit constants {path} hold no 'constants' mapping; ship them again (ship_fit)")
    return d


def shen_published(eps, xi):
    """Eq. 40 as published, read as ``BEST_READING`` (beta = 1 as printed); both branches."""
    return eq40(eps, xi)


def shen_refit(eps, xi):
    """Eq. 40 with every constant refit to the computed surface (``load_refit``), both branches."""
    d = load_refit()
    return eq40(eps, xi, {**PUBLISHED, **d["constants"]}, d["reading"], d["zero_load_exp"])
