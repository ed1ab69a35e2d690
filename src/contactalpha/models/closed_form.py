"""A closed form for alpha(eps, xi) that is exact at xi = 0 and fitted in delivered restitution.

The formula (``alpha_closed_form``; 19 constants, ``CONSTANT_NAMES``), with
``A = xi (1 - xi)^(-3/5) / 2`` the scaled load, ``L = ln A`` and
``x_eq = (4 A / 5)^(2/3)`` the static compression (docs/science.md, Sects. 2-4):

    alpha_s = alpha_0(eps) exp(xi (s_xi + s_xi_eps eps) + s_log eps^s_log_exp ln(1 - xi))
    z       = eps^2 (1/2 + A x_eq) / (A x_eq (1 - eps^2))
    alpha_c = 2 x_eq^(-5/2) exp(n_0 + n_1 L + n_2 L^2 + n_3 L^3 + n_4 L^4) (1 + c z)^(-q),
              c = exp(c_0 + c_1 L + c_2 L^2),  q = exp(q_0 + q_1 L + q_2 L^2)
    alpha   = (alpha_s^k + alpha_c^k)^(1/k),  k = k_0 eps^k_1 exp(xi (k_xi + k_xi_eps eps))

``alpha_0`` is the exact unloaded alpha, the root of ln((1+a)/(1-a eps)) = a (1+eps), written
explicitly to rounding (``engine.unloaded``: one exp or one log and a degree-13 polynomial).
Why this shape: when an impact creeps, its end is the static equilibrium, and the energy
identity of Stronge's eps (docs/science.md Sect. 3) gives the maximum compression exactly,
``x_m = x_eq (1 + z)``.  ``alpha_c`` is the damping that stops the compression there: it is
``2 x_eq^(-5/2)`` (the heavy-damping limit of the unloaded relation
``x_m^(5/2) = 2 (a - ln(1 + a)) / a^2``) times a correction in ``L``, falling as ``z`` grows.
Every other end state returns more energy, so the true alpha is at least ``alpha_c``;
``alpha_s`` is the unloaded alpha bent by the load, and the soft maximum switches between
them along the creep boundary.

Properties (tested): alpha = alpha_0 exactly at xi = 0 (alpha_c = 0 there), so alpha ~ 1/eps
as eps -> 0; alpha -> 0 as eps -> 1 (both branches vanish); smooth for 0 < eps < 1,
0 <= xi < 1.  The constants were fitted on 0.01 <= eps <= 0.99, 0 <= xi <= 0.99
(``paper.closedform``); outside that range the formula is an extrapolation.

``alpha_closed_form_scalar`` is the jitted scalar form for a user's numba loop; the
vectorised ``closed_form`` (the registry's model) runs it in a jitted loop.
"""

import json
from functools import lru_cache
from importlib.resources import files

import numpy as np
from numba import njit

from contactalpha.engine.scaling import scaled_load_unchecked
from contactalpha.engine.unloaded import alpha_unloaded_scalar

# Constants shipped with the package (written by ``snakemake -c1 closedform_ship``).
CONSTANTS_FILE = "closed_form.json"
# The constants in the order of the jitted form's argument vector.
CONSTANT_NAMES = (
    "s_xi",
    "s_xi_eps",
    "s_log",
    "s_log_exp",
    "n_0",
    "n_1",
    "n_2",
    "n_3",
    "n_4",
    "c_0",
    "c_1",
    "c_2",
    "q_0",
    "q_1",
    "q_2",
    "k_0",
    "k_1",
    "k_xi",
    "k_xi_eps",
)
# The constants' layout version; a shipped file of another version is refused.
FORMAT_VERSION = 2

_scaled_load = njit(cache=True, error_model="numpy")(scaled_load_unchecked)


@njit(cache=True, error_model="numpy")
def log_branches(eps, xi, c):
    """``(ln alpha_s, ln alpha_c, k)`` of the closed form at one point with 0 < eps < 1, 0 < xi < 1."""
    a0 = alpha_unloaded_scalar(eps)
    log_s = np.log(a0) + xi * (c[0] + c[1] * eps) + c[2] * eps ** c[3] * np.log1p(-xi)
    A = _scaled_load(xi)
    L = np.log(A)
    x_eq = (0.8 * A) ** (2.0 / 3.0)
    z = eps * eps * (0.5 + A * x_eq) / (A * x_eq * (1.0 - eps * eps))
    log_nr = np.log(2.0) - 2.5 * np.log(x_eq) + c[4] + L * (c[5] + L * (c[6] + L * (c[7] + L * c[8])))
    rate = np.exp(c[9] + L * (c[10] + L * c[11]))
    power = np.exp(c[12] + L * (c[13] + L * c[14]))
    log_c = log_nr - power * np.log1p(rate * z)
    k = c[15] * eps ** c[16] * np.exp(xi * (c[17] + c[18] * eps))
    return log_s, log_c, k


@njit(cache=True, error_model="numpy")
def alpha_closed_form_scalar(eps, xi, c):
    """The closed form at one point (module docstring); NaN outside 0 < eps <= 1, 0 <= xi < 1.

    Parameters
    ----------
    eps, xi : float
        Restitution and influence factor.
    c : ndarray, shape (19,)
        Constants in the order of ``CONSTANT_NAMES``.
    """
    if not (0.0 < eps <= 1.0 and 0.0 <= xi < 1.0):
        return np.nan
    if eps == 1.0:
        return 0.0
    if xi == 0.0:
        return alpha_unloaded_scalar(eps)
    log_s, log_c, k = log_branches(eps, xi, c)
    top = max(log_s, log_c)
    return np.exp(top + np.log(np.exp(k * (log_s - top)) + np.exp(k * (log_c - top))) / k)


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
    out = alpha_closed_form_many(np.ascontiguousarray(e).ravel(), np.ascontiguousarray(x).ravel(), c)
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
    d = json.loads(path.read_text(encoding="utf-8"))
    if d.get("format_version") != FORMAT_VERSION:
        raise ValueError(
            f"{path} has format_version {d.get('format_version')!r}; this package reads {FORMAT_VERSION}"
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
