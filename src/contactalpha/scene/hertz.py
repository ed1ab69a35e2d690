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

from contactalpha.validation import check_positive, check_range

# Poisson's ratio of an isotropic elastic material lies in (-1, 1/2].
POISSON_RANGE = (-1.0, 0.5)


def effective_modulus(modulus: float, poisson: float, modulus_2: float, poisson_2: float) -> float:
    """``E*`` of two bodies (Pa): ``1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2``."""
    compliance = 0.0
    for name, e, nu in (("modulus", modulus, poisson), ("modulus_2", modulus_2, poisson_2)):
        e = float(check_positive(name, e)) if e != math.inf else math.inf
        nu = float(check_range(f"poisson{name[len('modulus') :]}", nu, *POISSON_RANGE, lo_open=True))
        compliance += (1.0 - nu * nu) / e
    return 1.0 / compliance


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
    e_star = effective_modulus(modulus, poisson, modulus_2, poisson_2)
    return 4.0 / 3.0 * e_star * math.sqrt(effective_radius(radius, radius_2))
