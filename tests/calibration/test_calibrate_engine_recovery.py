"""A drop recorded in a real engine (OpenSim/Simbody) with known parameters, calibrated back.

The engine user's set-up: one ``HuntCrossleyForce`` whose dissipation ``c`` is set once, so the
engine's law is ``hc_damping`` with ``d = 3 c / 2``.  The touchdown times the engine gives, with a
phone's 0.1 ms jitter added, must give ``d`` and the stiffness back inside their 95 % intervals,
and the calibration must select ``hc_damping``.
"""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.scene.ball import Scene

pytestmark = pytest.mark.integration

SCENE = Scene(mass=0.05, radius=0.02, stiffness=1e8, approach_speed=2.0, force=0.0, eps=0.8, t_end=6.0)
FAST = {"accuracy": 1e-8, "per_tstar": 100, "window": 12.0, "settle": 5}


@pytest.fixture(scope="module")
def engine_run(opensim):
    from contactalpha.adapters import opensim_hc

    return opensim_hc.bounce(SCENE, per_impact=False, **FAST)


def test_opensim_drop_gives_its_parameters_back(engine_run):
    c = engine_run["contacts"]
    assert np.ptp(c["dissipation"]) == 0.0  # set once, as an engine user would
    d_true = 1.5 * c["dissipation"][0]
    t = c["t_touch"][:21]
    assert t.size == 21
    noisy = t + np.random.default_rng(28).normal(0.0, 1e-4, t.size)
    cal = ca.calibrate(noisy, kind="times", mass=SCENE.mass, radius=SCENE.radius)
    assert cal.selected == "hc_damping"
    f = cal.fits["hc_damping"]
    lo, hi = f.intervals["damping"]
    assert lo < d_true < hi and hi / lo < 1.2
    lo, hi = f.intervals["stiffness"]
    # Only the contact durations (~0.5 ms against 0.1 ms jitter) tell the stiffness here.
    assert lo < SCENE.stiffness < hi and hi / lo < 20.0
    # The engine input it hands back is the one the run used.
    c_fit = cal.engines["hc_damping"]["opensim_constant_dissipation"]
    lo, hi = f.intervals["damping"]
    assert lo / 1.5 < c_fit < hi / 1.5
