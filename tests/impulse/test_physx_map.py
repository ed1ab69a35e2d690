"""PhysX's TGS map read as a drop test reads it (no engine; SAPIEN itself: ``test_physx_engine.py``).

A touchdown faster than the contact distance a step (4 m/s at 0.01 s: 4 cm against 2 cm) passes
the contact distance in a free step and lands 2 cm deep; the bounce step then leaves the ball
below the plane moving up, and the next step's position iterations push it out by about 9 mm
while the clamped impulse gives its velocity back.  The flight starts after that step: e_N is
the parabola's well clear of the contact, which the map steps freely.
"""

import numpy as np
import pytest

from contactalpha.impulse import physx_map as pm
from contactalpha.impulse.delivered import drop_impulse, free_steps
from contactalpha.impulse.kernels import PHYSX
from contactalpha.stepping.flight import rebound_speed, touchdown_state

H, A, V = pm.DEFAULT_TIMESTEP, 9.81, 4.0
P = pm.make_params(0.95, 0.05)


def _flight_e_n(phase, steps=8):
    """e_N from the state ``steps`` steps after the touchdown state: past the contact distance, free."""
    z, w = touchdown_state(V, A, H, phase)
    for _ in range(steps):
        z, w = pm.step_physx(z, w, P, H, A)
    assert z > pm.CONTACT_DISTANCE and w > 0.0  # above the contact's reach: free flight since
    return rebound_speed(z, w, A, H) / V


@pytest.mark.parametrize("phase", [0.3, 0.505, 0.5104, 0.55, 0.6, 0.7, 0.8, 0.9, 0.95])
def test_the_rebound_is_read_after_the_step_that_pushes_only_the_position(phase):
    got, _, status = drop_impulse(PHYSX, P, H, phase, V, A)
    assert status == 0
    assert got == pytest.approx(_flight_e_n(phase), abs=1e-12)


def test_a_step_that_moves_only_the_position_is_not_free():
    h, a = 0.01, 9.81
    z = np.array([0.1, 0.1 + h * (0.5 - a * h), 0.0])
    w = np.array([0.5, 0.5 - a * h, 0.5 - 2.0 * a * h])  # velocities of free flight
    z[2] = z[1] + h * w[2] + 1e-3  # ... but the second step's position pushed by 1 mm
    assert free_steps(z, w, a, h, 1e-9, 1e-9).tolist() == [True, False]
    assert free_steps(z, w, a, h, 1e-9, 2e-3).tolist() == [True, True]
