"""The stepping engines' shared pieces, against closed forms of a semi-implicit Euler flight."""

import math

import numpy as np
import pytest

from contactalpha.adapters.base import Adapter, Delivered, refine
from contactalpha.adapters.stepped import measure_steps, summarise, touchdown_state


def euler_flight(z0, v0, a, h, n):
    """Stored states of n semi-implicit Euler steps in free flight (v' = v - a h, z' = z + h v')."""
    z, v = [z0], [v0]
    for _ in range(n):
        v.append(v[-1] - a * h)
        z.append(z[-1] + h * v[-1])
    return np.array(z), np.array(v)


@pytest.mark.parametrize("phase", [0.0, 0.3, 0.9])
def test_touchdown_state_meets_the_surface_at_the_approach_speed(phase):
    v, a, h = 0.7, 12.0, 1e-3
    z0, w0 = touchdown_state(v, a, h, phase)
    z, w = euler_flight(z0, w0, a, h, 3)
    # The stored positions lie on z(t) = z0 + (w0 - a h/2) t - a t^2/2 (closed form of the scheme).
    t = np.arange(4) * h
    assert np.allclose(z, z0 + (w0 - 0.5 * a * h) * t - 0.5 * a * t * t, rtol=0, atol=1e-15)
    tc = phase * h
    assert z0 + (w0 - 0.5 * a * h) * tc - 0.5 * a * tc * tc == pytest.approx(0.0, abs=1e-15)
    assert (w0 - 0.5 * a * h) - a * tc == pytest.approx(-v, rel=1e-14)


@pytest.mark.parametrize("tc", [0.0, 0.25, 0.8])
def test_rebound_speed_is_read_from_the_flight_parabola(tc):
    """A made-up contact (states in z < 0), then a flight whose parabola leaves z = 0 at speed u."""
    v, u, a, h = 1.0, 0.43, 9.81, 2e-3
    contact_z = -np.array([0.0, 1e-3, 2e-3, 1.5e-3, 0.5e-3])
    contact_v = np.array([-v, -0.6, 0.1, 0.4, 0.45])
    # Flight nodes at t_n = (n + tc) h after the surface crossing: stored v = u - a (t_n - h/2).
    t = (np.arange(1, 40) - 1 + tc) * h + h
    z = u * t - 0.5 * a * t * t
    w = u - a * (t - 0.5 * h)
    res = measure_steps(np.r_[contact_z, z], np.r_[contact_v, w], a, h, v)
    assert res.state == "separation"
    assert res.e_n == pytest.approx(u / v, rel=1e-12)


def test_a_hop_shorter_than_a_step_is_read_from_its_sample_above_the_surface():
    """One sample above the surface between two contacts (issue 44, S1): the rebound is the speed
    at z = 0 of the parabola through it (a user's reading), not "nonseparation"."""
    a, h, v = 200.0, 2e-3, 0.1
    z_hop, w_hop = 2e-5, 0.05  # the free step from it ends at w - a h = -0.35 (down) and z < 0
    z = np.array([1e-4, -1e-4, -2e-4, -1e-4, z_hop, z_hop + h * (w_hop - a * h), -1e-3])
    w = np.array([-v, -0.1, 0.0, 0.05, w_hop, w_hop - a * h, -0.2])
    res = measure_steps(z, w, a, h, v)
    s = w_hop - 0.5 * a * h
    assert res.state == "separation"
    assert res.e_n == pytest.approx(math.sqrt(s * s + 2.0 * a * z_hop) / v, rel=1e-12)


def test_no_free_step_after_the_deepest_point_is_no_separation():
    z = -np.array([0.0, 1e-3, 2e-3, 1.9e-3, 1.9e-3])
    w = np.array([-1.0, -0.5, 0.0, 0.01, 0.0])
    res = measure_steps(z, w, 9.81, 1e-3, 1.0)
    assert res.state == "nonseparation" and res.e_n == 0.0


def test_refine_finds_the_damping_of_a_monotone_map():
    ref = refine(lambda p: math.exp(-p), 0.5, 0.6, 1e-3)
    assert ref.status == "ok" and ref.damping == pytest.approx(math.log(2.0), abs=1e-5)
    assert abs(ref.e_n - 0.5) <= 1e-5 and ref.e_n_start == pytest.approx(math.exp(-0.6))


def test_refine_keeps_a_start_inside_the_tolerance():
    ref = refine(lambda p: math.exp(-p), 0.5, math.log(2.0) + 1e-4, 1e-3)
    assert ref.status == "unchanged" and ref.iterations == 0


def test_refine_says_unreachable_when_zero_damping_falls_short():
    ref = refine(lambda p: 0.4 * math.exp(-p), 0.8, 0.1, 1e-3)
    assert ref.status == "unreachable" and math.isnan(ref.damping)


def test_summarise_reports_mean_and_spread():
    got = summarise([0.4, 0.5, 0.6], [30, 29, 31], [True, True, True])
    assert got.e_n == pytest.approx(0.5) and got.spread == pytest.approx(0.2) and got.contact_steps == 29


class _LinearEngine(Adapter):
    """A fake engine whose delivered e_N falls linearly with the damping: e = top - damping / 10."""

    name, module, settings = "linear", "math", None

    def __init__(self, top):
        self.top, self.calls = top, []

    def parameters(self, damping, scene, settings=None):
        return {"damping": damping}

    def delivered(self, scene, damping, settings=None):
        self.calls.append(damping)
        return Delivered(self.top - damping / 10.0, 0.0, None, True)


@pytest.mark.parametrize("top, target", [(0.9, 0.8), (0.4, 0.8)])
def test_calibrate_has_one_fallback_rule(top, target):
    """Found: the refined damping's parameters; not found: ``{}``, and what the start delivers."""
    engine = _LinearEngine(top)
    params, ref, got = engine.calibrate(None, target, start=0.5)
    if ref.status == "ok":
        assert params["damping"] == pytest.approx(10.0 * (top - target), rel=1e-9)
        assert got.e_n == pytest.approx(target, abs=1e-5)
    else:
        assert ref.status == "unreachable" and params == {}
        assert engine.calls[-1] == 0.5 and got.e_n == pytest.approx(top - 0.05, rel=1e-15)


@pytest.mark.parametrize(
    ("steps", "spread", "says", "never"),
    [
        (8, 0.002, r"spans 8 steps \(coarse below 20\) and .* by up to 0\.002 "
         r"\(over the tolerance 0\.001\)", None),
        (8, 0.0005, r"spans 8 steps \(coarse below 20\); .* by up to 0\.0005 \(within the tolerance 0\.001\)",
         "over the tolerance"),
        (35, 0.002, r"by up to 0\.002 \(over the tolerance 0\.001\), though the contact spans 35 steps "
         r"\(20 or more: not coarse\)", "coarse below"),
    ],
    ids=["both", "coarse", "spread"],
)  # fmt: skip
def test_coarse_warning_says_what_triggered_it(steps, spread, says, never):
    from contactalpha.adapters.stepped import ContactStepsWarning, warn_if_coarse

    with pytest.warns(ContactStepsWarning, match=says) as record:
        warn_if_coarse("toy", Delivered(0.5, spread, steps, True), 1e-3)
    assert len(record) == 1 and (never is None or never not in str(record[0].message))


def test_fine_contact_within_tolerance_does_not_warn(recwarn):
    from contactalpha.adapters.stepped import warn_if_coarse

    warn_if_coarse("toy", Delivered(0.5, 0.0005, 35, True), 1e-3)
    assert not recwarn.list
