import numpy as np
import pytest
from scipy.integrate import solve_ivp

from contactalpha.engine.events import (
    OK,
    equilibrium,
    linear_turn,
    locate,
    trapped_above,
    trapped_below,
)
from contactalpha.engine.rk import N_STAGES, N_STATE, rhs
from contactalpha.engine.scaling import scaled_load


def _linear_turn_numeric(u0, v0, k, c):
    def ev(t, y):
        return y[1]

    ev.terminal = True
    sol = solve_ivp(
        lambda t, y: [y[1], -k * y[0] - c * y[1]], (0, 25.0), [u0, v0], events=ev, rtol=1e-12, atol=1e-16
    )
    if sol.t_events[0].size == 0:
        return False, 0.0
    return True, sol.y_events[0][0][0]


@pytest.mark.parametrize(
    "u0, v0, k, c",
    [
        (0.3, -0.2, 1.0, 0.5),  # under-damped
        (-0.1, -0.4, 2.0, 0.1),  # under-damped, below equilibrium
        (0.2, -2.0, 1.0, 3.0),  # over-damped, fast enough to overshoot
        (0.2, -0.1, 1.0, 3.0),  # over-damped creep
        (0.2, -0.5, 1.0, 2.0),  # critical, overshoots
        (0.2, -0.1, 1.0, 2.0),  # critical, creeps
        (-0.2, 0.05, 1.0, 3.0),  # compression creeping up: never turns
    ],
)
def test_linear_turn_matches_numerical_solution(u0, v0, k, c):
    turns, u = linear_turn(u0, v0, k, c)
    turns_ref, u_ref = _linear_turn_numeric(u0, v0, k, c)
    assert turns == turns_ref
    assert u == pytest.approx(u_ref, abs=1e-9)


@pytest.mark.parametrize(
    "u0, k, c",
    [
        (0.2, 1.0, 0.5),  # under-damped: turns half a period later
        (-0.1, 2.0, 0.1),  # under-damped, below equilibrium
        (0.2, 1.0, 3.0),  # over-damped: creeps, never turns
        (0.2, 1.0, 2.0),  # critical: creeps
        (1e-10, 0.83, 12.4),  # the restitution phase just past the onset at xi = 0.2
    ],
)
def test_linear_turn_from_rest(u0, k, c):
    # From rest the general formulas are 0/0; before the fix rounding decided, and an impact
    # just below the onset ended as "nonseparation" with eps = 0 instead of creeping.
    turns, u = linear_turn(u0, 0.0, k, c)

    def ev(t, y):
        return y[1]

    ev.terminal, ev.direction = True, 1 if u0 > 0 else -1  # u' returns to zero (not the start)
    sol = solve_ivp(
        lambda t, y: [y[1], -k * y[0] - c * y[1]], (0, 60.0), [u0, 0.0], events=ev, rtol=1e-12, atol=1e-22
    )
    assert turns == (sol.t_events[0].size > 0)
    assert u == pytest.approx(sol.y_events[0][0][0] if turns else 0.0, rel=1e-8)
    if turns:
        assert u == pytest.approx(-u0 * np.exp(-0.5 * c * np.pi / np.sqrt(k - 0.25 * c * c)), rel=1e-14)


def test_impacts_just_below_the_onset_creep_at_every_tolerance():
    from contactalpha.baselines.reference import impact_scipy
    from contactalpha.engine.driver import impact

    alpha = 109.69139664524563 * (1 - 1e-7)  # the onset at xi = 0.2 (solve_alpha(0.0, 0.2)), less 1e-7
    ref = impact_scipy(alpha, 0.2, rtol=1e-13, atol=1e-16, t_max=1e3)
    for rtol in (1e-11, 1e-12, 1e-13, 1e-14):
        r = impact(alpha, 0.2, rtol=rtol, atol=rtol * 1e-2)
        assert r.state == "creep" and r.x_end == equilibrium(float(scaled_load(0.2)))
        # eps was 0.0 ("nonseparation") at 1e-11 and 1e-13.  Near the onset eps is ill-conditioned
        # (d ln eps / d ln alpha ~ -5e6 here), so it agrees to ~1e6 rtol, not to rtol.
        assert r.eps == pytest.approx(ref.eps, rel=3e-5), rtol


def _never_turns(x, v, A, alpha, t_end=200.0):
    def f(t, y):
        return [y[1], A - 1.25 * max(y[0], 0) ** 1.5 * (1 + alpha * y[1])]

    sol = solve_ivp(f, (0, t_end), [x, v], method="Radau", rtol=1e-10, atol=1e-13, max_step=0.5)
    vs = sol.y[1]
    return np.all(vs <= 1e-12) if v < 0 else np.all(vs >= -1e-12)


def test_trapped_above_is_a_proof_of_creep():
    A = float(scaled_load(0.2))
    xeq = equilibrium(A)
    x, v, alpha = xeq * 1.2, -0.001, 50.0
    assert trapped_above(x, v, A, alpha)
    assert _never_turns(x, v, A, alpha)
    # too fast towards equilibrium: not trapped, and indeed it overshoots
    assert not trapped_above(x, -2.0, A, 50.0)
    assert not _never_turns(x, -2.0, A, 50.0)
    # light damping: never trapped
    assert not trapped_above(x, -1e-3, A, 0.5)


def test_trapped_below_is_a_proof_of_no_restitution():
    A = float(scaled_load(0.2))
    xeq = equilibrium(A)
    x, v, alpha = xeq * 0.9, 0.001, 500.0
    assert trapped_below(x, v, A, alpha)
    assert _never_turns(x, v, A, alpha)
    assert not trapped_below(x, 5.0, A, 500.0)
    assert not _never_turns(x, 5.0, A, 500.0)  # and indeed it overshoots and turns
    assert not trapped_below(xeq * 1.1, 0.001, A, 500.0)


def test_locate_places_maximum_compression_to_roundoff():
    # Start near the turning point and locate v = 0 with v as independent variable.
    A, alpha = 0.3, 0.7
    y = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])

    def f(t, s):
        return [s[1], A - 1.25 * max(s[0], 0) ** 1.5 * (1 + alpha * s[1])]

    ev = lambda t, s: s[1]  # noqa: E731
    ev.terminal = True
    ref = solve_ivp(f, (0, 10), [0.0, 1.0], events=ev, rtol=1e-13, atol=1e-15, method="DOP853")
    tm, xm = ref.t_events[0][0], ref.y_events[0][0][0]
    near = solve_ivp(f, (0, 0.9 * tm), [0.0, 1.0], rtol=1e-13, atol=1e-15, method="DOP853")
    y[0], y[1], y[2] = near.t[-1], near.y[0, -1], near.y[1, -1]
    K = np.empty((N_STAGES + 1, N_STATE))
    st, steps, _ = locate(y, 2, A, alpha, 1e-12, 1e-14, 1000, K, np.empty(6), np.empty(6))
    assert st == OK and steps >= 1
    assert y[2] == 0.0
    assert y[1] == pytest.approx(xm, abs=1e-12)
    assert y[0] == pytest.approx(tm, abs=1e-11)
    rhs(y, A, alpha, 0, K[0])
    assert K[0, 2] < 0  # decelerating: a true maximum


def test_trapped_above_sector_edge_keeps_its_margin_inside():
    """Issue 29, planted bug: flipping the sign of TRAP_MARGIN passed every test (the slow ones too).

    At x above x_eq the sector's edge is v = -s0 u with s0 the larger root of s (c - s) = g (c the
    damping at x_eq, g the secant slope of the Hertz force), computed here by hand.  A state a
    little inside the edge is a proof of creep; one within the margin of the edge, or outside it,
    is not.
    """
    from contactalpha.engine.events import trapped_above

    A, alpha = 0.2, 50.0
    x_eq = (A / 1.25) ** (2.0 / 3.0)
    x = 1.01 * x_eq
    u = x - x_eq
    c = alpha * A
    g = 1.25 * (x**1.5 - x_eq**1.5) / u
    assert c * c > 4.0 * g * 1.01  # a real sector, well clear of the discriminant's zero
    s0 = 0.5 * (c + np.sqrt(c * c - 4.0 * g))
    # The margin is 1e-6 (relative): 1e-4 inside the edge is inside it, 1e-7 inside is not.
    assert trapped_above(x, -s0 * u * (1.0 - 1e-4), A, alpha)
    assert not trapped_above(x, -s0 * u * (1.0 - 1e-7), A, alpha)
    assert not trapped_above(x, -s0 * u * (1.0 + 1e-7), A, alpha)
    assert not trapped_above(x, +1e-9, A, alpha)  # moving away from x_eq
    assert not trapped_above(0.99 * x_eq, -1e-9, A, alpha)  # below x_eq: the other sector


def test_trapped_below_sector_edge_keeps_its_margin_inside():
    """The mirror sector below x_eq: edge v = s0 u with s0 from c(x) and the tangent slope at x_eq."""
    from contactalpha.engine.events import trapped_below

    A, alpha = 0.2, 80.0
    x_eq = (A / 1.25) ** (2.0 / 3.0)
    x = 0.99 * x_eq
    u = x_eq - x
    c = 1.25 * alpha * x**1.5
    g = 1.5 * 1.25 * np.sqrt(x_eq)
    assert c * c > 4.0 * g * 1.01
    s0 = 0.5 * (c + np.sqrt(c * c - 4.0 * g))
    assert trapped_below(x, s0 * u * (1.0 - 1e-4), A, alpha)
    assert not trapped_below(x, s0 * u * (1.0 - 1e-7), A, alpha)
    assert not trapped_below(x, s0 * u * (1.0 + 1e-7), A, alpha)
    assert not trapped_below(x, -1e-9, A, alpha)  # moving away from x_eq
    assert not trapped_below(1.01 * x_eq, 1e-9, A, alpha)  # above x_eq: the other sector
