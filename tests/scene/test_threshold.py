"""The critical approach speed from the exact separation boundary, and its compact fit."""

import re

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.reference import impact_scipy
from contactalpha.engine.scaling import influence_factor, influence_from_scaled_load
from contactalpha.engine.solver import solve_alpha
from contactalpha.scene import threshold as th

BALL = {"mass": 0.5, "stiffness": 1.4e8}


def test_critical_speed_of_the_science_check():
    # docs: exact alpha, eps = 0.5, m = 0.5 kg, k = 1.4e8, a = 129.81 -> separate above ~0.364 m/s
    v = th.critical_speed(0.5, accel=129.81, **BALL)
    assert v == pytest.approx(0.364, abs=5e-4)


@pytest.mark.parametrize("eps", [0.1, 0.5, 0.9])
def test_exact_alpha_separates_above_and_not_below(eps):
    v = th.critical_speed(eps, accel=129.81, **BALL)
    states = []
    for factor in (1.001, 0.999):
        xi = influence_factor(BALL["mass"], BALL["stiffness"], v * factor, 129.81)
        states.append(str(solve_alpha(eps, xi).state))
    assert states == ["separation", "nonseparation"]


def _scipy_gap(alpha, A):
    r = impact_scipy(alpha, float(influence_from_scaled_load(A)))
    gap = -(r.v_end**2) / (2 * A) if r.state == "separation" else r.x_end
    return gap, r.eps, r.state


@pytest.mark.parametrize("eps", [0.2, 0.5])
def test_boundary_load_checked_by_an_independent_integrator(eps):
    # At A_b(eps), SciPy's own impacts around alpha_b put the boundary (end gap = 0) at eps to 1e-9,
    # so v_crit ~ A_b^(-5/6) is good to ~5/6 * (dlnA/dln eps) * 1e-9 / eps < 1e-8 relative.
    A_b, status = th.boundary_load(eps)
    assert status == "ok"
    alpha_b, eps_b, code = th.boundary_point(A_b)
    assert code == 0 and eps_b == pytest.approx(eps, abs=1e-12)
    d = alpha_b * 1e-3 * th.STENCIL
    rows = [_scipy_gap(alpha_b + x, A_b) for x in d]
    assert [r[2] for r in rows] == ["separation", "separation", "nonseparation", "nonseparation"]
    root = [
        r for r in np.roots(np.polyfit(d, [r[0] for r in rows], 3)) if np.isreal(r) and d[1] < r.real < d[2]
    ]
    eps_scipy = np.polyval(np.polyfit(d, [r[1] for r in rows], 3), root[0].real)
    assert abs(eps_scipy - eps) < 1e-9


def test_fit_is_good_to_1e3_with_six_constants():
    assert len(th.BOUNDARY_FIT) == 6
    lo, hi = th.BOUNDARY_FIT_DOMAIN
    for eps in (lo, 0.05, 0.3, 0.6, 0.85, 0.99, hi):
        A_b, status = th.boundary_load(eps)
        assert status == "ok"
        assert abs(th.boundary_load_fit(eps) / A_b - 1) < th.BOUNDARY_FIT_RTOL


def test_fit_refits_to_the_shipped_constants():
    A = np.geomspace(1e-4, 1e2, 24)
    eps_b = np.array([th.boundary_point(a)[1] for a in A])
    coef = th.fit_boundary(eps_b, A)
    e = np.linspace(0.02, 0.98, 9)
    assert np.allclose(np.polyval(coef, e), np.polyval(th.BOUNDARY_FIT, e), atol=2e-3)


def test_speed_scales_as_the_load():
    v1 = th.critical_speed(0.7, 0.5, 1.4e8, 10.0)
    # A ~ a m^0.4 k^-0.4 v^-1.2: doubling a at fixed A multiplies v by 2^(5/6), m by 2^(1/3).
    assert th.critical_speed(0.7, 0.5, 1.4e8, 20.0) == pytest.approx(v1 * 2 ** (5 / 6), rel=1e-12)
    assert th.critical_speed(0.7, 1.0, 1.4e8, 10.0) == pytest.approx(v1 * 2 ** (1 / 3), rel=1e-12)
    assert th.critical_speed_fit(0.7, 0.5, 1.4e8, 10.0) == pytest.approx(v1, rel=1e-3)


def test_elastic_contact_always_separates_and_bad_input_raises():
    assert th.critical_speed(1.0, 0.5, 1.4e8, 9.81) == 0.0
    for bad in ({"eps": 0.0}, {"eps": 1.2}, {"eps": np.nan}, {"mass": -1.0}, {"accel": 0.0}):
        args = {"eps": 0.5, "mass": 0.5, "stiffness": 1.4e8, "accel": 9.81} | bad
        with pytest.raises(ValueError, match=next(iter(bad))):
            th.critical_speed(**args)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"max_steps": None}, "max_steps = None is not a number"),
        ({"max_steps": 0}, "max_steps = 0.0 is outside the valid range"),
        ({"max_steps": -5}, "max_steps = -5.0 is outside the valid range"),
        ({"max_steps": 10.5}, "max_steps = 10.5 is not one whole number"),
        ({"rtol": 0}, "rtol = 0.0 is outside the valid range"),
        ({"rtol": -1e-12}, "rtol = -1e-12 is outside the valid range"),
        ({"rtol": 1.0}, "rtol = 1.0 is outside the valid range"),
        ({"atol": float("nan")}, "atol = nan is outside the valid range"),
    ],
)
def test_critical_speed_checks_its_integrator_settings(kwargs, message):
    """Issue 29, N5: None raised numba's TypingError, 0/-5/10.5 gave NaN, rtol 0 or 1 was taken."""
    with pytest.raises(ValueError, match=re.escape(message)):
        ca.critical_speed(0.5, 0.5, 1.4e8, 9.81, **kwargs)


@pytest.mark.parametrize("eps", [1e-5, 1e-6])
def test_critical_speed_refuses_restitutions_below_its_domain_at_once(eps, recwarn):
    """eps = 1e-6 gave NaN with a divide-by-zero warning, 1e-5 took 81 s: both are below 1e-4."""
    with pytest.raises(
        ValueError, match=re.escape(f"eps = {eps!r} is outside the valid range [0.0001, 1.0]")
    ):
        ca.critical_speed(eps, 0.5, 1.4e8, 9.81)
    assert len(recwarn) == 0


@pytest.mark.parametrize("eps", [0.3, 0.9])
def test_critical_speed_separates_the_end_states_by_a_route_without_speed_for_load(eps):
    """Issue 29, planted bug: speed_for_load x (1 + 1e-4) passed, every critical-speed path shares it.

    Here xi comes from influence_factor at speeds 2e-5 either side of v_crit, alpha from the solver,
    and the end state from SciPy's DOP853: it separates just above v_crit and not just below.
    """
    m, k, a = 0.5, 1.4e8, 9.81
    v = ca.critical_speed(eps, m, k, a)
    states = {}
    for side, factor in (("above", 1 + 2e-5), ("below", 1 - 2e-5)):
        xi = influence_factor(m, k, v * factor, a)
        alpha = solve_alpha(eps, xi).alpha
        states[side] = impact_scipy(alpha, xi, rtol=1e-13, atol=1e-16).state
    assert states == {"above": "separation", "below": "nonseparation"}
