"""The engine's damping for a target phase mean, checked by independent quadrature and by reach."""

import math

import numpy as np
import pytest

from contactalpha.stepping.delivered import at_phases, over_phase
from contactalpha.stepping.inverse import damping_for
from contactalpha.stepping.registry import stepper

MJ = stepper("mujoco")


def _dense_mean(p, h, v, a, key, n=65536):
    """A midpoint mean over n phases: independent of the adaptive quadrature (error <= jumps / n)."""
    return at_phases("mujoco", p, h, (np.arange(n) + 0.5) / n, v, a)[key].mean()


@pytest.mark.parametrize(
    ("target", "restitution", "v", "a"),
    [(0.5, "kinematic", 0.5, 9.81), (0.1, "kinematic", 1.0, 9.81), (0.95, "kinematic", 3.0, 59.81),
     (0.7, "energetic", 0.2, 29.81)],
)  # fmt: skip
def test_the_phase_mean_is_the_target(target, restitution, v, a):
    p = MJ.pack(stiffness=4e4, damping=0.0, impedance=0.9)
    inv = damping_for("mujoco", p, 0.002, v, a, target, restitution)
    assert inv.status == "ok" and inv.damping > 0.0
    mean, lo, hi = inv.stats.of(restitution)
    assert mean == pytest.approx(target, abs=1e-6)
    key = "e_n" if restitution == "kinematic" else "eps"
    assert _dense_mean(inv.p, 0.002, v, a, key) == pytest.approx(target, abs=2e-5)
    assert lo < target < hi  # one drop strays from the mean at this coarse step


def test_out_of_reach_gives_the_nearest_mean_and_a_step_that_reaches():
    # omega h = 2: one step per contact, the explicit step gains energy whatever the damping.
    p = MJ.pack(stiffness=1e6, damping=0.0, impedance=0.9)
    inv = damping_for("mujoco", p, 0.002, 0.5, 9.81, 0.9)
    assert inv.status == "unreachable" and math.isnan(inv.damping)
    assert abs(inv.nearest - 0.9) > 0.05
    h = inv.timestep_reachable
    assert 0.0 < h < 0.002
    again = damping_for("mujoco", p, h, 0.5, 9.81, 0.9)
    assert again.status == "ok"
    assert over_phase("mujoco", again.p, h, 0.5, 9.81).mean == pytest.approx(0.9, abs=1e-6)


def test_bad_target_names_the_argument():
    p = MJ.pack(stiffness=4e4, damping=0.0, impedance=0.9)
    with pytest.raises(ValueError, match="target"):
        damping_for("mujoco", p, 0.002, 0.5, 9.81, 1.0)
    with pytest.raises(ValueError, match="restitution"):
        damping_for("mujoco", p, 0.002, 0.5, 9.81, 0.5, "newton")
