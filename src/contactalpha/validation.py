"""Input checks shared by the public API: every message names the value and the valid range."""

import math
import reprlib

import numpy as np

# A float for scalar input, an array of the broadcast shape for array input.
FloatOrArray = float | np.ndarray
# A real number or an array of them (the public functions broadcast their array arguments).
RealLike = float | np.ndarray


# Upper limit on a step budget: far beyond any run, far below int64 overflow in the kernels.
MAX_STEPS_LIMIT = 1e15


def _describe(bad):
    flat = np.atleast_1d(bad).ravel()
    shown = ", ".join(repr(float(b)) for b in flat[:3])
    more = f" (and {flat.size - 3} more)" if flat.size > 3 else ""
    return shown + more


# Values that numpy would turn into numbers but that are not numbers.
_NOT_NUMBERS = (bool, np.bool_, str, bytes)


def as_real(name, value, valid="real numbers"):
    """Return ``value`` as a float array; complex input and non-numbers (None, bool, text) raise ValueError.

    numpy would cut a complex array to its real part with only a warning.
    """
    arr = np.asarray(value)
    if arr.dtype == object and any(v is None or isinstance(v, _NOT_NUMBERS) for v in arr.ravel()):
        raise ValueError(f"{name} = {reprlib.repr(value)} is not a number; valid: {valid}")
    if arr.dtype.kind in "bUS":  # numpy would read True as 1.0 and "0.5" as 0.5
        kind = "a bool" if arr.dtype.kind == "b" else "text"
        raise ValueError(f"{name} = {reprlib.repr(value)} is {kind}, not a number; valid: {valid}")
    if arr.dtype.kind == "c":
        shown = ", ".join(repr(complex(c)) for c in np.atleast_1d(arr).ravel()[:3])
        raise ValueError(f"{name} = {shown} is complex; valid: {valid}")
    try:
        return arr.astype(float, copy=False)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {reprlib.repr(value)} is not a number; valid: {valid}") from None


def check_range(name, value, lo, hi, *, lo_open=False, hi_open=False):
    """Return ``value`` as a float array, or raise ``ValueError`` naming the bad entries.

    NaN, infinities, complex numbers and non-numbers are always rejected.
    """
    if (
        type(value) in PLAIN_FLOATS
        and math.isfinite(value)
        and (value > lo if lo_open else value >= lo)
        and (value < hi if hi_open else value <= hi)
    ):
        return np.array(value)  # a plain float inside the range: the same 0-d array, ~20x sooner
    left = "(" if lo_open else "["
    right = ")" if hi_open else "]"
    arr = as_real(name, value, f"real numbers in {left}{lo}, {hi}{right}")
    ok = np.isfinite(arr)
    ok &= (arr > lo) if lo_open else (arr >= lo)
    ok &= (arr < hi) if hi_open else (arr <= hi)
    if not np.all(ok):
        raise ValueError(f"{name} = {_describe(arr[~ok])} is outside the valid range {left}{lo}, {hi}{right}")
    return arr


def check_count(name, value, lo, hi):
    """Return ``value`` as an int, or raise unless it is one whole number in [lo, hi] (not a bool)."""
    if isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} = {value!r} is a bool, not one whole number in [{lo:g}, {hi:g}]")
    arr = check_range(name, value, lo, hi)
    if arr.ndim != 0 or arr != np.floor(arr):
        raise ValueError(f"{name} = {reprlib.repr(value)} is not one whole number in [{lo:g}, {hi:g}]")
    return int(arr)


def check_scalar(name, value, lo, hi, *, lo_open=False, hi_open=False):
    """Return ``value`` as a float, or raise unless it is one real number in range (no bool, text, list)."""
    if (
        type(value) in PLAIN_FLOATS
        and (value > lo if lo_open else value >= lo)
        and (value < hi if hi_open else value <= hi)
        and math.isfinite(value)
    ):
        return float(value)  # a plain float inside the range: the front doors' fast path
    if isinstance(value, bool | np.bool_ | str | bytes) or np.ndim(value) != 0:
        raise ValueError(f"{name} = {reprlib.repr(value)} is not one real number; valid: a float")
    return float(check_range(name, value, lo, hi, lo_open=lo_open, hi_open=hi_open))


def check_flag(name, value):
    """Return ``value`` as a bool, or raise unless it is True or False (a string such as "False" is not)."""
    if not isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} = {reprlib.repr(value)} is not a bool; valid: True or False")
    return bool(value)


def check_max_steps(max_steps):
    """Step budget of an integration: a whole number in [1, MAX_STEPS_LIMIT]."""
    return check_count("max_steps", max_steps, 1, MAX_STEPS_LIMIT)


def check_positive(name, value):
    """Return ``value`` as a float array, or raise unless it is finite and > 0."""
    return check_range(name, value, 0.0, np.inf, lo_open=True, hi_open=True)


# Valid ranges of the dimensionless inputs: (lo, hi, lo_open, hi_open).  One home for the
# array checks below and for their scalar fast path ``plain_in``.
RANGES = {
    "eps": (0.0, 1.0, False, False),
    "xi": (0.0, 1.0, False, True),
    "alpha": (0.0, np.inf, False, True),
}
# Types the scalar fast path accepts as they are; anything else takes the full check.
PLAIN_FLOATS = (float, np.float64)
# The two restitution coefficients a target may be given in: Stronge's energetic eps, Newton's e_N.
RESTITUTIONS = ("energetic", "kinematic")


def check_restitution(restitution):
    """``restitution`` if it names one of ``RESTITUTIONS``; else a ``ValueError`` naming them."""
    if restitution not in RESTITUTIONS:
        raise ValueError(f"restitution = {restitution!r} is not one of {', '.join(map(repr, RESTITUTIONS))}")
    return restitution


def plain_in(name, value):
    """True if ``value`` is a plain float inside the range ``RANGES[name]`` (NaN is not).

    The scalar fast path of ``check_eps``, ``check_xi`` and ``check_alpha`` for users'
    one-contact-at-a-time loops (~0.2 us); on False the caller runs the full check, which
    words the error.
    """
    if type(value) not in PLAIN_FLOATS:
        return False
    lo, hi, lo_open, hi_open = RANGES[name]
    return (value > lo if lo_open else value >= lo) and (value < hi if hi_open else value <= hi)


def _check_named(name, value):
    lo, hi, lo_open, hi_open = RANGES[name]
    return check_range(name, value, lo, hi, lo_open=lo_open, hi_open=hi_open)


def check_eps(eps):
    """Restitution coefficient: 0 <= eps <= 1."""
    return _check_named("eps", eps)


def check_xi(xi):
    """Influence factor of the external load: 0 <= xi < 1."""
    return _check_named("xi", xi)


def check_alpha(alpha):
    """Hysteresis damping factor: alpha >= 0 and finite."""
    return _check_named("alpha", alpha)


# Floor of a relative tolerance set by double precision.
RTOL_FLOOR = 1e-15


def check_tolerances(rtol, atol):
    """Relative tolerance in [RTOL_FLOOR, 0.1], absolute tolerance in (0, 1]: one number each."""
    rtol = check_scalar("rtol", rtol, 0.0, 0.1, lo_open=True)
    atol = check_scalar("atol", atol, 0.0, 1.0, lo_open=True)
    if rtol < RTOL_FLOOR:
        raise ValueError(f"rtol = {rtol!r} is below the floor {RTOL_FLOOR} set by double precision")
    return float(rtol), float(atol)


def plain_integrator_settings(rtol, atol, max_steps):
    """True if plain ``rtol``, ``atol``, ``max_steps`` pass ``check_tolerances`` and ``check_max_steps``.

    The scalar fast path of those checks; on False the caller runs them in full.
    """
    return (
        type(rtol) in PLAIN_FLOATS
        and type(atol) in PLAIN_FLOATS
        and type(max_steps) is int
        and RTOL_FLOOR <= rtol <= 0.1
        and 0.0 < atol <= 1.0
        and 1 <= max_steps <= MAX_STEPS_LIMIT
    )
