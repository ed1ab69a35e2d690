"""Hertz stiffness ``k`` of two elastic bodies in contact, from their moduli, Poisson ratios and radii.

Hertz's law for two bodies of Young's moduli ``E_i``, Poisson ratios ``nu_i`` and radii of
curvature ``R_i`` at the contact point (K. L. Johnson, *Contact Mechanics*, 1985, Sect. 4.2):

    f = k delta^{3/2},   k = (4/3) E* sqrt(R*),
    1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2,    1/R* = 1/R_1 + 1/R_2.

A flat body (a half space) has ``R_2 = inf``; a rigid one ``E_2 = inf``.  ``k`` is the
``stiffness`` that ``contact_parameters`` takes.  Engines spell it in their own conventions
(``engine_conventions``): OpenSim's per-geometry ``stiffness`` is not ``E`` nor ``E*``.
"""

import math
import sys

from contactalpha.validation import check_positive, check_range

# Natural logarithms of the smallest normal and the largest double: k must lie between them.
LOG_FLOAT_RANGE = (math.log(sys.float_info.min), math.log(sys.float_info.max))
# Poisson's ratio of an isotropic elastic material lies in (-1, 1/2].
POISSON_RANGE = (-1.0, 0.5)


def effective_modulus(modulus: float, poisson: float, modulus_2: float, poisson_2: float) -> float:
    """``E*`` of two bodies (Pa): ``1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2``."""
    log_e_star = _log_effective_modulus(modulus, poisson, modulus_2, poisson_2)
    compliance = sum((1.0 - nu * nu) / e for e, nu in ((modulus, poisson), (modulus_2, poisson_2)))
    return 1.0 / compliance if 0.0 < compliance < math.inf else math.exp(log_e_star)


def _log_effective_modulus(modulus, poisson, modulus_2, poisson_2):
    """``ln E*``, summed in logarithms: a tiny modulus would overflow the plain compliance."""
    logs = []
    for name, e, nu in (("modulus", modulus, poisson), ("modulus_2", modulus_2, poisson_2)):
        e = float(check_positive(name, e)) if e != math.inf else math.inf
        nu = float(check_range(f"poisson{name[len('modulus') :]}", nu, *POISSON_RANGE, lo_open=True))
        if e != math.inf:
            logs.append(math.log1p(-nu * nu) - math.log(e))
    if not logs:
        raise ValueError(
            f"modulus = {modulus!r} and modulus_2 = {modulus_2!r}: two rigid bodies have no Hertz contact; "
            "give a finite modulus"
        )
    top = max(logs)
    return -(top + math.log(sum(math.exp(x - top) for x in logs)))


def effective_radius(radius: float, radius_2: float = math.inf) -> float:
    """``R*`` of two convex bodies (m): ``1/R* = 1/R_1 + 1/R_2`` (``inf`` for a flat)."""
    inverse = 0.0
    for name, r in (("radius", radius), ("radius_2", radius_2)):
        if r != math.inf:
            inverse += 1.0 / float(check_positive(name, r))
    if inverse == 0.0:
        raise ValueError("radius = inf and radius_2 = inf: two flats have no Hertz contact; give a radius")
    return 1.0 / inverse


def hertz_stiffness(
    modulus: float,
    poisson: float,
    radius: float,
    *,
    modulus_2: float | None = None,
    poisson_2: float | None = None,
    radius_2: float = math.inf,
) -> float:
    """Hertz stiffness ``k = (4/3) E* sqrt(R*)`` (N/m^1.5) of two bodies.

    Parameters
    ----------
    modulus : float
        Young's modulus E_1 of the first body, Pa (> 0).
    poisson : float
        Its Poisson ratio nu_1, in (-1, 0.5].
    radius : float
        Its radius of curvature at the contact R_1, m (> 0; ``inf`` for a flat).
    modulus_2, poisson_2 : float, optional
        The second body's; default the first body's (the same material).  ``modulus_2 = inf``
        for a rigid body.
    radius_2 : float
        The second body's radius, m; default ``inf``: a flat (a sphere on a half space).

    Returns
    -------
    float
        ``k`` for ``contact_parameters(..., stiffness=k)``.

    Raises
    ------
    ValueError
        Naming the value and its valid range.

    Examples
    --------
    A steel ball of radius 1 cm on a steel plate (E = 210 GPa, nu = 0.3):

    >>> round(hertz_stiffness(210e9, 0.3, 0.01) / 1e9, 3)
    15.385
    """
    modulus_2 = modulus if modulus_2 is None else modulus_2
    poisson_2 = poisson if poisson_2 is None else poisson_2
    # In logarithms: E* or R* may leave double precision although k does not.
    log_e_star = _log_effective_modulus(modulus, poisson, modulus_2, poisson_2)
    r_star = effective_radius(radius, radius_2)
    log_k = math.log(4.0 / 3.0) + log_e_star + 0.5 * math.log(r_star)
    if not LOG_FLOAT_RANGE[0] < log_k < LOG_FLOAT_RANGE[1]:
        raise ValueError(
            f"hertz stiffness of modulus = {modulus!r}, modulus_2 = {modulus_2!r}, radius = {radius!r}, "
            f"radius_2 = {radius_2!r} is e^{log_k:.6g}: outside double precision (1e-308 to 1e308 N/m^1.5)"
        )
    e_star = effective_modulus(modulus, poisson, modulus_2, poisson_2)
    k = 4.0 / 3.0 * e_star * math.sqrt(r_star)  # the plain product where nothing leaves the normal range
    return k if min(e_star, r_star, k) >= sys.float_info.min and k < math.inf else math.exp(log_k)
