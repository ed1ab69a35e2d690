"""The nonlinear laws' shipped tables: their inverse delivers its target, and a changed file is refused."""

import shutil
from dataclasses import asdict, replace

import numpy as np
import pytest
from scipy_reference import reference_impact

from contactalpha.laws import LAWS, get_law
from contactalpha.laws.table import LawTable, check_arrays, load_law_tables

TABULATED = [law for law in LAWS if isinstance(law.fast, LawTable)]
# What the inverse through a table must deliver (issue 26), in restitution.
TARGET_TOL = 1e-7


def _domain(n, seed, corners=True):
    """Targets uniform and log-uniform over [0.01, 1]; loads uniform and log-uniform over [0, 0.99].

    ``corners`` adds the domain's corners (e = 0.01 at xi = 0 and 0.99, e -> 1).
    """
    rng = np.random.default_rng(seed)
    half = n // 2
    target = np.concatenate([rng.uniform(0.01, 1.0, half), np.exp(rng.uniform(np.log(0.01), 0.0, n - half))])
    xi = np.concatenate([0.99 * rng.random(half), np.exp(rng.uniform(np.log(1e-9), np.log(0.99), n - half))])
    if corners:
        target[:4] = [0.01, 0.01, 1.0, 0.999]
        xi[:4] = [0.0, 0.99, 0.5, 0.99]
    return target, xi


def test_the_nonlinear_and_piecewise_linear_laws_have_tables():
    assert {law.name for law in TABULATED} == {
        "hunt_crossley_linear",
        "hertz_tsuji",
        "hertz_tsuji_unfloored",
        "hertz_viscoelastic",
        "hertz_viscoelastic_unfloored",
        "kelvin_voigt",
        "mujoco_soft",
    }
    for law in TABULATED:
        _, meta = load_law_tables(law.fast.path)
        assert meta["law"] == law.name and tuple(meta["cuts"]) == law.fast.cuts
        assert meta.get("impedance", 0.0) == law.fast.impedance == law.impedance
        # The documented build command (the law's own settings) reproduces the shipped grid.
        assert {k: meta[k] for k in asdict(law.fast.settings)} == asdict(law.fast.settings)


@pytest.mark.parametrize("law", TABULATED, ids=lambda law: law.name)
@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_table_inverse_delivers_its_target_through_the_integrator(law, restitution):
    target, xi = _domain(400, 26)
    p = law.fast_damping(target, xi, restitution)
    assert np.all(np.isfinite(p)) and np.all(p >= 0.0)
    got = law.restitution(p, xi, restitution)
    np.testing.assert_allclose(got, target, rtol=0, atol=TARGET_TOL)


PIECEWISE = [law for law in TABULATED if law.piecewise_linear]


@pytest.mark.parametrize("law", PIECEWISE, ids=lambda law: law.name)
@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_piecewise_linear_table_inverse_delivers_its_target_through_the_closed_form(law, restitution):
    # The closed form (laws/closed_form.py) is the forward map these tables were not built from.
    target, xi = _domain(2000, 27)
    p = law.fast_damping(target, xi, restitution)
    ok = np.isfinite(p)
    assert np.all(p[ok] >= 0.0) and ok.mean() >= 0.995
    got = law.fast_restitution(p[ok], xi[ok], restitution)
    np.testing.assert_allclose(got, target[ok], rtol=0, atol=TARGET_TOL)
    # NaN only where root finding on the closed form misses too (eps(zeta) jumps there).
    exact = law.fast_damping(target[~ok], xi[~ok], restitution, exact=True)
    assert np.all(np.abs(law.fast_restitution(exact, xi[~ok], restitution) - target[~ok]) > TARGET_TOL)


def test_the_former_jump_is_a_closed_form_glitch_and_now_inverts_exactly():
    # Small loads, eps near 0.016: the closed form ended impacts early after a re-contact
    # (a rounding-side error at the floor's root), which looked like a jump of eps(zeta); the
    # integrator has none.  The table's answer now meets the target through the integrator.
    law = get_law("kelvin_voigt")
    target, xi = 0.01584, 0.002294
    p = law.fast_damping(target, xi)
    assert np.isfinite(p)
    assert abs(law.restitution(p, xi) - target) < 1e-9
    assert abs(law.restitution(law.fast_damping(target, xi, exact=True), xi) - target) < 1e-9


def test_mujoco_at_another_impedance_inverts_by_the_closed_form():
    from contactalpha.laws.fast import CLOSED_FORM

    law = get_law("mujoco_soft", impedance=0.5)
    assert not law.fast.covers(law) and law.fast.covers(get_law("mujoco_soft"))
    target, xi = _domain(200, 28)
    p = law.fast_damping(target, xi)
    A = np.atleast_1d(law.scaled_load(xi))
    want, status = CLOSED_FORM.damping(law, target, False, A, xi)
    np.testing.assert_array_equal(p, np.where(status == 0, want, np.nan))
    np.testing.assert_allclose(law.fast_restitution(p, xi), target, rtol=0, atol=TARGET_TOL)
    # Not the table's numbers: the default impedance's damping delivers another restitution.
    assert np.max(np.abs(get_law("mujoco_soft").fast_damping(target, xi) - p)) > 1e-3


def test_a_table_without_a_forward_map_refuses_another_impedance(tmp_path):
    law = get_law("mujoco_soft", impedance=0.5)
    law = replace(law, fast=replace(law.fast, forward=None))
    with pytest.raises(ValueError, match="impedance 0.5 has no fast inverse"):
        law.fast_damping(0.5, 0.2)
    with pytest.raises(ValueError, match="has no fast forward map"):
        law.fast_restitution(0.5, 0.2)


def test_a_table_built_at_another_impedance_is_refused(tmp_path):
    from contactalpha.laws.table import save_law_tables

    law = get_law("mujoco_soft")
    arrays, meta = load_law_tables(law.fast.path)
    path = save_law_tables(arrays, dict(meta, impedance=0.8), tmp_path / "table.npz")
    law = replace(law, fast=replace(law.fast, file=str(path)))
    with pytest.raises(ValueError, match="built at impedance 0.8, expected 0.9"):
        law.fast_damping(0.5, 0.2)


def _scipy_check(law, restitution, n, seed):
    # Without the corners: the reference's segments do not end at e = 0.01, xi = 0 (p = 100, no
    # load); the zero-load column is checked against the exact relations below.
    target, xi = _domain(n, seed, corners=False)
    p = law.fast_damping(target, xi, restitution)
    # NaN only for the linear laws, where no damping delivers the target (tested above).
    ok = np.isfinite(p)
    assert ok.all() or (law.piecewise_linear and ok.mean() >= 0.99)
    A = law.scaled_load(xi)
    got = [
        reference_impact(law.name, pi, Ai, law.impedance)[0 if restitution == "energetic" else 1]
        for pi, Ai in zip(p[ok], A[ok], strict=True)
    ]
    np.testing.assert_allclose(got, target[ok], rtol=0, atol=TARGET_TOL)


@pytest.mark.parametrize("law", TABULATED, ids=lambda law: law.name)
@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_table_inverse_delivers_its_target_through_scipy(law, restitution):
    # An independent integration (SciPy's DOP853, tests/laws/scipy_reference.py) at 40 points;
    # ``pytest -m slow`` checks 200 more.
    _scipy_check(law, restitution, 40, 6)


@pytest.mark.slow
@pytest.mark.parametrize("law", TABULATED, ids=lambda law: law.name)
@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_table_inverse_delivers_its_target_through_scipy_at_200_more_points(law, restitution):
    _scipy_check(law, restitution, 200, 7)


def test_n1_table_at_zero_load_is_the_exact_unloaded_relation():
    # At zero load Hunt-Crossley's alpha(e) does not depend on n: the n = 3/2 engine's exact relation.
    from contactalpha.engine.exact import alpha_exact_scalar, restitution_exact_scalar

    e = np.exp(np.linspace(np.log(0.01), np.log(0.999), 60))
    want = np.array([alpha_exact_scalar(x) for x in e])
    for restitution in ("energetic", "kinematic"):
        got = get_law("hunt_crossley_linear").fast_damping(e, 0.0, restitution)
        np.testing.assert_allclose(got, want, rtol=1e-6)
        delivered = [restitution_exact_scalar(a) for a in got]
        np.testing.assert_allclose(delivered, e, rtol=0, atol=TARGET_TOL)


def test_tsuji_table_at_zero_load_is_the_spring_dashpot_with_beta_sqrt5_zeta():
    e = np.exp(np.linspace(np.log(0.01), np.log(0.999), 60))
    spring = get_law("kelvin_voigt")
    zeta = spring.fast_damping(e, 0.0, "kinematic")
    for restitution in ("energetic", "kinematic"):
        beta = get_law("hertz_tsuji").fast_damping(e, 0.0, restitution)
        np.testing.assert_allclose(beta, np.sqrt(5.0) * zeta, rtol=1e-6)
        delivered = spring.fast_restitution(beta / np.sqrt(5.0), 0.0, "kinematic")  # the closed form
        np.testing.assert_allclose(delivered, e, rtol=0, atol=TARGET_TOL)


def test_outside_the_table_is_nan_or_an_error_never_a_number():
    law = get_law("hertz_tsuji")
    assert np.isnan(law.fast_damping(0.005, 0.3))
    assert np.isnan(law.fast_damping(0.5, 0.995))
    with pytest.raises(ValueError, match="xi"):
        law.fast_damping(0.5, 1.0)
    with pytest.raises(ValueError, match="has no fast forward map"):
        law.fast_restitution(0.5, 0.1)


@pytest.fixture
def copied(tmp_path):
    law = get_law("hunt_crossley_linear")
    path = tmp_path / "table.npz"
    shutil.copy(law.fast.path, path)
    return replace(law, fast=replace(law.fast, file=str(path))), path


def test_a_copy_of_the_shipped_table_loads_and_agrees(copied):
    law, _ = copied
    assert law.fast_damping(0.4, 0.3) == get_law("hunt_crossley_linear").fast_damping(0.4, 0.3)


def test_changed_arrays_or_shapes_are_refused(copied):
    law, path = copied
    arrays, meta = load_law_tables(path)
    changed = dict(arrays, r0_c=arrays["r0_c"] * (1.0 + 1e-15))
    with pytest.raises(ValueError, match="checksum"):
        check_arrays(changed, meta, path)
    cut = dict(arrays, r1_c=arrays["r1_c"][:-1])
    with pytest.raises(ValueError, match="array r1_c has shape"):
        check_arrays(cut, meta, path)
    with pytest.raises(ValueError, match="format"):
        check_arrays(arrays, dict(meta, format="law-table-1"), path)


@pytest.mark.parametrize("how", ["truncated", "garbage"])
def test_a_corrupted_table_file_names_itself(copied, how):
    law, path = copied
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) // 2] if how == "truncated" else b"\x00\xff" * 64)
    with pytest.raises(ValueError, match=rf"law table {path} cannot be read"):
        law.fast_damping(0.5, 0.2)
