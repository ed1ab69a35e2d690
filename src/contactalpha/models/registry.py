"""Registry of contact models: one list, ``REGISTRY``, of ``Model`` values with their capabilities.

A model maps a target restitution and the load factor ``xi`` to the damping of its contact law
(``Model.law``, a name in ``contactalpha.laws``): alpha for Hunt-Crossley, zeta for the
spring-dashpot and MuJoCo's soft contact, beta for Tsuji's damping.  Which restitution it takes,
its domain, whether it reaches eps = 0 and how it is evaluated are fields, never decided by name.
``MODELS`` is the view of the default law's models (Hunt-Crossley, n = 3/2), by name, that the
paper's studies iterate; ``ALL_MODELS`` has every model.  Use ``alpha(eps, xi, model=NAME)``.
"""

import numpy as np

from contactalpha.engine.exact import alpha_exact
from contactalpha.engine.table import EPS_MIN, XI_MAX, alpha_tabulated, scalar_lookup
from contactalpha.laws import DEFAULT_LAW
from contactalpha.validation import (
    PLAIN_FLOATS,
    FloatOrArray,
    RealLike,
    check_eps,
    check_xi,
)

from .closed_form import closed_form
from .engine_mappings import ENGINE_MAPPINGS
from .model import BOTH, Model
from .shen import eq25, shen_published, shen_refit


def hunt_crossley(eps, xi=0.0):
    """Hunt & Crossley (1975), J. Appl. Mech. 42: alpha = 3 (1 - eps) / 2.  Ignores xi."""
    return 1.5 * (1.0 - eps) + 0.0 * xi


def lankarani_nikravesh(eps, xi=0.0):
    """Lankarani & Nikravesh (1990), J. Mech. Des. 112: alpha = 3 (1 - eps^2) / 4.  Ignores xi."""
    return 0.75 * (1.0 - eps**2) + 0.0 * xi


def flores(eps, xi=0.0):
    """Flores et al. (2011), Mech. Mach. Theory 46: alpha = 8 (1 - eps) / (5 eps).  Ignores xi."""
    return 1.6 * (1.0 - eps) / eps + 0.0 * xi


def hu_guo(eps, xi=0.0):
    """Hu & Guo (2015), Mech. Mach. Theory 85; paper Eq. 25: alpha = 3 (1 - eps) / (2 eps).  Ignores xi."""
    return eq25(eps) + 0.0 * xi


def gonthier(eps, xi=0.0):
    """Gonthier et al. (2004), Multibody Syst. Dyn. 11: alpha = (1 - eps^2) / eps.  Ignores xi."""
    return (1.0 - eps**2) / eps + 0.0 * xi


def exact_unloaded(eps, xi=0.0):
    """Exact at xi = 0 (Carvalho & Martins 2019): ln((1+alpha)/(1-alpha eps)) = alpha (1+eps).  Ignores xi."""
    return alpha_exact(eps) + 0.0 * xi


def shen_zero_load(eps, xi=0.0):
    """Shen et al., Eq. 40, xi = 0 branch: alpha = 3 (1 - eps) / (2 eps^0.89).  Ignores xi."""
    return 1.5 * (1.0 - eps) / eps**0.89 + 0.0 * xi


def exact_tabulated(eps, xi):
    """Exact alpha(eps, xi) from the shipped spline table (``table.py``): ~1e-7 relative, formula speed.

    Domain 0.01 <= eps <= 1, 0 <= xi <= 0.99; outside it, use ``exact_solve``.
    """
    try:
        return alpha_tabulated(eps, xi)
    except ValueError as exc:
        if not _solvable_off_table(eps, xi):
            raise  # bad input or shapes: the hint would mislead
        raise ValueError(f"{exc} of the exact table; model='exact_solve' covers the rest") from None


def _solvable_off_table(eps, xi):
    """True when some valid target ``(eps, xi)`` lies outside the table only, so ``exact_solve`` covers it."""
    try:
        e, x = np.broadcast_arrays(check_eps(eps), check_xi(xi))
    except ValueError:
        return False  # not a table-domain error; the caller re-raises the original
    off = (e < EPS_MIN) | (x > XI_MAX)
    return bool(np.any(off & ~((e == 0.0) & (x == 0.0))))


def exact_surface(eps, xi):
    """Exact alpha(eps, xi): the root of Stronge's restitution, solved with the impact engine.

    Slow (one Newton solve per point, ~0.1 ms); ``contactalpha.alpha(...,
    model="exact")`` is the fast tabulated form of the same surface.
    """
    from contactalpha.engine.solver import solve_alpha

    sol = solve_alpha(eps, xi)
    _raise_unsolved(sol)
    return sol.alpha


def exact_surface_kinematic(e_n, xi):
    """Exact alpha for Newton's e_N, solved with the impact engine (``exact_surface`` for e_N)."""
    from contactalpha.engine.solver import solve_alpha

    sol = solve_alpha(e_n, xi, restitution="kinematic")
    _raise_unsolved(sol)
    return sol.alpha


def exact_tabulated_kinematic(e_n, xi):
    """Exact alpha for Newton's e_N from the shipped kinematic table (``engine/table.py``)."""
    try:
        return alpha_tabulated(e_n, xi, restitution="kinematic")
    except ValueError as exc:
        if not _solvable_off_table(e_n, xi):
            raise
        raise ValueError(f"{exc} of the kinematic table; model='exact_solve' covers the rest") from None


REGISTRY = [
    Model("hunt_crossley", "Hunt–Crossley", "Hunt & Crossley 1975", "3(1−ε)/2", False, hunt_crossley),
    Model(
        "lankarani_nikravesh",
        "Lankarani–Nikravesh",
        "Lankarani & Nikravesh 1990",
        "3(1−ε²)/4",
        False,
        lankarani_nikravesh,
    ),
    Model("flores", "Flores et al.", "Flores et al. 2011", "8(1−ε)/(5ε)", False, flores),
    Model("hu_guo", "Hu–Guo", "Hu & Guo 2015 (paper Eq. 25)", "3(1−ε)/(2ε)", False, hu_guo),
    Model("gonthier", "Gonthier et al.", "Gonthier et al. 2004", "(1−ε²)/ε", False, gonthier),
    Model(
        "shen_zero_load",
        "Shen et al., ξ = 0 branch",
        "Shen et al., Eq. 40",
        "3(1−ε)/(2ε^0.89)",
        False,
        shen_zero_load,
    ),
    Model(
        "exact_unloaded",
        "exact, ξ = 0",
        "Carvalho & Martins 2019",
        "ln((1+α)/(1−αε)) = α(1+ε)",
        False,
        exact_unloaded,
    ),
    Model(
        "exact_solve",
        "exact (solved)",
        "this package: root of Stronge's ε",
        "ε(α, ξ) = ε",
        True,
        exact_surface,
        restitutions=BOTH,
        handles_zero=True,
        kinematic_fn=exact_surface_kinematic,
        solver=True,
    ),
    Model(
        "exact",
        "exact",
        "this package: spline table of the solved surface",
        "table of ε(α, ξ) = ε, 0.01 ≤ ε ≤ 1, ξ ≤ 0.99",
        True,
        exact_tabulated,
        restitutions=BOTH,
        kinematic_fn=exact_tabulated_kinematic,
        validates=True,
        scalar_table=True,
    ),
    Model("shen_published", "Shen et al., Eq. 40", "Shen et al., Eq. 40", "Eq. 40", True, shen_published),
    Model("shen_refit", "Shen et al., refit", "Eq. 40 refit to this surface", "Eq. 40", True, shen_refit),
    Model(
        "closed_form",
        "closed form (exact at ξ = 0)",
        "this package, issue 13: models/closed_form.py",
        "(α_s^k + α_c^k)^(1/k), α_s = α₀(ε)·e^(…)",
        True,
        closed_form,
    ),
    *ENGINE_MAPPINGS,
]
ALL_MODELS = {m.name: m for m in REGISTRY}
# The default law's models: what the paper's studies and the advisor compare.
MODELS = {m.name: m for m in REGISTRY if m.law == DEFAULT_LAW}


def register(model):
    """Add or replace a model in the registry (used for the fitted Shen et al. models)."""
    ALL_MODELS[model.name] = model
    if model.law == DEFAULT_LAW:
        MODELS[model.name] = model


def contact_force(
    delta: RealLike,
    delta_dot: RealLike,
    approach_speed: RealLike,
    stiffness: RealLike,
    eps: RealLike,
    xi: RealLike,
    model: str = "exact",
    *,
    clip_tension: bool = False,
) -> FloatOrArray:
    """Hunt-Crossley contact force ``k delta^{3/2} (1 + alpha delta_dot / v_minus)`` (paper Eq. 41).

    Parameters
    ----------
    delta : array_like
        Penetration, m; no force where ``delta <= 0``.
    delta_dot : array_like
        Penetration rate, m/s (positive while compressing).
    approach_speed : float or array_like
        Approach speed of this impact, m/s (> 0).
    stiffness : float or array_like
        Hertz stiffness, N/m^1.5 (> 0).
    eps, xi : float or array_like
        Restitution coefficient and influence factor of this impact.
    model : str
        Name in ``MODELS`` that gives alpha.
    clip_tension : bool
        If True, negative (adhesive) forces late in restitution are set to 0.

    Returns
    -------
    force : float or ndarray, N
    """
    from contactalpha.validation import check_positive, check_range

    v0 = check_positive("approach_speed", approach_speed)
    kk = check_positive("stiffness", stiffness)
    # Any finite real penetration and rate: no force where delta <= 0.
    delta = check_range("delta", delta, -np.inf, np.inf, lo_open=True, hi_open=True)
    delta_dot = check_range("delta_dot", delta_dot, -np.inf, np.inf, lo_open=True, hi_open=True)
    a = alpha(eps, xi, model=model)
    d = np.maximum(delta, 0.0)
    f = kk * d * np.sqrt(d) * (1.0 + a * delta_dot / v0)
    if clip_tension:
        f = np.maximum(f, 0.0)
    return f[()] if np.ndim(f) == 0 else f


def alpha(
    eps: RealLike, xi: RealLike = 0.0, model: str = "exact", *, restitution: str = "energetic"
) -> FloatOrArray:
    """Damping from a named model: alpha for Hunt-Crossley, the damping of ``MODELS[model].law`` otherwise.

    Parameters
    ----------
    eps : array_like
        Restitution coefficient; 0 < eps <= 1 (0 only for models with ``handles_zero``).
        Stronge's energetic eps, or Newton's kinematic e_N (separation speed over
        approach speed) when ``restitution="kinematic"``.
    xi : array_like
        Influence factor of the load, 0 <= xi < 1; ignored by models whose
        ``uses_xi`` is False.
    model : str
        A key of ``ALL_MODELS``.
    restitution : {"energetic", "kinematic"}
        Which coefficient ``eps`` is; it must be one of the model's ``restitutions``
        (e_N = 0 holds for every damping past the separation boundary, so it has no inverse).

    Returns
    -------
    alpha : float or ndarray
    """
    if model == "exact" and type(eps) in PLAIN_FLOATS and type(xi) in PLAIN_FLOATS:
        # Scalar fast path: the packed table, no array checks; NaN (outside) takes the full path.
        fast = scalar_lookup(restitution)
        value = fast[0](eps, xi, fast[1])
        if value == value:
            return value
    found = ALL_MODELS.get(model) if isinstance(model, str) else None
    if found is None:
        raise ValueError(f"unknown model {model!r}; known models: {', '.join(sorted(ALL_MODELS))}")
    if restitution not in ("energetic", "kinematic"):
        raise ValueError(f"restitution = {restitution!r} is not one of 'energetic', 'kinematic'")
    if restitution not in found.restitutions:
        takes = " and ".join(_DEFINITIONS[r] for r in found.restitutions)
        others = [m.name for m in REGISTRY if m.law == found.law and restitution in m.restitutions]
        raise ValueError(
            f"model {model!r} is defined for {takes}; restitution={restitution!r} needs one of "
            f"{', '.join(map(repr, others))} (models of law {found.law!r})"
            + (" (or convert_restitution first)" if restitution == "kinematic" else "")
        )
    fn = found.kinematic_fn if restitution == "kinematic" and found.kinematic_fn is not None else found.fn
    if restitution == "kinematic" and np.any(np.asarray(eps) == 0.0) and found.law == DEFAULT_LAW:
        from contactalpha.engine.solver import no_kinematic_inverse

        raise no_kinematic_inverse()
    if found.validates:
        return fn(eps, xi)  # validates in one jitted pass: keeps formula speed
    e = check_eps(eps)
    x = check_xi(xi)
    if np.any(e == 0.0) and not found.handles_zero:
        raise ValueError(f"eps = 0.0 is outside the valid range (0.0, 1.0] of model {model!r}")
    with np.errstate(divide="ignore", invalid="ignore"):
        out = fn(e, x)
    out = np.asarray(out, dtype=float)
    return out[()] if out.ndim == 0 else out


_DEFINITIONS = {"energetic": "Stronge's energetic eps", "kinematic": "Newton's kinematic e_N"}


def _raise_unsolved(sol):
    if not np.all(sol.ok):
        bad = np.asarray(sol.status)[~np.asarray(sol.ok)]
        raise RuntimeError(
            f"alpha solve failed at {np.size(bad)} point(s): {sorted(set(np.atleast_1d(bad)))}"
        )
