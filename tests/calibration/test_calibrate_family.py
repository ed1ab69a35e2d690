"""The contact-law family's laws as calibration laws: one contact against a physical solve_ivp.

Integration: the family's general kernel compiles for minutes on a cold numba cache.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from contactalpha.calibration import hypotheses
from contactalpha.calibration.family import FAMILY_HYPOTHESES

pytestmark = pytest.mark.integration

M, A, V = 0.05, 9.81, 0.5
# law -> (values, physical acceleration delta'' given (delta, delta_dot))
CASES = {
    "hunt_crossley_linear_damping": (
        {"damping": 0.5, "stiffness": 1e5},
        lambda x, u: A - max(0.0, 1e5 * x * (1.0 + 0.5 * u)) / M,
    ),
    "kelvin_voigt_damping": (
        {"damping": 5.0, "stiffness": 1e5},
        lambda x, u: A - max(0.0, 1e5 * x + 5.0 * u) / M,
    ),
    "hertz_tsuji_damping": (
        {"damping": 200.0, "stiffness": 1e8},
        lambda x, u: A - max(0.0, 1e8 * x**1.5 + 200.0 * x**0.25 * u) / M,
    ),
    "mujoco_soft_damping": (
        {"damping": 100.0, "stiffness": 1e5},
        lambda x, u: A - max(0.0, 0.9 * A + 100.0 * u + 1e5 * x),
    ),
}


def _ivp(acc):
    def rhs(_, s):
        return [s[1], acc(max(s[0], 0.0), s[1])]

    def lift(t, s):
        return s[0] if t > 1e-9 else 1.0

    lift.terminal, lift.direction = True, -1
    sol = solve_ivp(rhs, (0, 1.0), [0.0, V], events=lift, rtol=1e-12, atol=1e-16, method="DOP853")
    return -sol.y_events[0][0][1], sol.t_events[0][0]


def test_every_family_law_is_tested():
    assert set(CASES) == set(FAMILY_HYPOTHESES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_family_contact_matches_solve_ivp(name):
    values, acc = CASES[name]
    c = hypotheses.HYPOTHESES[name].contact(values, M, A, V)
    v_out, duration = _ivp(acc)
    assert c.separated
    assert c.v_out == pytest.approx(v_out, rel=1e-6)
    assert c.duration == pytest.approx(duration, rel=1e-6)
    assert np.isfinite(c.duration)
