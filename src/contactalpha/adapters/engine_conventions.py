"""Our damping factor alpha in the parameters of real multibody engines (pure formulas, no engine).

Every engine below applies the paper's contact law ``f = k delta^{3/2} (1 + alpha delta_dot /
v_minus)`` (Eq. 23, ``mu = alpha k / v_minus``) under its own names and units.  The formulas come
from each engine's documentation and source; the in-engine checks (a static penetration for the
stiffness, an impact for the damping) are in ``contactalpha.adapters``.

**Simbody, through OpenSim's** ``HuntCrossleyForce`` (Simbody ``HuntCrossleyForce.h`` and
``HuntCrossleyForceImpl.h``).  Each contact geometry ``i`` carries a ``stiffness`` ``E_i``, the
plane-strain modulus in Pa, and a ``dissipation`` ``c_i`` in s/m.  For one contact the engine
uses

    E = (E_1^{-2/3} + E_2^{-2/3})^{-3/2},   s_1 = E_2^{2/3} / (E_1^{2/3} + E_2^{2/3}),
    c = s_1 c_1 + (1 - s_1) c_2,            R = R_1 R_2 / (R_1 + R_2),
    f = (4/3) sqrt(R) E delta^{3/2} (1 + (3/2) c delta_dot).

A half space has ``R_2 = inf``, so ``R`` is the sphere's radius.  With both geometries given the
same parameters (one ``ContactParameters`` holding both, OpenSim's usual set-up) ``E = E_i /
2^{3/2}`` and ``c = c_i``, so

    k = (4/3) sqrt(R) E_i / 2^{3/2}   <=>   E_i = 3 k / sqrt(2 R),
    alpha = (3/2) c v_minus            <=>   c = 2 alpha / (3 v_minus).

``c`` is fixed in the engine while alpha is per impact: an engine run must reset ``c`` whenever
the approach speed changes.  The engine's own reading of a restitution ``eps`` is Hunt and
Crossley's ``c = (1 - eps) / v_minus`` (alpha = 3(1 - eps)/2).

**Exudyn's** ``ObjectContactSphereSphere`` (its item documentation and
``CObjectContactSphereSphere.cpp``), with ``contactStiffnessExponent`` 1.5 and
``contactStiffness`` ``k_c`` = ``k`` (N/m^1.5; no geometry enters).  Its impact models add
``lambda delta^{3/2} v_gap`` with the gap velocity ``v_gap = -delta_dot`` and

    lambda = -(k / v_hat) g(e_res),    v_hat = max(minimumImpactVelocity, recorded impact speed),
    impactModel 1 (Hunt-Crossley):     g(e) = (3/2)(1 - e),
    impactModel 2 (Carvalho-Martins for e > 1/3, Gonthier et al. below):
                                       g(e) = (3/2)(1 - e)(11 - e)/(1 + 9 e)  or  (1 - e^2)/e,

so ``alpha = g(e_res) v_minus / v_hat``.  With ``v_hat = v_minus`` our alpha is delivered by the
``restitutionCoefficient`` ``e_res = g^{-1}(alpha)``: impactModel 2 covers every alpha > 0 (g
falls from inf to 0 on (0, 1], continuous at 1/3 where both branches give 8/3), impactModel 1 only
alpha < 3/2.  ``contactDamping`` must stay 0: it adds a *linear* damper, not Hunt-Crossley's.
"""

import math

import numpy as np

from contactalpha.validation import PLAIN_FLOATS, check_alpha, check_positive, check_range

# Restitution at which Exudyn's impactModel 2 switches from Gonthier et al. to Carvalho-Martins.
EXUDYN_SWITCH = 1.0 / 3.0
# Exudyn's impact models that have a restitution -> damping mapping.
EXUDYN_IMPACT_MODELS = (1, 2)


def _plain(value, lo):
    """True for a plain finite float >= ``lo``: the scalar fast paths' whole check."""
    return type(value) in PLAIN_FLOATS and lo <= value < math.inf


def _out(arr):
    arr = np.asarray(arr, dtype=float)
    return float(arr) if arr.ndim == 0 else arr


def opensim_stiffness(stiffness, radius):
    """OpenSim ``stiffness`` (Pa) of each of two geometries that together give Hertz ``stiffness``.

    Parameters
    ----------
    stiffness : float or array
        Hertz stiffness k of the contact, N/m^1.5 (> 0).
    radius : float or array
        Radius R of the sphere that meets a half space, m (> 0).

    Returns
    -------
    float or ndarray
        ``E_i = 3 k / sqrt(2 R)``, to give both the sphere and the half space.
    """
    return opensim_stiffness_unchecked(
        check_positive("stiffness", stiffness), check_positive("radius", radius)
    )


def opensim_stiffness_unchecked(stiffness, radius):
    """``opensim_stiffness`` of inputs already checked (the front doors'): for the inner layers."""
    k, r = np.asarray(stiffness, dtype=float), np.asarray(radius, dtype=float)
    return _out(3.0 * k / np.sqrt(2.0 * r))


def opensim_hertz_stiffness(stiffness_1, stiffness_2, radius_1, radius_2=np.inf):
    """Hertz stiffness k (N/m^1.5) that Simbody builds from two geometries' ``stiffness`` (Pa).

    ``radius_2 = inf`` is a half space.  The inverse of ``opensim_stiffness`` for equal stiffnesses.
    """
    e1 = check_positive("stiffness_1", stiffness_1)
    e2 = check_positive("stiffness_2", stiffness_2)
    r1 = check_positive("radius_1", radius_1)
    r2 = np.asarray(radius_2, dtype=float)
    half_space = np.isposinf(r2)
    r2 = np.where(half_space, 1.0, check_positive("radius_2", np.where(half_space, 1.0, r2)))
    e = (e1 ** (-2.0 / 3.0) + e2 ** (-2.0 / 3.0)) ** -1.5
    r = np.where(half_space, r1, r1 * r2 / (r1 + r2))
    return _out(4.0 / 3.0 * np.sqrt(r) * e)


def opensim_dissipation(alpha, approach_speed):
    """OpenSim/Simbody ``dissipation`` c (s/m) for damping factor ``alpha`` at ``approach_speed`` (m/s).

    ``c = 2 alpha / (3 v_minus)``: valid for the one impact with that approach speed.
    """
    if _plain(alpha, 0.0) and _plain(approach_speed, 0.0) and approach_speed > 0.0:
        return 2.0 * alpha / (3.0 * approach_speed)  # scalar fast path, same arithmetic
    return opensim_dissipation_unchecked(check_alpha(alpha), check_positive("approach_speed", approach_speed))


def opensim_dissipation_unchecked(alpha, approach_speed):
    """``opensim_dissipation`` of inputs already checked (the front doors'): for the inner layers."""
    a, v = np.asarray(alpha, dtype=float), np.asarray(approach_speed, dtype=float)
    return _out(2.0 * a / (3.0 * v))


def opensim_alpha(dissipation, approach_speed):
    """Damping factor that a dissipation c (s/m) gives at ``approach_speed``: ``(3/2) c v_minus``."""
    c = check_range("dissipation", dissipation, 0.0, np.inf, hi_open=True)
    v = check_positive("approach_speed", approach_speed)
    return _out(1.5 * c * v)


def exudyn_alpha(restitution, impact_model=2):
    """Damping factor ``g(e_res)`` of Exudyn's ``impactModel`` 1 or 2, when it sees the true approach speed.

    Parameters
    ----------
    restitution : float or array
        Exudyn's ``restitutionCoefficient``, in (0, 1].
    impact_model : {1, 2}
        1: Hunt-Crossley, ``3(1-e)/2``; 2: Carvalho-Martins ``3(1-e)(11-e)/(2(1+9e))`` for
        ``e > 1/3``, Gonthier et al. ``(1-e^2)/e`` below.
    """
    _check_model(impact_model)
    e = check_range("restitution", restitution, 0.0, 1.0, lo_open=True)
    if impact_model == 1:
        return _out(1.5 * (1.0 - e))
    cm = 1.5 * (1.0 - e) * (11.0 - e) / (1.0 + 9.0 * e)
    return _out(np.where(e > EXUDYN_SWITCH, cm, (1.0 - e * e) / e))


def exudyn_restitution_input(alpha, impact_model=2):
    """Exudyn ``restitutionCoefficient`` whose built-in mapping gives damping factor ``alpha``.

    The inverse of ``exudyn_alpha``: for impactModel 2, ``e = (sqrt(alpha^2 + 4) - alpha)/2`` when
    ``alpha >= 8/3`` (Gonthier branch), else the root in (1/3, 1] of
    ``3 e^2 - (36 + 18 alpha) e + 33 - 2 alpha = 0``; for impactModel 1, ``e = 1 - 2 alpha/3``.

    Raises
    ------
    ValueError
        For ``alpha`` outside [0, inf) (model 2) or [0, 3/2) (model 1, whose restitution must
        stay > 0).
    """
    if impact_model == 2 and _plain(alpha, 0.0):
        # Scalar fast path: the same expressions in floats (sqrt is correctly rounded in both).
        gonthier, cm = _model2_branches(alpha, math.sqrt, max)
        return gonthier if alpha >= 8.0 / 3.0 else cm
    _check_model(impact_model)
    if impact_model == 1:
        a = check_range("alpha", alpha, 0.0, 1.5, hi_open=True)
        return _out(1.0 - 2.0 * a / 3.0)
    a = check_alpha(alpha)
    gonthier, cm = _model2_branches(a, np.sqrt, np.maximum)
    return _out(np.where(a >= 8.0 / 3.0, gonthier, cm))


def _model2_branches(a, sqrt, maximum):
    """Restitution input of Exudyn's impactModel 2 on its Gonthier and its Carvalho-Martins branch.

    ``sqrt``, ``maximum``: numpy's for arrays, math's and ``max`` for a float.
    """
    b = 36.0 + 18.0 * a
    # The smaller root, written without cancellation: (b - sqrt(b^2 - 4ac)) / 6 = 2c' / (b + sqrt(...)).
    c0 = 33.0 - 2.0 * a
    return 2.0 / (a + sqrt(a * a + 4.0)), 2.0 * c0 / (b + sqrt(maximum(b * b - 12.0 * c0, 0.0)))


def _check_model(impact_model):
    if impact_model not in EXUDYN_IMPACT_MODELS:
        raise ValueError(
            f"impact_model = {impact_model!r} is outside the valid choices {EXUDYN_IMPACT_MODELS}"
        )
