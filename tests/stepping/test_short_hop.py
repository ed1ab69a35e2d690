"""A hop shorter than one step (issue 44, S1): e_N is what a user reads in the engine.

Under a heavy load at a coarse step the body leaves the surface, flies less than a step and lands
again.  A user reads the rebound from the free parabola through the first sample above the
surface; here that reading is written out independently of ``flight.rebound_speed`` and compared
with the drop, the affine phase mean and the drop-by-drop quadrature.  The scenes are two of the
issue's MuJoCo scenes at 2 ms (a h / v from 0.87 to 1.25) with the damping the package solves.
"""

import math

import numpy as np
import pytest

from contactalpha.stepping.affine_phase import phase_mean_affine
from contactalpha.stepping.codes import D_EN, P_MEAN
from contactalpha.stepping.delivered import over_phase
from contactalpha.stepping.drop import run_drops, trajectory
from contactalpha.stepping.kernels import MUJOCO
from contactalpha.stepping.registry import stepper

H = 0.002
# (stiffness, damping per unit mass, approach speed, load acceleration), impedance 0.9
SCENES = [(2018.2481751824816, 6.332621238689599, 0.105, 9.81 + 98.8 / 2.74),
          (1659.9099099099099, 3.5416296148293043, 0.0901, 9.81 + 2.06 / 0.0444)]  # fmt: skip
PHASES = 4096


def _user_reading(zs, ws, a, v):
    """Exit speed over v of the parabola through the first sample above the surface after the
    first below it, and whether the body lands again within the next step (a short hop)."""
    k0 = int(np.argmax(zs < 0.0))
    above = np.nonzero(zs[k0:] > 0.0)[0]
    if above.size == 0:
        return 0.0, False
    j = k0 + int(above[0])
    s = ws[j] - 0.5 * a * H  # the parabola's speed at the sample
    hop = ws[j] - a * H <= 0.0  # the free step from the sample ends moving down
    return math.sqrt(s * s + 2.0 * a * zs[j]) / v, bool(hop)


@pytest.mark.parametrize("scene", SCENES)
def test_a_short_hop_is_read_from_the_first_sample_above_the_surface(scene):
    k, c, v, a = scene
    p = stepper("mujoco").pack(stiffness=k, damping=c, impedance=0.9)
    phases = (np.arange(PHASES) + 0.5) / PHASES
    read = [_user_reading(*trajectory(MUJOCO, p, H, f, v, a, 400), a, v) for f in phases]
    e_user = np.array([e for e, _ in read])
    hops = sum(hop for _, hop in read)
    assert hops > 0.05 * PHASES  # the scene has short hops (they were e_N = 0)
    e = run_drops(MUJOCO, p, H, phases, v, a, 5000)[:, D_EN]
    np.testing.assert_allclose(e, e_user, rtol=0.0, atol=1e-12)
    mean = phase_mean_affine(MUJOCO, p, H, v, a, 5000, 1e-12)[P_MEAN]
    assert abs(mean - e_user.mean()) < 5e-4  # the midpoint sample's error at the jumps
    assert abs(mean - over_phase("mujoco", p, H, v, a).mean) < 1e-9
