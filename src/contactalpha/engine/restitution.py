"""Stronge's energetic eps <-> Newton's kinematic e_N at one load, through the alpha they share.

At separation the two are tied by the energy identity of the scaled impact (paper Eq. 17 with
Eq. 24; docs/science.md), ``eps^2 = (e_N^2 / 2 + A x_m) / (1/2 + A x_m)``, so ``eps > e_N``
whenever the load ``A > 0``.  ``x_m`` depends on the damping, so the conversion solves for the
alpha that gives the coefficient it is handed and reads the other one off the same impact.
"""

from typing import Any

import numpy as np

from contactalpha.validation import FloatOrArray, RealLike

from .solver import no_kinematic_inverse, solve_alpha

# The two directions of a conversion, keyed by the coefficient asked for.
CONVERSIONS = ("kinematic", "energetic")
# The options of ``solve_alpha`` a conversion passes on (the definition is set by ``to``).
SOLVER_OPTIONS = ("tol", "rtol", "atol", "max_steps")


def convert_restitution(
    value: RealLike, xi: RealLike, to: str = "kinematic", **solver_options: Any
) -> FloatOrArray:
    """Convert a restitution coefficient between the energetic and the kinematic definition.

    Parameters
    ----------
    value : float or array_like
        Stronge's eps when ``to="kinematic"`` (0 <= eps <= 1), Newton's e_N when
        ``to="energetic"`` (0 < e_N <= 1).
    xi : float or array_like
        Influence factor of the load, 0 <= xi < 1; broadcast against ``value``.
    to : {"kinematic", "energetic"}
        The coefficient wanted.
    **solver_options
        Passed to ``solve_alpha``: ``tol``, ``rtol``, ``atol``, ``max_steps`` (any other raises).

    Returns
    -------
    float or ndarray
        The other coefficient of the same impact: e_N = 0 for an eps that ends without
        separation; NaN where the solve failed (``solve_alpha`` says why).

    Raises
    ------
    ValueError
        For e_N = 0 (every eps up to the separation boundary's gives it), for values or
        loads outside their ranges, and for a solver option not in ``SOLVER_OPTIONS``.
    """
    if to not in CONVERSIONS:
        raise ValueError(f"to = {to!r} is not one of {', '.join(map(repr, CONVERSIONS))}")
    unknown = sorted(set(solver_options) - set(SOLVER_OPTIONS))
    if unknown:
        raise ValueError(
            f"solver option(s) {', '.join(unknown)} not taken (the definition is set by to = {to!r}); "
            f"valid: {', '.join(SOLVER_OPTIONS)}"
        )
    if to == "kinematic":
        s = solve_alpha(value, xi, **solver_options)
        other = s.e_n_reached
    else:
        if np.any(np.asarray(value) == 0.0):
            raise no_kinematic_inverse()
        s = solve_alpha(value, xi, restitution="kinematic", **solver_options)
        other = s.eps_reached
    # A failed solve's last impact is not the impact asked for: NaN, never its coefficient.
    if np.ndim(other) == 0:
        return float(other) if s.ok else float("nan")
    return np.where(s.ok, other, np.nan)
