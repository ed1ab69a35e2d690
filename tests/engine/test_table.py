import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from numba import njit

import contactalpha as ca
from contactalpha.engine.table import (
    DEFAULT_FILE,
    DEGREE,
    EPS_MIN,
    TABLE_FORMAT_VERSION,
    XI_MAX,
    XI_SCALE,
    eta_of_xi,
    load_table,
)
from contactalpha.engine.table_build import save_table, xi_of_eta

ROOT = Path(__file__).resolve().parents[2]


def _random_points(n, seed):
    rng = np.random.default_rng(seed)
    eps = np.exp(rng.uniform(np.log(EPS_MIN), 0.0, n))
    # half log-uniform in xi to sample the ridge near xi -> 0+, half uniform
    xi = np.where(
        rng.random(n) < 0.5,
        np.exp(rng.uniform(np.log(1e-9), np.log(XI_MAX), n)),
        rng.uniform(0.0, XI_MAX, n),
    )
    return eps, xi


def test_exact_model_within_1e_6_of_solver_off_the_nodes():
    eps, xi = _random_points(3000, seed=20261122)
    ref = ca.solve_alpha(eps, xi, tol=1e-13, guess="formula")
    assert np.all(ref.ok)
    fast = ca.alpha(eps, xi, model="exact")
    rel = np.abs(fast / ref.alpha - 1.0)
    print(f"exact table: max rel err {rel.max():.2e}, median {np.median(rel):.1e} over {eps.size} points")
    assert rel.max() < 1e-6


def test_exact_model_on_the_zero_load_column_and_eps_one():
    eps = np.array([0.01, 0.0123, 0.5, 0.987654, 1.0])
    np.testing.assert_allclose(ca.alpha(eps, 0.0, model="exact")[:-1], ca.alpha_exact(eps[:-1]), rtol=1e-7)
    assert ca.alpha(1.0, 0.4, model="exact") == 0.0
    # near eps = 1, alpha ~ (1 - eps) / |deps/dalpha at 0|: the table's last column
    e = 1 - 1e-6
    assert ca.alpha(e, 0.4, model="exact") == pytest.approx(ca.solve_alpha(e, 0.4).alpha, rel=1e-6)


def test_jitted_scalar_form_matches_vectorised_form():
    f = ca.jit_alpha_tabulated()

    @njit
    def loop(eps, xi):
        out = np.empty(eps.size)
        for i in range(eps.size):
            out[i] = f(eps[i], xi[i])
        return out

    eps, xi = _random_points(200, seed=3)
    np.testing.assert_array_equal(loop(eps, xi), ca.alpha_tabulated(eps, xi))


# Outside the table's domain, and NaN: before the fix the jitted form extrapolated
# (3.4e-5, 110.30, 0.0 for the first three; the true alphas are 2.2e-3, 109.68, none).
OFF_DOMAIN = [(0.5, 0.999999), (0.001, 0.2), (1.5, 0.2), (0.5, -1e-9), (np.nan, 0.2), (0.5, np.nan)]


@pytest.mark.parametrize("eps, xi", OFF_DOMAIN)
def test_jitted_form_is_nan_outside_its_domain_and_the_python_form_raises(eps, xi):
    f = ca.jit_alpha_tabulated()
    assert np.isnan(f(eps, xi))
    name = "eps" if not (EPS_MIN <= eps <= 1.0) else "xi"
    with pytest.raises(ValueError, match=f"{name} = .* outside the valid range"):
        ca.alpha(eps, xi, model="exact")
    with pytest.raises(ValueError, match=f"{name} = .* outside the valid range"):
        ca.alpha_tabulated(eps, xi)


def test_jitted_form_is_finite_on_the_edges_of_its_domain():
    f = ca.jit_alpha_tabulated()
    for eps, xi in [(EPS_MIN, 0.0), (EPS_MIN, XI_MAX), (1.0, XI_MAX), (1.0, 0.0)]:
        assert f(eps, xi) == ca.alpha_tabulated(eps, xi)
    # The corners hold the solver's alpha, not merely a finite number.
    corners = ca.solve_alpha([EPS_MIN, EPS_MIN, 1.0 - 1e-9], [0.0, XI_MAX, XI_MAX], tol=1e-13)
    got = [f(EPS_MIN, 0.0), f(EPS_MIN, XI_MAX), f(1.0 - 1e-9, XI_MAX)]
    np.testing.assert_allclose(got, corners.alpha, rtol=1e-6)
    assert f(1.0, 0.3) == 0.0


def test_eta_coordinate_round_trips():
    xi = np.array([0.0, 1e-12, 1e-6, 0.01, 0.5, XI_MAX])
    np.testing.assert_allclose(xi_of_eta(eta_of_xi(xi)), xi, rtol=1e-12, atol=1e-24)


def test_table_records_its_grid_and_tolerances():
    # The metadata must describe the arrays and the settings the table was built with (config.yaml's
    # models.table), not merely hold the keys: each spline of degree d on n rows has n + 2 d knots.
    t = load_table()
    meta = t.meta
    built = yaml.safe_load((ROOT / "config.yaml").read_text())["models"]["table"]
    assert meta["format_version"] == TABLE_FORMAT_VERSION
    assert {k: meta[k] for k in ("n_eta", "n_p", "tol", "rtol", "atol")} == {
        k: built[k] for k in ("n_eta", "n_p", "tol", "rtol", "atol")
    }
    assert (meta["eps_min"], meta["xi_max"], meta["xi_scale"]) == (EPS_MIN, XI_MAX, XI_SCALE)
    d = meta["degree"]
    assert d == DEGREE and (t.s_tx.size, t.s_ty.size) == (meta["n_eta"] + 2 * d, meta["n_p"] + 2 * d)
    assert meta["n_p_region_n"] == built["refine_n"] * (meta["n_p"] - 1) + 1
    assert (t.n_tx.size, t.n_ty.size) == (meta["n_eta_region_n"] + 2 * d, meta["n_p_region_n"] + 2 * d)


def test_table_with_other_version_is_refused(tmp_path):
    t = load_table(DEFAULT_FILE)
    path = tmp_path / "old.npz"
    save_table(t, path, format_version=TABLE_FORMAT_VERSION - 1)
    assert json.loads(str(np.load(path)["meta"]))["format_version"] == TABLE_FORMAT_VERSION - 1
    with pytest.raises(ValueError, match="format version .* this package reads version"):
        load_table(path)


def test_out_of_table_domain_is_an_error_naming_the_range():
    with pytest.raises(
        ValueError, match=r"eps = 0.005 is outside the valid range \[0.01, 1.0\].*exact_solve"
    ):
        ca.alpha(0.005, 0.2, model="exact")
    with pytest.raises(ValueError, match="xi = 0.995"):
        ca.alpha(0.5, 0.995, model="exact")


def test_unknown_model_lists_the_known_ones():
    with pytest.raises(ValueError, match="unknown model 'nope'; known models: .*exact.*hunt_crossley"):
        ca.alpha(0.5, 0.2, model="nope")


def test_contact_force_is_hunt_crossley_with_the_models_alpha():
    a = ca.alpha(0.6, 0.3, model="hu_guo")
    F = ca.contact_force(2e-5, -0.1, 0.5, 1.4e8, 0.6, 0.3, model="hu_guo")
    assert F == pytest.approx(1.4e8 * 2e-5**1.5 * (1 - a * 0.1 / 0.5), rel=1e-14)
    assert ca.contact_force(-1e-5, 0.1, 0.5, 1.4e8, 0.6, 0.3) == 0.0
    assert ca.contact_force(1e-5, -10.0, 0.5, 1.4e8, 0.6, 0.3, model="hu_guo", clip_tension=True) == 0.0
    with pytest.raises(ValueError, match="approach_speed = 0.0"):
        ca.contact_force(1e-5, 0.1, 0.0, 1.4e8, 0.6, 0.3)


def test_models_that_ignore_load_say_so():
    from contactalpha.models import MODELS

    for name in ("hunt_crossley", "lankarani_nikravesh", "flores", "hu_guo", "gonthier"):
        assert not MODELS[name].uses_xi
        assert ca.alpha(0.4, 0.0, model=name) == ca.alpha(0.4, 0.7, model=name)
    assert MODELS["exact"].uses_xi


@pytest.mark.parametrize(
    "name, value",
    [
        ("hunt_crossley", 1.5 * 0.6),
        ("lankarani_nikravesh", 0.75 * (1 - 0.16)),
        ("flores", 1.6 * 0.6 / 0.4),
        ("hu_guo", 1.5 * 0.6 / 0.4),
        ("gonthier", (1 - 0.16) / 0.4),
    ],
)
def test_classical_formulas(name, value):
    assert ca.alpha(0.4, 0.0, model=name) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize(
    "eps, xi, match",
    [
        (np.full(3, 0.5), np.full(4, 0.2), "shape mismatch"),
        (0.5 + 1j, 0.2, "eps = .* is complex"),
        (1.5, 0.2, r"eps = 1.5 is outside the valid range \[0.01, 1.0\]"),
        (np.nan, 0.2, "eps = nan"),
        (0.5, 1.0, "xi = 1.0"),
    ],
)
def test_exact_model_adds_the_exact_solve_hint_only_where_exact_solve_covers_the_point(eps, xi, match):
    with pytest.raises(ValueError, match=match) as err:
        ca.alpha(eps, xi, model="exact")
    assert "exact_solve" not in str(err.value)
    with pytest.raises(ValueError, match=r"xi = 0.995 .*'exact_solve' covers the rest"):
        ca.alpha(0.5, 0.995, model="exact")
