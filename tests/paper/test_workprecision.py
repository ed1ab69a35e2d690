import numpy as np
import pytest

import contactalpha as ca
from contactalpha.baselines.reference import alpha_bracketed, impact_scipy, impact_scipy_limited
from contactalpha.engine.codes import OUT_EPS2, OUT_STATUS, STATUS
from contactalpha.engine.kernel import impact_kernel
from contactalpha.paper.bench import workprecision as wp
from contactalpha.paper.bench.report import checkpoint

NO_RECORD = np.empty((0, 3))


# --- the engine reports every failure it can have in its status -----------------


def test_engine_step_limit_is_reported_not_a_number():
    r = ca.impact(0.5, 0.2, max_steps=5)
    assert r.status == "step limit exceeded"
    assert r.state == "failed"
    assert np.isnan(r.eps)
    s = ca.solve_alpha(0.5, 0.2, max_steps=20)
    assert s.status == "step limit exceeded"
    assert np.isnan(s.alpha)


def test_engine_overflowing_damping_is_a_non_finite_state():
    r = ca.impact(1e300, 0.2)
    assert r.status == "non-finite state"
    assert np.isnan(r.eps)


def test_engine_step_size_underflow_below_the_public_tolerance_floor():
    # The public API refuses rtol < 1e-15; the kernel itself must still report.
    out, _ = impact_kernel(0.5, float(ca.scaled_load(0.2)), 1e-18, 1e-300, 2_000_000, NO_RECORD, np.inf)
    assert STATUS[int(out[OUT_STATUS])] == "step size underflow"
    assert np.isnan(out[OUT_EPS2])


def test_engine_event_location_failure():
    # Found by a random search over tolerances below the public floor.
    out, _ = impact_kernel(
        0.07989064346494258, 0.0, 7.617111975300427e-17, 3.80276171523534e-67, 2_000_000, NO_RECORD, np.inf
    )
    assert STATUS[int(out[OUT_STATUS])] == "event location failed"
    assert np.isnan(out[OUT_EPS2])


def test_a_tol_below_the_resolution_stops_at_alpha_resolved_to_ulp():
    # tol = 1e-15 is below what eps(alpha) resolves at double alpha: the solver stops where a
    # Newton step is a few ulp of alpha and says so by eps_reached (2.4e-15 off), not by NaN.
    s = ca.solve_alpha(0.9, 0.2, rtol=1e-4, atol=1e-6, tol=1e-15, guess="formula")
    assert s.status == "ok"
    assert 0 < abs(s.eps_reached - 0.9) < 1e-13


def test_engine_solves_where_the_old_alpha_limit_gave_no_bracket():
    # eps(5e8) = 2e-6 at xi = 1e-8: eps = 1e-6 needs alpha ~ 1.9e10, beyond the old
    # ALPHA_MAX = 1e9 that reported 'no root bracketed' although a root exists (issue 15).
    s = ca.solve_alpha(1e-6, 1e-8)
    assert s.status == "ok"
    assert 1e9 < s.alpha < 1e12
    assert abs(s.eps_reached - 1e-6) <= 1e-6 * 1e-6


# --- Brent's method and the budgeted SciPy impact --------------------------------


class Fake:
    def __init__(self, eps, status="ok", state="separation", nfev=10):
        self.eps, self.status, self.state, self.nfev = eps, status, state, nfev


def test_brent_finds_the_engine_alpha_with_rk4():
    from contactalpha.baselines.fixedstep import impact_rk4

    b = alpha_bracketed(0.5, lambda a: impact_rk4(a, 0.2, h=1e-3), alpha0=1.0, rtol=1e-14)
    assert b.status == "ok"
    assert b.alpha == pytest.approx(float(ca.solve_alpha(0.5, 0.2).alpha), rel=1e-9)
    assert b.impacts >= 3


def test_brent_solves_an_analytic_law_to_its_tolerance():
    b = alpha_bracketed(0.25, lambda a: Fake(1.0 / (1.0 + a)), alpha0=0.1, rtol=1e-14)
    assert b.alpha == pytest.approx(3.0, rel=1e-13)


def test_brent_reports_no_root_bracketed():
    b = alpha_bracketed(0.5, lambda a: Fake(0.9), alpha0=1.0, alpha_max=1e3)
    assert b.status == "no root bracketed"
    assert np.isnan(b.alpha)


def test_brent_passes_on_the_failure_of_an_impact():
    b = alpha_bracketed(0.5, lambda a: Fake(np.nan, status="missed event", state="failed"), alpha0=1.0)
    assert b.status == "missed event"
    assert np.isnan(b.alpha)
    assert b.impacts == 1


def test_scipy_budget_is_a_step_limit():
    r = impact_scipy_limited(50.0, 0.2, method="RK45", rtol=1e-10, atol=1e-12, max_nfev=100)
    assert r.status == "step limit exceeded"
    assert r.nfev == 100
    ok = impact_scipy_limited(0.5, 0.2, method="DOP853", rtol=1e-10, atol=1e-12)
    assert ok.status == "ok"
    assert ok.eps == pytest.approx(float(ca.impact(0.5, 0.2).eps), abs=1e-8)


# --- measurements ----------------------------------------------------------------


@pytest.mark.parametrize(
    "status, state, alpha, true_state, category",
    [
        ("ok", "separation", 1.0, "separation", "ok"),
        ("ok", "separation", 1.0 + 2e-6, "separation", "error > 1e-6"),
        ("ok", "nonseparation", 1.0, "creep", "wrong end state"),
        ("missed event", "failed", np.nan, "failed", "missed event"),
        ("step limit exceeded", "failed", np.nan, "failed", "step limit"),
        ("no root bracketed", "failed", np.nan, "failed", "no root bracketed"),
        ("non-finite state", "failed", np.nan, "failed", "other"),
    ],
)
def test_classify(status, state, alpha, true_state, category):
    assert wp.CATEGORIES[wp.classify(status, state, alpha, 1.0, true_state)] == category


def test_unknown_method_raises():
    with pytest.raises(ValueError, match="method"):
        wp.solve_with("euler", 1e-3, 0.5, 0.2)


def test_work_precision_error_falls_with_tolerance():
    alpha_ref = float(ca.solve_alpha(0.5, 0.2).alpha)
    rows = wp.work_precision(0.5, 0.2, alpha_ref, {"engine": [1e-4, 1e-10], "rk4": [0.02, 0.005]})
    by = {(r["method"], r["setting"]): r for r in rows}
    assert by["engine", 1e-10]["err_alpha"] < 1e-8 < by["engine", 1e-4]["err_alpha"]
    assert by["rk4", 0.005]["err_alpha"] < by["rk4", 0.02]["err_alpha"] < 1e-5
    assert all(r["status"] == "ok" for r in rows)
    assert by["engine", 1e-10]["err_eps"] < 1e-9
    # err_eps is the error of the eps each alpha delivers: the SciPy oracle's, not the engine's.
    for r in rows:
        oracle = impact_scipy(r["alpha"], 0.2, rtol=1e-12, atol=1e-14).eps
        assert r["err_eps"] == pytest.approx(abs(oracle - 0.5), abs=2e-12), (r["method"], r["setting"])
    # RK4's cost is its fixed step count: a quarter of the step, four times the evaluations.
    fine, coarse = by["rk4", 0.005], by["rk4", 0.02]
    assert fine["impacts"] == coarse["impacts"]
    assert fine["nfev"] / coarse["nfev"] == pytest.approx(4.0, rel=1e-2)


def test_unloaded_reference_is_exact_and_confirmed():
    ref = wp.reference_point(0.5, 0.0)
    assert ref["alpha"] == pytest.approx(float(ca.alpha_exact(0.5)), rel=1e-15)
    assert ref["spread"] < 1e-9


def test_failure_map_flags_a_coarse_rk4_and_passes_the_engine():
    eps = np.array([0.5, 0.02])
    xi = np.array([0.0, 0.2])
    alpha_ref, _ = wp.reference_grid(eps, xi)
    rk = wp.failure_map("rk4", 0.1, eps, xi, alpha_ref)
    counts = wp.category_counts(rk["category"])
    assert counts["ok"] < 4
    assert sum(counts.values()) == 4
    engine = wp.failure_map("engine", 1e-10, eps, xi, alpha_ref)
    assert wp.category_counts(engine["category"])["ok"] == 4
    assert np.nanmax(engine["err_alpha"]) < 1e-6


def test_fit_power_recovers_an_exponent():
    x = np.logspace(1, 4, 7)
    p, c = wp.fit_power(x, 3.0 * x**1.7)
    assert p == pytest.approx(1.7, rel=1e-12)
    assert c == pytest.approx(3.0, rel=1e-10)


def test_cost_to_reach_takes_the_cheapest_setting_that_is_accurate_enough():
    rows = [
        {"method": "a", "err_alpha": 1e-4, "seconds": 1.0},
        {"method": "a", "err_alpha": 1e-8, "seconds": 3.0},
        {"method": "a", "err_alpha": 1e-9, "seconds": 2.0},
        {"method": "b", "err_alpha": np.nan, "seconds": 0.1},
    ]
    assert wp.cost_to_reach(rows, "a", 1e-7) == 2.0
    assert wp.cost_to_reach(rows, "a", 1e-3) == 1.0
    assert np.isnan(wp.cost_to_reach(rows, "b", 1.0))


def test_fill_page_replaces_only_the_marked_block(tmp_path):
    from contactalpha.paper.bench.report import PAGE_END, PAGE_START, fill_page

    page = tmp_path / "performance.md"
    page.write_text(f"# head\n{PAGE_START}\nold 1.0\n{PAGE_END}\ntail\n")
    fill_page(page, "new 2.0\n")
    assert page.read_text() == f"# head\n{PAGE_START}\nnew 2.0\n{PAGE_END}\ntail\n"
    (tmp_path / "bare.md").write_text("no markers\n")
    with pytest.raises(ValueError, match="bench:start"):
        fill_page(tmp_path / "bare.md", "x\n")


def test_brent_counts_a_round_off_nan_eps_as_zero():
    # eps^2 < 0 by round-off gives NaN with status "ok" in impact_scipy.
    # Above alpha = 5 every eps is NaN, i.e. 0 < 0.1: the sign change sits at 5.
    b = alpha_bracketed(0.1, lambda a: Fake(1.0 / (1.0 + a) if a < 5.0 else np.nan), alpha0=0.5, rtol=1e-14)
    assert b.status == "ok"
    assert b.alpha == pytest.approx(5.0, rel=1e-13)


def test_checkpoint_resumes_only_rows_of_the_same_settings(tmp_path):
    table = tmp_path / "wp.csv"
    done, save, partial = checkpoint(table, {"rtols": [1e-4]}, log=lambda msg: None)
    assert done == []
    save([{"method": "engine", "err": 1e-5}, {"method": "rk4", "err": float("nan")}])
    done, _, _ = checkpoint(table, {"rtols": [1e-4]}, log=lambda msg: None)
    assert done == [{"method": "engine", "err": 1e-5}, {"method": "rk4", "err": None}]
    said = []
    done, save, _ = checkpoint(table, {"rtols": [1e-8]}, log=said.append)
    assert done == [] and not partial.exists() and "discarded" in said[0]
    save([{"method": "engine", "err": 1e-9}])
    assert checkpoint(table, {"rtols": [1e-8]}, log=said.append)[0] == [{"method": "engine", "err": 1e-9}]
