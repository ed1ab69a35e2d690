"""The mean over the touchdown phase, its range and its jumps, against independent computations."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from contactalpha.laws import get_law
from contactalpha.stepping.delivered import at_phases, over_phase
from contactalpha.stepping.registry import stepper

MJ = stepper("mujoco")
# (stiffness s^-2, damping s^-1, speed m/s, accel m/s^2, step s): coarse contacts, 5-25 steps.
CASES = [
    (4e4, 80.0, 0.5, 9.81, 0.002),
    (5e3, 20.0, 0.05, 14.81, 0.002),
    (1e5, 30.0, 3.0, 14.81, 0.002),
    (2.5e4, 200.0, 0.2, 19.81, 0.002),
]


def _e(p, h, v, a, phases):
    return at_phases("mujoco", p, h, phases, v, a)["e_n"], at_phases("mujoco", p, h, phases, v, a)["steps"]


def _own_jumps(p, h, v, a, n=4096):
    """The test's own jump finder: dense sampling of the contact steps, then bisection."""
    x = np.arange(n) / n
    steps = at_phases("mujoco", p, h, x, v, a)["steps"]
    cuts = [0.0]
    for i in np.nonzero(np.diff(steps))[0]:
        lo, hi = x[i], x[i + 1]
        for _ in range(60):
            m = 0.5 * (lo + hi)
            if at_phases("mujoco", p, h, [m], v, a)["steps"][0] == steps[i]:
                lo = m
            else:
                hi = m
        cuts.append(hi)
    return [*cuts, 1.0]


@pytest.mark.parametrize("case", CASES)
def test_the_mean_is_scipys_quadrature_between_the_jumps(case):
    k, c, v, a, h = case
    p = MJ.pack(stiffness=k, damping=c, impedance=0.9)
    st = over_phase("mujoco", p, h, v, a)
    cuts = _own_jumps(p, h, v, a)
    assert st.jumps == len(cuts) - 2  # the same jumps (cases 0-2 have them)

    def f(x):
        return at_phases("mujoco", p, h, [x], v, a)["e_n"][0]

    exact = sum(
        quad(f, lo, hi, epsabs=1e-14, epsrel=1e-13, limit=400)[0]
        for lo, hi in zip(cuts, cuts[1:], strict=False)
    )
    assert st.mean == pytest.approx(exact, abs=1e-10)
    assert st.status == "ok" and st.quad_error < 1e-9


@pytest.mark.parametrize("case", CASES)
def test_1024_and_more_phases_converge_on_the_mean_range_and_std(case):
    k, c, v, a, h = case
    p = MJ.pack(stiffness=k, damping=c, impedance=0.9)
    st = over_phase("mujoco", p, h, v, a)
    for n in (1024, 16384):
        e = at_phases("mujoco", p, h, (np.arange(n) + 0.5) / n, v, a)["e_n"]
        jump_bound = 2.0 * (st.maximum - st.minimum) * (st.jumps + 1) / n  # a jump costs <= its size / n
        assert abs(e.mean() - st.mean) <= jump_bound
        assert st.minimum <= e.min() + 1e-15 and e.max() <= st.maximum + 1e-15
        assert abs(e.std() - st.std) <= 10 * jump_bound
    # The dense sample reaches the predicted extremes: they are drops, not bounds.
    assert e.min() - st.minimum < 5e-3 * (st.maximum - st.minimum) + 1e-12
    assert st.maximum - e.max() < 5e-3 * (st.maximum - st.minimum) + 1e-12
    assert st.steps_min == at_phases("mujoco", p, h, (np.arange(n) + 0.5) / n, v, a)["steps"].min()


def test_a_fine_step_delivers_the_continuous_law():
    """As h -> 0 the mean goes to MuJoCo's direct-mode law (laws.mujoco_soft), an independent integrator."""
    stiffness, zeta, v, a = 4e4, 0.2, 0.5, 9.81
    omega = math.sqrt(stiffness)
    law = get_law("mujoco_soft", impedance=0.9)
    xi = law.load_factor(law.load(1.0, stiffness, v, a))
    continuous = law.restitution(zeta, xi, "kinematic")
    p = MJ.pack(stiffness=stiffness, damping=2 * zeta * omega, impedance=0.9)
    errors = [abs(over_phase("mujoco", p, h, v, a).mean - continuous) for h in (2e-4, 2e-5)]
    assert errors[1] < 2e-4
    assert errors[1] < 0.2 * errors[0]  # first order in h


def test_bad_input_names_the_argument():
    p = MJ.pack(stiffness=4e4, damping=80.0, impedance=0.9)
    with pytest.raises(ValueError, match="timestep"):
        over_phase("mujoco", p, -0.002, 0.5, 9.81)
    with pytest.raises(ValueError, match="approach_speed"):
        over_phase("mujoco", p, 0.002, math.nan, 9.81)
    with pytest.raises(ValueError, match="accel"):
        over_phase("mujoco", p, 0.002, 0.5, 0.0)
    with pytest.raises(ValueError, match="engine"):
        over_phase("bullet3", p, 0.002, 0.5, 9.81)
    with pytest.raises(ValueError, match="phases"):
        at_phases("mujoco", p, 0.002, [1.0], 0.5, 9.81)


def test_a_drop_out_of_steps_gives_nan_and_a_status():
    p = MJ.pack(stiffness=4e4, damping=80.0, impedance=0.9)  # 7-8 steps in contact
    st = over_phase("mujoco", p, 0.002, 0.5, 9.81, max_steps=4)
    assert st.status == "step limit exceeded" and math.isnan(st.mean) and math.isnan(st.maximum)
