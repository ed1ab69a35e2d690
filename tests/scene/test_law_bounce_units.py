"""A law's bounce sequence in SI units: flights and contacts in seconds (issue 34: a flight time halved
was caught by integration tests only)."""

import dataclasses
import math

import numpy as np
import pytest

from contactalpha.scene import ball
from contactalpha.scene.bounces import predict_bounces


def test_flights_are_ballistic_and_the_time_to_rest_adds_them_up():
    scene = dataclasses.replace(ball.Scene(), stiffness=1e5, eps=0.6)
    seq = predict_bounces(scene, "classic_zeta", law="kelvin_voigt")
    # Up and down at the rebound speed under the constant acceleration: 2 v / a seconds.
    rebounds = seq["v_out"][: seq["flight"].size]
    np.testing.assert_allclose(seq["flight"], 2.0 * rebounds / scene.accel, rtol=1e-15)
    assert seq["time_to_rest"] == pytest.approx(seq["contact"].sum() + seq["flight"].sum(), rel=1e-12)


def test_a_light_contact_lasts_half_a_spring_period():
    # Undamped and nearly unloaded, a spring contact lasts pi sqrt(m / k) seconds.
    scene = dataclasses.replace(ball.Scene(), stiffness=1e5, eps=1.0, force=0.0, gravity=1e-6)
    seq = predict_bounces(scene, "classic_zeta", law="kelvin_voigt", max_contacts=1)
    assert seq["contact"][0] == pytest.approx(math.pi * math.sqrt(scene.mass / 1e5), rel=1e-6)
