"""The stepping figures' numbers: phase curves and the step a tolerance needs, checked on dense phases."""

import numpy as np
import pytest

from contactalpha.stepping.delivered import at_phases
from contactalpha.stepping.inverse import damping_for
from contactalpha.studies.stepping import compute


def test_phase_curves_scatter_around_their_mean_less_at_finer_steps():
    curves = compute.phase_curves(phases=256)
    spreads = []
    for _phi, e, st in curves.values():
        assert e.mean() == pytest.approx(st.mean, abs=2e-3)
        assert st.minimum <= e.min() and e.max() <= st.maximum
        spreads.append(np.ptp(e))
    assert spreads[0] > spreads[1] > spreads[2]  # the steps are in falling order


def test_the_step_needed_keeps_every_drop_within_the_tolerance():
    zeta, load, tol = 0.2, 0.1, 0.02
    h = compute.step_needed(zetas=(zeta,), loads=(load,), tol=tol)[0, 0]
    target = compute.continuous_e_n(zeta, load)
    p = compute.stepper("mujoco").pack(stiffness=1.0, damping=0.0, impedance=compute.IMPEDANCE)
    inv = damping_for("mujoco", p, h, 1.0, load, target)
    e = at_phases("mujoco", inv.p, h, np.arange(4096) / 4096, 1.0, load)["e_n"]
    assert np.max(np.abs(e - target)) <= tol + 1e-12
    assert 0.0 < h < np.pi / 4
