"""The largest step at which one drop stays within a tolerance, checked on dense phases."""

import numpy as np
import pytest

from contactalpha.stepping.delivered import at_phases
from contactalpha.stepping.inverse import damping_for
from contactalpha.stepping.registry import stepper
from contactalpha.stepping.stepsize import step_for_tolerance, within

MJ = stepper("mujoco")


@pytest.mark.parametrize(("target", "tol"), [(0.5, 0.01), (0.8, 0.02)])
def test_at_the_step_found_every_phase_is_within_the_tolerance(target, tol):
    p = MJ.pack(stiffness=4e4, damping=0.0, impedance=0.9)
    need = step_for_tolerance("mujoco", p, 0.5, 9.81, target, tol)
    assert need.status == "ok"
    h = need.timestep
    e = at_phases("mujoco", need.inverse.p, h, np.arange(4096) / 4096, 0.5, 9.81)["e_n"]
    assert np.max(np.abs(e - target)) <= tol + 1e-12
    assert need.inverse.stats.mean == pytest.approx(target, abs=1e-6)
    # The default 2 ms step does not do it: the tolerance asks for a finer step.
    assert h < 0.002
    assert not within(damping_for("mujoco", p, 0.002, 0.5, 9.81, target), target, tol, "kinematic")
    # The nearest coarser step tried fails, within a rung of the answer.
    assert h < need.fails_at <= h / 2.0**-0.25
    assert not within(damping_for("mujoco", p, need.fails_at, 0.5, 9.81, target), target, tol, "kinematic")
