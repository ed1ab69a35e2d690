"""A closed form for alpha(eps, xi) that is exact at xi = 0 and fitted in delivered restitution.

The formula (``alpha_closed_form``; 25 constants, ``CONSTANT_NAMES``), with
``A = xi (1 - xi)^(-3/5) / 2`` the scaled load, ``L = ln A``, ``x_eq = (4 A / 5)^(2/3)`` the
static compression and ``w = x_eq^(5/4)`` (docs/science.md, Sects. 2-4):

    alpha_s = alpha_0(eps) exp(xi (s_xi + s_xi_eps2 eps^2)
                               + (s_log eps^(-3/5) + s_log_eps eps) ln(1 - xi))
    z       = eps^2 (1/2 + A x_eq) / (A x_eq (1 - eps^2)),   g = A x_eq / (1/2 + A x_eq)
    alpha_c = 2 x_eq^(-5/2) (1 + (on_b w)^on_m)^(1/on_m) exp(on_eps eps + on_g g) (1 + c z)^(-q),
              c = exp(c_0 + c_1 L),  q = exp(q_0 + q_1 L + q_2 L^2 + q_eps eps)
    k       = k_0 eps^k_1 exp(xi (k_xi + k_xi_eps eps + k_xi2 xi))
    r       = L - (3/2 ln eps - 3/5 ln(1 - eps) + sep_r0 (1 - eps) - (8/5) ln 2 eps)
    alpha_b = (alpha_s^k + alpha_c^k)^(1/k) exp(sep_a r / (1 + sep_b r^2)^2)
    rho     = ln(alpha_b / alpha_crit) - crit_r0,  alpha_crit = (8/5) (15/8)^(1/2) x_eq^(-5/4)
    alpha   = alpha_b exp(crit_a rho / (1 + crit_b rho^2)^3)

``alpha_0`` is the exact unloaded alpha, the root of ln((1+a)/(1-a eps)) = a (1+eps), written
explicitly to rounding (``engine.unloaded``: one exp or one log and a degree-13 polynomial).
Why this shape: when an impact creeps, its end is the static equilibrium, and the energy
identity of Stronge's eps (docs/science.md Sect. 3) gives the maximum compression exactly,
``x_m = x_eq (1 + z)``.  ``alpha_c`` is the damping that stops the compression there.  At
``z -> 0`` it is the onset of "no restitution", which bends between its two limits: the
heavy-damping limit of the unloaded relation ``x_m^(5/2) = 2 (a - ln(1 + a)) / a^2``, i.e.
``2 x_eq^(-5/2)`` for a light load, and critical damping of the motion linearised about ``x_eq``,
``(8/5) (15/8)^(1/2) x_eq^(-5/4)``, for a heavy one; their ratio grows like ``w``, and the soft
maximum ``(1 + (on_b w)^on_m)^(1/on_m)`` joins them (alone it fits the onset to 0.002 in
ln alpha over 1e-4 <= xi <= 0.99, where a quartic in ``L`` is off by 0.1).  The factor
``(1 + c z)^(-q)`` lowers alpha as the impact overshoots ``x_eq``.  ``g`` is the load's share of
the work that stops the compression at ``x_eq`` (the rest, 1/2, is the impact's kinetic energy):
the exact onset approaches its heavy-load limit like ``1/(A x_eq)`` (measured
``ln(alpha x_eq^(5/4)) = 1.0735 + 0.255/(A x_eq)`` for xi = 0.99 ... 0.9999), which the soft
maximum alone (``~ w^(-on_m)``) does not follow; ``exp(on_g g)`` supplies it and leaves the
light-load limit (``g -> 0``) exact.  The exponent -3/5 of ``alpha_s``'s ``ln(1 - xi)`` term is
fixed: at small eps the load acts on a heavily damped impact whose maximum compression is
``x_m ~ (2 eps)^(2/5)`` (``x_m^(5/2) = 2 (a - ln(1 + a)) / a^2``, ``a ~ 1/eps``), so the load
against the contact force there is ``A / x_m^(3/2) ~ xi eps^(-3/5)`` (fitted free it lands on
-0.600 to -0.603).
Every other end state returns more energy, so the true alpha is at least ``alpha_c``;
``alpha_s`` is the unloaded alpha bent by the load, and the soft maximum switches between them
along the creep boundary.  ``r = ln(A / A_b(eps))`` measures the distance from the separation
boundary, across which the exact alpha is continuous but not smooth (docs/science.md, "Shape of
the surface"): ``ln A_b`` runs linearly in eps between the boundary's exact limits
(``log_separation_load``), and the odd bump ``sep_a r / (1 + sep_b r^2)^2`` (~3 % in alpha,
peak at ``|r| ~ 0.45``) takes out the step of the smooth form's error there, which had left waves
parallel to the boundary; it vanishes as xi -> 0, eps -> 0 and eps -> 1 (``|r| -> inf``).
``alpha_crit`` is the creep boundary, exactly: an impact creeps iff its motion linearised about
``x_eq`` is overdamped (``LOG_CRITICAL``).  Just below it the rebound overshoots ``x_eq`` by a
fraction that vanishes like ``exp(-pi zeta / (1 - zeta^2)^(1/2))``, ``zeta = alpha / alpha_crit``;
the smooth form's ln-alpha error, plotted against ``rho``, stepped there for every load
(negative below it, up to +0.04 in ln alpha just past it on the ridge), and the odd bump
``crit_a rho / (1 + crit_b rho^2)^3``, measured from the form's own ``alpha_b``, takes it out
(-17 % RMS in delivered eps); it vanishes as xi -> 0 and eps -> 1 (``rho -> -inf``).

Properties (tested): alpha = alpha_0 exactly at xi = 0 (alpha_c = 0 there), so alpha ~ 1/eps
as eps -> 0; alpha -> 0 as eps -> 1 (both branches vanish, the bumps' factors -> 1); smooth
for 0 < eps < 1, 0 <= xi < 1.  The constants were fitted on 0.01 <= eps <= 0.99, 0 <= xi <= 0.99
(``paper.closedform``); outside that range the formula is an extrapolation.

``alpha_closed_form_scalar`` is the jitted scalar form for a user's numba loop; the
vectorised ``closed_form`` (the registry's model) runs it in a jitted loop.
"""

from functools import lru_cache
from importlib.resources import files

import numpy as np
from numba import njit

from contactalpha.engine.boundary import LIMIT_EPS_POWER, LIMIT_ONE_MINUS_EPS_POWER, LOG_LIMIT_AT_ONE
from contactalpha.engine.scaling import scaled_load_unchecked
from contactalpha.engine.threads import flat_owned
from contactalpha.engine.unloaded import alpha_unloaded_scalar
from contactalpha.io import read_json

# Constants shipped with the package (written by ``snakemake -c1 closedform_ship``).
CONSTANTS_FILE = "closed_form.json"
# The constants in the order of the jitted form's argument vector.
CONSTANT_NAMES = (
    "s_xi",
    "s_xi_eps2",
    "s_log",
    "s_log_eps",
    "on_b",
    "on_m",
    "on_eps",
    "on_g",
    "c_0",
    "c_1",
    "q_0",
    "q_1",
    "q_2",
    "q_eps",
    "k_0",
    "k_1",
    "k_xi",
    "k_xi_eps",
    "k_xi2",
    "sep_a",
    "sep_b",
    "sep_r0",
    "crit_a",
    "crit_b",
    "crit_r0",
)
# The constants' layout version; a shipped file of another version is refused.
FORMAT_VERSION = 8

# ln(4/5) and ln 2 of x_eq = (4 A / 5)^(2/3) and alpha_c's prefactor 2 x_eq^(-5/2).
LOG_FOUR_FIFTHS = float(np.log(0.8))
LOG_TWO = float(np.log(2.0))
# Fixed exponent of eps in alpha_s's ln(1 - xi) term: A / x_m^(3/2) with x_m ~ (2 eps)^(2/5), the
# heavily damped unloaded maximum compression (module docstring).
S_LOG_EXP = -0.6
# ln of the critical damping of the motion linearised about x_eq, alpha_crit = (8/5) (15/8)^(1/2)
# x_eq^(-5/4) (c^2 = 4 k with c = alpha A, k = (15/8) x_eq^(1/2): ``engine.events.linear_constants``):
# the creep boundary, exactly (creep iff alpha > alpha_crit, ``engine.events.linear_turn``).
LOG_CRITICAL = float(np.log(1.6 * np.sqrt(15.0 / 8.0)))
# ``log_separation_load`` interpolates ln A_b between the separation boundary's exact limits
# (``engine.boundary.LIMIT_*``) linearly in eps; with r0 = ln c it is within 0.033 of the exact
# boundary (a tenth of the bump's width); the fit places the bump with its own sep_r0.

_scaled_load = njit(cache=True, error_model="numpy")(scaled_load_unchecked)


# Inlined in numba's IR: as a separate call it cost ~45 ns of the form's ~370 ns per evaluation.
@njit(cache=True, error_model="numpy", inline="always")
def log_separation_load(eps, log_eps, r0):
    """The log of A_b(eps), the scaled load on the separation boundary, between its exact limits.

    ``3/2 ln eps - 3/5 ln(1 - eps) + r0 (1 - eps) + ln(2^(-3/5) / 2) eps``, ``log_eps = ln eps``:
    exact as eps -> 1, ``r0`` the constant of the eps -> 0 limit.
    """
    return (
        LIMIT_EPS_POWER * log_eps
        - LIMIT_ONE_MINUS_EPS_POWER * np.log1p(-eps)
        + r0 * (1.0 - eps)
        + LOG_LIMIT_AT_ONE * eps
    )


@njit(cache=True, error_model="numpy")
def log_branches(eps, xi, c):
    """``(ln alpha_s, ln alpha_c, k, sep, crit)`` of the closed form at one point, 0 < eps < 1, 0 < xi < 1.

    ``sep`` is the separation-boundary term added to the soft maximum's ln alpha, ``crit`` the
    log of the creep boundary's damping ``alpha_crit`` times ``exp(crit_r0)``.
    """
    log_eps = np.log(eps)
    log_free = np.log1p(-xi)
    log_s = (
        np.log(alpha_unloaded_scalar(eps))
        + xi * (c[0] + c[1] * eps * eps)
        + (c[2] * np.exp(S_LOG_EXP * log_eps) + c[3] * eps) * log_free
    )
    A = _scaled_load(xi)
    L = np.log(A)
    log_x_eq = (2.0 / 3.0) * (LOG_FOUR_FIFTHS + L)
    a_x_eq = 1.25 * np.exp(2.5 * log_x_eq)  # A x_eq = (5/4) x_eq^(5/2), as x_eq^(3/2) = 4 A / 5
    g = a_x_eq / (0.5 + a_x_eq)  # the load's share of the work to x_eq
    onset = np.log1p(np.exp(c[5] * (np.log(c[4]) + 1.25 * log_x_eq))) / c[5] + c[6] * eps + c[7] * g
    z = eps * eps / (g * (1.0 - eps * eps))  # eps^2 (1/2 + A x_eq) / (A x_eq (1 - eps^2))
    rate_z = np.exp(c[8] + L * c[9]) * z
    power = np.exp(c[10] + L * (c[11] + L * c[12]) + c[13] * eps)
    log_c = LOG_TWO - 2.5 * log_x_eq + onset - power * np.log1p(rate_z)
    k = c[14] * np.exp(c[15] * log_eps + xi * (c[16] + c[17] * eps + c[18] * xi))
    r = L - log_separation_load(eps, log_eps, c[21])  # ln(A / A_b(eps))
    u = 1.0 + c[20] * r * r
    return log_s, log_c, k, c[19] * r / (u * u), LOG_CRITICAL - 1.25 * log_x_eq + c[24]


@njit(cache=True, error_model="numpy")
def alpha_closed_form_scalar(eps, xi, c):
    """The closed form at one point (module docstring); NaN outside 0 < eps <= 1, 0 <= xi < 1.

    Parameters
    ----------
    eps, xi : float
        Restitution and influence factor.
    c : ndarray, shape (25,)
        Constants in the order of ``CONSTANT_NAMES``.
    """
    if not (0.0 < eps <= 1.0 and 0.0 <= xi < 1.0):
        return np.nan
    if eps == 1.0:
        return 0.0
    if xi == 0.0:
        return alpha_unloaded_scalar(eps)
    log_s, log_c, k, sep, crit = log_branches(eps, xi, c)
    log_a = max(log_s, log_c) + np.log1p(np.exp(-k * abs(log_s - log_c))) / k + sep
    rho = log_a - crit  # ln(alpha / alpha_crit) - crit_r0: distance from the creep boundary
    u = 1.0 + c[23] * rho * rho
    return np.exp(log_a + c[22] * rho / (u * u * u))


@njit(cache=True, error_model="numpy")
def alpha_closed_form_many(eps, xi, c):
    """``alpha_closed_form_scalar`` over flat float arrays ``eps``, ``xi`` (one thread)."""
    out = np.empty(eps.size)
    for i in range(eps.size):
        out[i] = alpha_closed_form_scalar(eps[i], xi[i], c)
    return out


def constants_vector(constants):
    """A dict ``{name: value}`` of constants as the jitted form's vector (ValueError if one is missing)."""
    missing = [n for n in CONSTANT_NAMES if n not in constants]
    if missing:
        raise ValueError(f"closed-form constants missing: {missing}; expected {list(CONSTANT_NAMES)}")
    return np.array([float(constants[n]) for n in CONSTANT_NAMES])


def alpha_closed_form(eps, xi, constants=None):
    """The closed form on arrays (broadcast), without validation: NaN outside its domain.

    ``constants`` is a dict ``{name: value}`` or a vector in ``CONSTANT_NAMES`` order;
    default the shipped ones (``load_constants``).
    """
    c = shipped_vector() if constants is None else constants
    c = constants_vector(c) if isinstance(c, dict) else np.ascontiguousarray(c, dtype=float)
    if c.shape != (len(CONSTANT_NAMES),):
        raise ValueError(f"closed-form constants have shape {c.shape}; expected ({len(CONSTANT_NAMES)},)")
    e, x = np.broadcast_arrays(np.asarray(eps, dtype=float), np.asarray(xi, dtype=float))
    out = alpha_closed_form_many(flat_owned(e), flat_owned(x), c)
    out = out.reshape(e.shape)
    return out[()] if out.ndim == 0 else out


@lru_cache(maxsize=1)
def load_constants():
    """The shipped constants file ``contactalpha/data/closed_form.json`` (a dict).

    Raises
    ------
    FileNotFoundError
        If the package was built without it (``snakemake -c1 closedform_ship`` writes it).
    ValueError
        If the file is of another format version or lacks a constant.
    """
    path = files("contactalpha") / "data" / CONSTANTS_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{path} is missing: run `snakemake -c1 closedform_ship` to write it")
    d = read_json(path, "closed-form constants")
    if not isinstance(d, dict) or d.get("format_version") != FORMAT_VERSION:
        raise ValueError(
            f"{path} has format_version {d.get('format_version') if isinstance(d, dict) else None!r}; "
            f"this package reads {FORMAT_VERSION}"
        )
    constants_vector(d["constants"])
    return d


def shipped_vector():
    """The shipped constants as the jitted form's vector."""
    return constants_vector(load_constants()["constants"])


def closed_form(eps, xi):
    """The registry's ``closed_form`` model: the closed form with the shipped constants."""
    return alpha_closed_form(eps, xi)


def jit_alpha_closed_form(constants=None):
    """A jitted scalar ``f(eps, xi)`` of the closed form for use inside a user's numba code.

    NaN outside 0 < eps <= 1, 0 <= xi < 1.  The constants (default: shipped) are frozen in.
    """
    c = shipped_vector() if constants is None else constants
    c = constants_vector(c) if isinstance(c, dict) else np.ascontiguousarray(c, dtype=float)

    @njit(error_model="numpy")
    def f(eps, xi):
        return alpha_closed_form_scalar(eps, xi, c)

    return f
