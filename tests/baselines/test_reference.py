import pytest
import scipy.integrate._ivp.ivp as ivp

from contactalpha.baselines.reference import impact_scipy_limited


@pytest.mark.parametrize("kw", [{"method": "RK99"}, {"atol": -1.0}])
def test_bad_arguments_are_the_callers_error_not_an_event_failure(kw):
    with pytest.raises(ValueError, match="method|atol"):
        impact_scipy_limited(0.5, 0.2, **kw)


def test_a_failing_event_location_is_reported_as_such(monkeypatch):
    def solve_event_equation(*args, **kwargs):  # the name SciPy's event placement has
        raise ValueError("f(a) and f(b) must have different signs")

    monkeypatch.setattr(ivp, "solve_event_equation", solve_event_equation)
    r = impact_scipy_limited(0.5, 0.2)
    assert r.state == "failed"
    assert r.status.startswith("event location failed: f(a) and f(b)")
    assert r.nfev > 0


def test_the_budget_still_ends_a_run_as_step_limit():
    r = impact_scipy_limited(0.5, 0.2, max_nfev=50)
    assert r.status == "step limit exceeded" and r.nfev == 50
