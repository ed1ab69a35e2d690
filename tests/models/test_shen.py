"""Shen et al.'s closed form and its building blocks (shen.py): identities, oracles, bad input."""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from contactalpha import models, solve_alpha, trajectory
from contactalpha.models import shen

XI = np.array([0.0, 0.001, 0.05, 0.2, 0.5, 0.9])


def test_s1_at_zero_load_is_four_fifteenths():
    # u = x^{5/2}: s1(0) = (2/5) int_0^1 sqrt(1 - u) du = 4/15.
    assert shen.s1(0.0) == pytest.approx(4 / 15, rel=1e-12)


def test_contact_factor_is_sqrt_half_s2_eq33():
    for x in XI:
        r = x / (1 - x)
        s2, _ = quad(
            lambda u, r=r: u**1.5 * (1 - u**2.5 + r * (u - u**2.5)), 0, 1, epsabs=1e-14, epsrel=1e-13
        )
        assert shen.contact_factor(x) == pytest.approx(np.sqrt(0.5 * s2), rel=1e-12)


def test_s21_tracks_s1_within_one_percent_fig6():
    xi = np.linspace(0, 0.99, 100)
    rel = shen.s21(xi) / shen.s1(xi) - 1
    assert np.max(np.abs(rel)) < 0.01
    assert np.all(np.diff(shen.s1(xi)) > 0)  # compression damping grows with the load


def test_eq40_zero_load_branch_and_registry():
    eps = np.array([0.05, 0.3, 0.7, 0.95])
    np.testing.assert_allclose(shen.eq40(eps, 0.0), 1.5 * (1 - eps) / eps**0.89, rtol=1e-15)
    np.testing.assert_allclose(
        models.alpha(eps, 0.0, model="shen_published"), models.alpha(eps, 0.0, "shen_zero_load")
    )
    np.testing.assert_allclose(
        models.alpha(eps, 0.3, model="shen_published"), shen.eq40(eps, 0.3), rtol=1e-15
    )


def test_eq40_sigma_reading_written_out_from_the_paper():
    eps, xi = 0.3, 0.25
    S = np.sqrt((7 - 4 * xi) / (70 * (1 - xi)))
    eta = eps ** (0.86 + 2.6 * xi + xi**3.5 - 1.5 * eps * xi)
    lam = max(1 - (eps / xi**0.59) ** (1 + xi**0.3 * (1 - eps * (1 - xi))), 0.0)
    first = np.exp(-((eps + 1 - xi**0.05) ** 2) / (0.1568 * xi**0.9)) * (1 - eps) ** 6
    b = eps ** (xi**1.3) + 0.1 * xi - 0.97
    second = 0.47 * (1 - eps**2 - lam**2.5) / (S * eps**b * (eps**2 + eta * (1 - lam**2.5)))
    assert lam > 0  # the point is in the non-separation region: every factor counts
    assert shen.eq40(eps, xi, reading="sigma_a6") == pytest.approx(first + second, rel=1e-14)
    beta_first = np.exp(-((eps + 1 - xi**0.05) ** 2)) / (0.1568 * xi**0.9)
    assert shen.eq40(eps, xi, reading="beta_a0") == pytest.approx(beta_first + second, rel=1e-14)


def test_lambda_is_clipped_and_zero_without_load():
    eps = np.linspace(0.01, 1, 50)
    for x in XI:
        lam = shen.lambda_eq40(eps, x)
        assert np.all((lam >= 0) & (lam < 1))
    assert np.all(shen.lambda_eq40(eps, 0.0) == 0)
    assert shen.lambda_eq40(0.9, 0.1) == 0  # eps > xi^0.59: separation


@pytest.fixture(scope="module")
def solved():
    eps, xi = np.meshgrid([0.05, 0.2, 0.5, 0.8], [0.01, 0.2, 0.6], indexing="ij")
    sol = solve_alpha(eps, xi)
    assert np.all(sol.ok)
    return eps, xi, sol


def test_eq38_with_measured_ratios_reproduces_alpha(solved):
    eps, xi, sol = solved
    d = shen.dissipation(eps, xi, sol.alpha, sol.x_max, sol.x_end)
    np.testing.assert_allclose(shen.eq38(eps, xi, d.lam, d.eta_c, d.eta_r), sol.alpha, rtol=1e-9)
    # Eq. 27: eps^2 dE_c + dE_r = (1 - eps^2 - lambda^{5/2}) (elastic energy at x_m)
    np.testing.assert_allclose(
        eps**2 * d.d_c + d.d_r, (1 - eps**2 - d.lam**2.5) * 0.5 * sol.x_max**2.5, rtol=1e-10
    )


@pytest.mark.parametrize(("eps", "xi"), [(0.3, 0.0), (0.5, 0.2), (0.1, 0.6)])
def test_compression_work_identity_matches_trajectory_quadrature(eps, xi):
    sol = solve_alpha(eps, xi)
    path, res = trajectory(float(sol.alpha), xi, max_step=2e-4)
    quadrature = shen.compression_work_path(path, float(sol.alpha))
    identity = shen.dissipation(eps, xi, sol.alpha, res.x_max, res.x_end).d_c
    assert quadrature == pytest.approx(float(identity), rel=1e-5)


def test_damped_sa_is_below_undamped_s1(solved):
    eps, xi, sol = solved
    d = shen.dissipation(eps, xi, sol.alpha, sol.x_max, sol.x_end)
    assert np.all(d.s_a < shen.s1(xi))
    assert np.all(d.eta_c < 1.0) and np.all(d.eta_c > 0.5)


def test_shen_refit_uses_the_shipped_constants():
    # The file itself (read here, not through load_refit), and the model's alpha to the bit.
    shipped = Path(shen.__file__).parents[1] / "data" / shen.REFIT_FILE
    data = json.loads(shipped.read_text(encoding="utf-8"))
    assert shen.load_refit() == data
    assert set(data["constants"]) == set(shen.PUBLISHED)
    assert data["reading"] in shen.READINGS
    c = {**shen.PUBLISHED, **data["constants"]}
    assert c != shen.PUBLISHED  # the refit moved the constants: a model on PUBLISHED would differ
    eps = np.array([0.05, 0.4, 0.9])
    refit = models.alpha(eps, 0.3, model="shen_refit")
    assert np.array_equal(refit, shen.eq40(eps, 0.3, c, data["reading"]))
    assert not np.array_equal(refit, models.alpha(eps, 0.3, model="shen_published"))
    assert np.array_equal(
        models.alpha(eps, 0.0, model="shen_refit"), shen.zero_load(eps, data["zero_load_exp"])
    )


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: shen.eq40(1.5, 0.2), r"eps = 1\.5 is outside the valid range \[0\.0, 1\.0\]"),
        (lambda: shen.eq40(0.0, 0.2), r"eps = 0\.0 is outside the valid range \(0\.0, 1\.0\]"),
        (lambda: shen.eq40(0.5, 1.0), r"xi = 1\.0 is outside the valid range \[0\.0, 1\.0\)"),
        (lambda: shen.eq40(0.5, 0.2, reading="sigma"), r"reading = 'sigma' is not one of the valid readings"),
        (lambda: shen.s1(-0.1), r"xi = -0\.1 is outside the valid range"),
    ],
)
def test_bad_input_names_value_and_range(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_eq26_peak_alpha_restitutes_far_above_region_one():
    # Eq. 26 at xi = 0.2 gives alpha = exp(-tau^2/sigma)/beta = 8.77 at eps = 0 (the paper's region I).
    # Stronge's eps of that alpha, by the engine and by SciPy's integrator, is about 0.25, not ~0:
    # the paper's region-I alpha and our surface disagree (results/fit/comparison.md, Eq. 26).
    from contactalpha import restitution
    from contactalpha.baselines.reference import impact_scipy

    peak = shen.eq26(0.0, **shen.EQ26_PUBLISHED)
    assert peak == pytest.approx(np.exp(-(0.01**2) / 0.011) / 0.113, rel=1e-14)
    eps = restitution(peak, 0.2)
    assert eps == pytest.approx(impact_scipy(peak, 0.2).eps, abs=1e-8)
    assert eps > 0.2


def test_each_paper_formula_is_the_one_the_models_use():
    eps = np.array([0.05, 0.3, 0.7, 0.99])
    # Hu & Guo's model is Eq. 25 to the bit; Eq. 39's first term is Eq. 26 times (1 - eps)^a.
    assert np.array_equal(models.alpha(eps, 0.4, model="hu_guo"), shen.eq25(eps))
    np.testing.assert_allclose(
        shen.first_term(eps, 0.1, 0.2, 0.3, 6.0), shen.eq26(eps, 0.1, 0.2, 0.3) * (1 - eps) ** 6
    )
    # The printed digits of Eq. 40's first term: tau = 1 - xi^0.05, width 0.1568 xi^0.9.
    assert shen.printed_tau(0.2) == 1.0 - 0.2**0.05
    assert shen.printed_width(0.2) == 0.1568 * 0.2**0.9
    first, _ = shen.eq40_terms(eps, 0.2, reading="sigma_a6")
    expected = shen.first_term(eps, 1.0 - 0.2**0.05, 0.1568 * 0.2**0.9, shen.PUBLISHED["beta"], 6.0)
    assert np.array_equal(first, expected)


def test_unknown_reading_is_refused_by_name():
    with pytest.raises(ValueError, match="sigma_a6"):
        shen.check_reading("sigma_a7")


# Points of the gradient tests: both sides of lambda's clip at 0, the ridge's small xi, eps near 1.
GRAD_EPS, GRAD_XI = (
    g.ravel()
    for g in np.meshgrid(
        np.linspace(0.02, 0.98, 17), np.r_[1e-5, 1e-3, 0.03, 0.2, 0.5, 0.8, 0.97], indexing="ij"
    )
)


def _central(f, x, h):
    """Fourth-order central difference of f at x with step h."""
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)


@pytest.mark.parametrize("reading", sorted(shen.READINGS))
def test_eq40_gradient_is_the_derivative_of_eq40_terms(reading):
    c = {**shen.PUBLISHED, "beta": 0.002, "a": 9.0, "lam_xi_pow": -0.5}  # a refit-like point
    names = shen.reading_constants(reading)
    value, jac = shen.eq40_gradient(GRAD_EPS, GRAD_XI, c, reading, names)
    first, second = shen.eq40_terms(GRAD_EPS, GRAD_XI, c, reading)
    # the jitted value is Eq. 40 to rounding (its powers go through exp and log)
    np.testing.assert_allclose(value, first + second, rtol=1e-11)
    assert jac.shape == (GRAD_EPS.size, len(names)) and np.all(np.isfinite(jac))
    for j, name in enumerate(names):
        h = 1e-5 * max(1.0, abs(c[name]))
        fd = _central(
            lambda v, n=name: np.add(*shen.eq40_terms(GRAD_EPS, GRAD_XI, {**c, n: v}, reading)), c[name], h
        )
        # relative to the derivative, or to alpha where the derivative is ~0 (rounding of the difference)
        np.testing.assert_array_less(np.abs(jac[:, j] - fd), 1e-4 * np.abs(fd) + 1e-7 * np.abs(value), name)
    assert np.isfinite(jac).all()


def test_eq40_gradient_names_columns_and_refuses_unknown_constants():
    _, jac = shen.eq40_gradient(GRAD_EPS, GRAD_XI, names=["a", "beta"], reading="beta_a0")
    assert np.all(jac == 0.0)  # neither enters Eq. 40 under beta_a0
    with pytest.raises(ValueError, match=r"constants \['gamma'\] are not constants of Eq\. 40"):
        shen.eq40_gradient(GRAD_EPS, GRAD_XI, names=["gamma"])


def test_eq39_gradient_is_the_derivative_of_eq39():
    lam = np.clip(1.0 - GRAD_EPS / GRAD_XI**0.6, 0.0, None)  # zeros and values inside (0, 1)
    args = {"tau": -0.1, "sigma": 0.05, "beta": 0.01, "a": 6.0, "b": -0.8, "eta_r": 1.3, "energy_coef": 0.47}
    value, grad = shen.eq39_gradient(GRAD_EPS, GRAD_XI, lam=lam, eta_c=1.0, **args)
    assert np.array_equal(value, shen.eq39(GRAD_EPS, GRAD_XI, lam=lam, eta_c=1.0, **args))
    for name, x in args.items():
        fd = _central(
            lambda v, n=name: shen.eq39(GRAD_EPS, GRAD_XI, lam=lam, eta_c=1.0, **{**args, n: v}), x, 1e-5
        )
        np.testing.assert_allclose(grad[name], fd, rtol=1e-5, atol=1e-8 * np.max(np.abs(value)), err_msg=name)
    # lambda: only where it is inside (0, 1); its clip at 0 has zero slope
    live = lam > 0
    with np.errstate(invalid="ignore"):  # lambda - 2h < 0 at the clipped points, not compared
        fd = _central(lambda v: shen.eq39(GRAD_EPS, GRAD_XI, lam=v, eta_c=1.0, **args), lam, 1e-6)
    np.testing.assert_allclose(grad["lam"][live], fd[live], rtol=1e-5, atol=1e-8 * np.max(np.abs(value)))
    assert np.all(grad["lam"][~live] == 0.0)
