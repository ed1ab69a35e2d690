"""Newton's kinematic e_N beside Stronge's eps: the impact, the identity between them, the solver."""

import numpy as np
import pytest
from scipy.integrate import simpson

import contactalpha as ca
from contactalpha.baselines.reference import impact_scipy
from contactalpha.engine.boundary import separation_boundary


@pytest.mark.parametrize("alpha, xi", [(0.5, 0.2), (0.003, 0.95), (1.5, 0.3), (0.01, 0.6)])
def test_identity_at_separation_against_quadrature_of_contact_work(alpha, xi):
    # eps^2 = (e_N^2/2 + A x_m) / (1/2 + A x_m): eps from the work of the contact force
    # (Stronge's definition, by quadrature), e_N from the SciPy oracle's exit speed.
    path, r = ca.trajectory(alpha, xi, max_step=1e-4, max_rows=200_000)
    assert r.state == "separation"
    t, x, v = path.T
    F = 1.25 * np.maximum(x, 0) ** 1.5 * (1 + alpha * v)
    m = int(np.argmin(abs(t - r.t_max)))
    eps_work = np.sqrt(-simpson(F[m:] * v[m:], x=t[m:]) / simpson(F[: m + 1] * v[: m + 1], x=t[: m + 1]))
    ref = impact_scipy(alpha, xi)
    e_n = -ref.v_end
    A = float(ca.scaled_load(xi))
    eps_identity = np.sqrt((0.5 * e_n**2 + A * ref.x_max) / (0.5 + A * ref.x_max))
    assert eps_identity == pytest.approx(eps_work, abs=1e-9)
    assert r.e_n == pytest.approx(e_n, rel=1e-9)
    if xi > 0:
        assert r.eps > r.e_n  # the load makes Stronge's coefficient the larger


@pytest.mark.parametrize(
    "alpha, xi, state",
    [
        (5.0, 0.2, "nonseparation"),
        (50.0, 0.2, "creep"),
        (500.0, 0.2, "no_restitution"),
        (0.1, 0.99, "nonseparation"),
    ],
)
def test_e_n_is_zero_without_separation(alpha, xi, state):
    r = ca.impact(alpha, xi)
    assert r.state == state
    assert r.e_n == 0.0
    assert r.eps > 0.0 or state == "no_restitution"


def test_unloaded_e_n_equals_eps():
    r = ca.impact(np.array([0.01, 0.5, 3.0, 40.0]), 0.0)
    np.testing.assert_allclose(r.e_n, r.eps, rtol=1e-12)


@pytest.mark.parametrize("xi", [0.05, 0.3, 0.857])
def test_e_n_falls_continuously_to_zero_at_the_boundary(xi):
    # Near alpha_b the exit speed goes like sqrt(alpha_b - alpha).  A grazing exit, where one
    # step passes x = 0 and turns v beyond it, once ended as 'nonseparation' at x < 0 with
    # e_N jumping from ~1e-2 to 0 (xi = 0.857).
    alpha_b, _, status = separation_boundary(xi)
    assert status == 0
    d = np.array([1e-10, 1e-8, 1e-6, 1e-4])
    below = ca.impact(alpha_b * (1 - d), xi)
    assert np.all(below.state == "separation")
    np.testing.assert_allclose(below.e_n[1:] / below.e_n[:-1], 10.0, rtol=2e-3)
    above = ca.impact(alpha_b * (1 + d), xi)
    assert np.all(above.state == "nonseparation")
    assert np.all(above.x_end > 0.0) and np.all(above.e_n == 0.0)


@pytest.mark.parametrize("xi", [0.0, 1e-6, 0.1, 0.5, 0.9, 0.99])
@pytest.mark.parametrize("e_n", [0.01, 0.2, 0.6, 0.95])
def test_kinematic_solve_round_trips(e_n, xi):
    s = ca.solve_alpha(e_n, xi, restitution="kinematic")
    assert s.ok and s.state == "separation"
    assert s.e_n_reached == pytest.approx(e_n, abs=1e-11)
    r = ca.impact(s.alpha, xi)
    assert r.e_n == pytest.approx(e_n, abs=1e-11)
    assert s.eps_reached == pytest.approx(r.eps, abs=1e-11)
    if xi == 0.0:
        assert s.alpha == ca.solve_alpha(e_n, 0.0).alpha  # e_N = eps without a load


def test_kinematic_alpha_tends_to_the_boundary():
    xi = 0.3
    alpha_b, _, _ = separation_boundary(xi)
    alphas = [ca.solve_alpha(e, xi, restitution="kinematic").alpha for e in (1e-2, 1e-3, 1e-4)]
    gaps = alpha_b - np.array(alphas)
    assert np.all(gaps > 0)
    np.testing.assert_allclose(gaps[1:] / gaps[:-1], 0.01, rtol=1e-2)  # alpha_b - alpha ~ e_N^2


def test_zero_kinematic_target_names_the_boundary():
    with pytest.raises(ValueError, match=r"e_N = 0.0 has no kinematic inverse.*alpha_b\(xi\)"):
        ca.solve_alpha(0.0, 0.3, restitution="kinematic")
    with pytest.raises(ValueError, match=r"e_N = 1.5 is outside"):
        ca.solve_alpha(1.5, 0.3, restitution="kinematic")
    with pytest.raises(ValueError, match="restitution = 'newton'"):
        ca.solve_alpha(0.5, 0.3, restitution="newton")


def test_scalar_fast_paths_give_the_array_paths_numbers():
    for alpha, xi in [(0.5, 0.3), (5.0, 0.2), (500.0, 0.2), (2.0, 0.0)]:
        s = ca.impact(alpha, xi)
        a = ca.impact(np.array([alpha]), np.array([xi]))
        for name in s.__dataclass_fields__:
            got, want = getattr(s, name), getattr(a, name)[0]
            assert got == want or (np.isnan(got) and np.isnan(want)), name
    for target, xi, kind in [(0.5, 0.3, "energetic"), (0.5, 0.3, "kinematic"), (0.2, 0.0, "energetic")]:
        s = ca.solve_alpha(target, xi, restitution=kind)
        a = ca.solve_alpha(np.array([target]), np.array([xi]), restitution=kind)
        for name in s.__dataclass_fields__:
            got, want = getattr(s, name), getattr(a, name)[0]
            assert got == want or (np.isnan(got) and np.isnan(want)), name
