import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import contactalpha as ca
from contactalpha.engine.solver import solve_table

EPS = np.round(np.arange(1, 100) * 0.01, 2)


def test_exact_relation_round_trips_to_machine_precision():
    eps = np.concatenate([[1e-6], EPS, [0.999999]])
    np.testing.assert_allclose(ca.restitution_exact(ca.alpha_exact(eps)), eps, rtol=0, atol=5e-16)


def test_exact_relation_asymptotes():
    # alpha -> 1/eps for small eps, and 3(1 - eps)/2 near eps = 1 (Hunt-Crossley)
    assert ca.alpha_exact(1e-4) == pytest.approx(1e4, rel=1e-12)
    assert ca.alpha_exact(1 - 1e-6) == pytest.approx(1.5e-6, rel=1e-5)


def test_zero_load_column_integrated_matches_exact_relation(paper_eps):
    s = ca.solve_alpha(paper_eps, 0.0, exact_at_zero=False)
    assert np.all(s.ok)
    assert s.alpha[0] == pytest.approx(100.0, rel=1e-3)  # eps = 0.01
    np.testing.assert_allclose(s.alpha, ca.alpha_exact(paper_eps), rtol=1e-9)


def test_zero_load_uses_the_exact_relation_without_integrating():
    s = ca.solve_alpha(0.3, 0.0)
    assert s.impacts == 0 and s.alpha == ca.alpha_exact(0.3)


# The paper's domain, with the stiff ridge near eps -> 0, xi -> 0+ resolved.
RIDGE_XI = np.concatenate([[1e-5, 1e-4, 1e-3, 3e-3, 0.005], np.linspace(0.01, 0.99, 9)])
RIDGE_EPS = np.array([0.01, 0.02, 0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99])


def test_round_trip_hits_target_to_1e_10_over_domain_and_ridge():
    E, X = np.meshgrid(RIDGE_EPS, RIDGE_XI, indexing="ij")
    s = ca.solve_alpha(E, X)
    assert np.all(s.ok), E[~s.ok]
    back = ca.restitution(s.alpha, X)
    assert np.max(abs(back - E)) < 1e-10
    # the ridge: alpha climbs by orders of magnitude over a thin layer of xi
    assert s.alpha[0, 0] < 110 and s.alpha[0, 5] > 1000


@given(eps=st.floats(0.01, 0.99), xi=st.floats(1e-6, 0.99))
def test_solver_hits_its_target_anywhere(eps, xi):
    s = ca.solve_alpha(eps, xi)
    assert s.ok
    assert abs(s.eps_reached - eps) <= 1e-12
    assert abs(ca.restitution(s.alpha, xi) - eps) <= 1e-12


def test_alpha_grows_as_eps_falls():
    s = ca.solve_alpha(EPS[::7], 0.3)
    assert np.all(np.diff(s.alpha) < 0)


def test_onset_alpha_for_zero_restitution():
    s = ca.solve_alpha(0.0, 0.2)
    assert s.ok and s.state == "no_restitution"
    just_below = ca.impact(s.alpha * (1 - np.array([1e-9, 4e-9, 1.6e-8])), 0.2)
    assert np.all(just_below.state == "creep")
    # Next to the onset eps ~ sqrt(onset - alpha): four times closer, half the eps (not a quarter).
    np.testing.assert_allclose(just_below.eps[1:] / just_below.eps[:-1], 2.0, rtol=1e-2)
    assert just_below.eps[0] == pytest.approx(3.93e-6, rel=1e-2)  # eps^2 ~ 1.5e-2 (1 - alpha/onset)
    assert ca.impact(s.alpha * (1 + 1e-9), 0.2).state == "no_restitution"


def test_split_grid_is_bit_identical():
    E, X = np.meshgrid(EPS[::11], np.linspace(0, 0.98, 8), indexing="ij")
    whole, _ = solve_table(E, X)
    parts = [solve_table(E[:, j], X[:, j])[0] for j in range(X.shape[1])]
    pieced = np.stack([p for p in parts], axis=1).reshape(-1, whole.shape[1])
    reordered = whole.reshape(E.shape + (-1,)).reshape(-1, whole.shape[1])
    assert np.array_equal(np.nan_to_num(pieced), np.nan_to_num(reordered))
    single = solve_table(E[3, 5], X[3, 5])[0]
    assert np.array_equal(np.nan_to_num(single[0]), np.nan_to_num(whole.reshape(E.shape + (-1,))[3, 5]))


def test_unreachable_target_is_an_error():
    with pytest.raises(ValueError, match="eps = 0.0 at xi = 0.0 cannot be reached"):
        ca.solve_alpha(0.0, 0.0)


@pytest.mark.parametrize(
    "eps, xi, match",
    [
        (1.5, 0.2, r"eps = 1.5 .*\[0.0, 1.0\]"),
        (-0.1, 0.2, "eps = -0.1"),
        (np.nan, 0.2, "eps = nan"),
        (0.5, 1.0, r"xi = 1.0 .*\[0.0, 1.0\)"),
        (0.5, np.inf, "xi = inf"),
    ],
)
def test_bad_targets_are_rejected(eps, xi, match):
    with pytest.raises(ValueError, match=match):
        ca.solve_alpha(eps, xi)


def test_failure_is_reported_in_status_not_as_a_number():
    s = ca.solve_alpha(0.3, 0.5, max_steps=10)
    assert not s.ok and s.status == "step limit exceeded"
    assert np.isnan(s.alpha)


def test_full_restitution_needs_no_damping():
    s = ca.solve_alpha(1.0, 0.4)
    assert s.alpha == 0.0 and s.state == "separation"


# Issue 15, item 3: the solver to eps -> 0, over 1e-6 <= eps <= 1, 0 <= xi <= 0.99, with the
# ridge columns xi = 1e-6, 1e-4 and the (3e-4, 1e-3), which once gave "no root bracketed".
SMALL_EPS_GRID = np.array([1e-6, 1e-5, 1e-4, 3e-4, 1e-3, 1e-2, 0.1, 0.5, 0.9, 1.0])
SMALL_XI_GRID = np.array([0.0, 1e-6, 1e-4, 1e-3, 0.01, 0.2, 0.5, 0.9, 0.99])


def test_every_point_down_to_eps_1e_6_solves_and_hits_its_target():
    E, X = np.meshgrid(SMALL_EPS_GRID, SMALL_XI_GRID, indexing="ij")
    s = ca.solve_alpha(E, X)
    assert np.all(s.ok), list(zip(E[~s.ok], X[~s.ok], s.status[~s.ok], strict=True))
    # Where eps^2 is a sliver of x_eq the stop is the energy identity's resolution at the
    # tightest tolerance, ~1e-16 in eps^2: |eps - target| <= max(tol, 3e-16 / eps).
    miss = abs(s.eps_reached - E)
    bound = np.where(E < 1.0, np.maximum(1e-12, 3e-16 / E), 2e-12)  # eps = 1: alpha = 0, no iteration
    assert np.all(miss <= bound), np.max(miss / bound)
    assert np.all(s.alpha[E == 1.0] == 0.0)
    assert np.max(miss[E >= 1e-4] / E[E >= 1e-4]) < 3e-8
    # The impacts there cost tens of iterations (eps ~ sqrt(onset - alpha)), never the 60 allowed.
    assert s.impacts.max() <= 45


def test_no_root_bracketed_is_not_reported_where_a_root_exists():
    # The case gave "no root bracketed" after one impact: the root lies in (1e5, 9.2e5).
    s = ca.solve_alpha(3e-4, 1e-3)
    assert s.ok and 1e5 < s.alpha < 9.2e5
    # For xi > 0 every eps in [0, 1] has a root below the onset: the grid test asserts all "ok".
    onset = ca.solve_alpha(0.0, 1e-3)
    assert onset.ok and s.alpha < onset.alpha


# The solver's search bracket is [0, ALPHA_MAX]; every valid target has a root inside it
# (docs/science.md, "Shape of the surface"), so 'no root bracketed' can only be seen by moving
# the bracket's end below a known root.  ALPHA_MAX is compiled into the kernel: the probe runs
# the same algorithm uncompiled (NUMBA_DISABLE_JIT=1), with the constant lowered.
NO_ROOT_PROBE = """
import json, sys
import contactalpha as ca
from contactalpha.engine import solver
solver.ALPHA_MAX = float(sys.argv[1])
s = ca.solve_alpha(0.5, 0.2, guess="formula")
print(json.dumps([s.status, s.alpha, s.eps_reached, s.state]))
"""


@pytest.mark.parametrize("where", [1 - 1e-6, 1 + 1e-6])
def test_no_root_bracketed_exactly_when_the_bracket_excludes_the_root(where):
    import json
    import os
    import subprocess
    import sys

    root = float(ca.solve_alpha(0.5, 0.2).alpha)  # 1.5384855..., restitutes 0.5 in SciPy (test_cli)
    alpha_max = root * where
    env = {**os.environ, "NUMBA_DISABLE_JIT": "1"}
    run = subprocess.run(
        [sys.executable, "-c", NO_ROOT_PROBE, repr(alpha_max)], capture_output=True, text=True, env=env
    )
    assert run.returncode == 0, run.stderr
    status, alpha, eps_reached, state = json.loads(run.stdout.replace("NaN", "null"))
    if where < 1:
        # The root lies beyond the bracket: NaN and the status, and the eps it reached is the
        # bracket end's eps (the solver tried ALPHA_MAX itself before giving up), above 0.5.
        assert status == "no root bracketed" and alpha is None and state == "separation"
        assert eps_reached == pytest.approx(float(ca.impact(alpha_max, 0.2).eps), abs=1e-13)
        assert eps_reached > 0.5
    else:
        assert status == "ok" and alpha == pytest.approx(root, rel=1e-13)
        assert eps_reached == pytest.approx(0.5, abs=1e-12)


def _eps_at_max_compression_scipy(alpha, xi):
    """Stronge's eps of a creeping impact from SciPy's compression phase alone (x_e = x_eq)."""
    from scipy.integrate import solve_ivp

    A = 0.5 * xi * (1.0 - xi) ** -0.6
    x_eq = (A / 1.25) ** (2.0 / 3.0)

    def f(t, y):
        x = max(y[0], 0.0)
        return [y[1], A - 1.25 * x**1.5 * (1.0 + alpha * y[1])]

    def turn(t, y):
        return y[1]

    turn.terminal, turn.direction = True, -1
    run = solve_ivp(f, (0.0, 1e6), [0.0, 1.0], method="DOP853", rtol=2.3e-14, atol=1e-18, events=turn)
    x_m = run.y_events[0][0][0]
    return np.sqrt(A * (x_m - x_eq) / (0.5 + A * x_m))


@pytest.mark.parametrize(
    "eps, xi, rel",
    # rel: the measured gap (engine vs SciPy) rounded up; SciPy at its floor rtol 2.2e-14 is the
    # larger part of it (its rtol 1e-13 and 2.2e-14 runs differ by as much).
    [(1e-3, 0.2, 1e-9), (1e-3, 0.5, 5e-9), (1e-4, 0.2, 5e-8), (1e-4, 0.5, 2e-7), (1e-5, 0.2, 1e-5)],
)
def test_small_eps_keeps_its_relative_accuracy(eps, xi, rel):
    s = ca.solve_alpha(eps, xi)
    assert s.state == "creep"
    assert s.eps_reached == pytest.approx(_eps_at_max_compression_scipy(float(s.alpha), xi), rel=rel)


RIDGE_E, RIDGE_X = np.meshgrid(RIDGE_EPS, RIDGE_XI, indexing="ij")


@pytest.mark.parametrize("guess, total, most", [("table", 201, 2), ("formula", 698, 17)])
def test_newton_work_on_a_fixed_set_of_points(guess, total, most):
    # The counts measured with the full Newton step; a halved or reversed step needs 2-15x more.
    s = ca.solve_alpha(RIDGE_E, RIDGE_X, guess=guess)
    assert np.all(s.ok)
    assert s.impacts.max() <= most
    assert s.impacts.sum() <= round(1.03 * total)


def test_the_paper_surface_costs_about_1_6_impacts_per_point():
    eps = np.round(np.arange(1, 100) * 0.01, 2)
    xi = np.concatenate([np.round(np.arange(1, 100) * 0.01, 2), np.geomspace(1e-5, 0.01, 25)])
    s = ca.solve_alpha(*np.meshgrid(eps, xi, indexing="ij"))
    assert np.all(s.ok)
    assert s.impacts.mean() <= 1.65  # 1.634 measured (12276 points with xi > 0)
    assert s.impacts.max() <= 2


def test_slow_and_integration_markers_are_registered_and_left_out_of_the_default_run(tmp_path):
    # docs/workflow.md: "Slow studies are marked `slow` and stay out of the default run (`pytest -m slow`)";
    # the heavy tests are marked `integration`, which .ci/run runs after the default run.
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    probe = tmp_path / "test_probe.py"
    probe.write_text(
        "import pytest\n\n@pytest.mark.slow\ndef test_a():\n    pass\n\ndef test_b():\n    pass\n\n"
        "@pytest.mark.integration\ndef test_c():\n    pass\n"
    )
    cmd = [sys.executable, "-m", "pytest", "-c", str(root / "pyproject.toml"), "--rootdir", str(tmp_path)]
    run = subprocess.run(
        [*cmd, "--strict-markers", "--collect-only", "-q", str(probe)], capture_output=True, text=True
    )
    assert "test_b" in run.stdout and "test_a" not in run.stdout and "test_c" not in run.stdout, run.stdout
    assert "2 deselected" in run.stdout, run.stdout
    for marker, chosen in (("slow", "test_a"), ("integration", "test_c")):
        run = subprocess.run(
            [*cmd, "--strict-markers", "-m", marker, "--collect-only", "-q", str(probe)],
            capture_output=True,
            text=True,
        )
        others = {"test_a", "test_b", "test_c"} - {chosen}
        assert chosen in run.stdout and not any(t in run.stdout for t in others), run.stdout
