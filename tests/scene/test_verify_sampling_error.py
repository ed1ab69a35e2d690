"""``verify``'s sampling error: the N-phase mean's distance from the phase integral, estimated."""

import numpy as np
import pytest

from contactalpha.cli import main
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.parameters.verify import VERIFY_TOL, phase_mean_error

# MuJoCo at its 2 ms step, 2-3 steps per contact: one drop's e_N jumps with the phase.
COARSE = {"mass": 0.5, "stiffness": 1e5, "approach_speed": 0.5, "accel": 9.81, "e_N": 0.5}


def test_phase_mean_error_of_a_sawtooth():
    """f = phase over N phases k/N: the mean is 1/2 - 1/(2N), the error 1/(2N) exactly, as estimated."""
    for n in (16, 64, 1024):
        f = np.arange(n) / n
        assert f.mean() == pytest.approx(0.5 - 0.5 / n, rel=1e-14)
        assert phase_mean_error(f) == pytest.approx(0.5 / n, rel=1e-12)
    assert np.isnan(phase_mean_error([0.4]))


def test_verify_reports_the_sampling_error_against_the_map(mujoco):
    """64 phases lie 2.6e-3 from the map's phase mean; the estimate says so (within 10 %)."""
    cp = contact_parameters(**COARSE, engine="mujoco", timestep=0.002, verify=64)
    st = cp.stepped
    gap = abs(st.verify["mean"] - st.mean)
    assert gap > 1e-3 and st.steps_max <= 4
    assert st.verify["sampling_error"] == pytest.approx(gap, rel=0.1)


def test_verify_default_doubles_until_the_error_is_small(mujoco, capsys):
    cp = contact_parameters(**COARSE, engine="mujoco", timestep=0.002, verify="default")
    v = cp.stepped.verify
    assert v["sampling_error"] <= VERIFY_TOL and abs(v["mean"] - cp.stepped.mean) <= 2 * VERIFY_TOL
    assert v["phases"] > 64
    argv = ["params", "--mass", "0.5", "--stiffness", "1e5", "--speed", "0.5", "--accel", "9.81",
            "--e-n", "0.5", "--engine", "mujoco", "--timestep", "--verify", "--quiet"]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f"at {v['phases']} phases: mean {v['mean']:.6g} (sampling error {v['sampling_error']:.1e}" in out
