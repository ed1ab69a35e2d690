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
        Passed to ``solve_alpha`` (``tol``, ``rtol``, ``atol``, ``max_steps``).

    Returns
    -------
    float or ndarray
        The other coefficient of the same impact: e_N = 0 for an eps that ends without
        separation; NaN where the solve failed (``solve_alpha`` says why).

    Raises
    ------
    ValueError
        For e_N = 0 (every eps up to the separation boundary's gives it) and for values or
        loads outside their ranges.
    """
    if to not in CONVERSIONS:
        raise ValueError(f"to = {to!r} is not one of {', '.join(map(repr, CONVERSIONS))}")
    if to == "kinematic":
        return solve_alpha(value, xi, **solver_options).e_n_reached
    if np.any(np.asarray(value) == 0.0):
        raise no_kinematic_inverse()
    return solve_alpha(value, xi, restitution="kinematic", **solver_options).eps_reached
