"""contact_parameters, advise, critical_speed and predict_bounces with law=."""

import dataclasses

import numpy as np
import pytest

from contactalpha.laws import get_law
from contactalpha.parameters.front_door import ContactParameters, contact_parameters
from contactalpha.scene import ball
from contactalpha.scene.advisor import advise
from contactalpha.scene.bounces import predict_bounces
from contactalpha.scene.threshold import critical_speed

G = 9.81


def test_contact_parameters_of_mujocos_soft_contact():
    cp = contact_parameters(e_N=0.5, mass=1.0, stiffness=1e4, approach_speed=0.5, accel=G, law="mujoco_soft")
    law = get_law("mujoco_soft")
    assert cp.e_n == pytest.approx(0.5, abs=1e-9)
    assert cp.xi == pytest.approx(law.load_factor(G / (100.0 * 0.5)), rel=1e-14)
    assert cp.engines["mujoco"]["solref"] == (-1e4, pytest.approx(-2.0 * cp.damping * 100.0, rel=1e-14))
    # What the engine receives delivers the target: the law's forward map at its damping.
    assert law.impact(cp.damping, cp.xi).e_n == pytest.approx(0.5, abs=1e-9)


def test_default_law_is_unchanged():
    args = dict(eps=0.5, mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=129.81)
    assert contact_parameters(**args) == contact_parameters(**args, law="hunt_crossley")
    assert isinstance(contact_parameters(**args), ContactParameters)


def test_unknown_law_names_the_choices():
    with pytest.raises(ValueError, match="unknown contact law 'ode'; valid: hunt_crossley"):
        contact_parameters(eps=0.5, mass=1.0, stiffness=1e4, approach_speed=0.5, accel=G, law="ode")


def test_advise_judges_the_laws_models_in_delivered_restitution():
    a = advise(0.5, 1.0, 1e4, 0.5, accel=G, restitution="kinematic", law="mujoco_soft")
    by_name = {m.name: m for m in a.models}
    assert set(by_name) == {"mujoco_dampratio", "mujoco_default", "mujoco_soft_exact"}
    assert by_name["mujoco_soft_exact"].adequate and a.cheapest == "mujoco_soft_exact"
    assert abs(by_name["mujoco_dampratio"].delivered - 0.5) > 0.01  # the classic zeta misses under load
    assert by_name["mujoco_default"].state == "creep"


def test_critical_speed_separates_above_and_not_below():
    law = get_law("kelvin_voigt")
    m, k = 1.0, 1e4
    v = critical_speed(0.5, m, k, G, law=law)
    for factor, state in ((1.001, "separation"), (0.999, "nonseparation")):
        xi = law.load_factor(law.load(m, k, factor * v, G))
        assert law.damping_for(0.5, xi).state in ((state,) if state == "separation" else (state, "creep"))


def test_predict_bounces_under_a_law():
    scene = dataclasses.replace(ball.Scene(), stiffness=1e5, eps=0.6)
    seq = predict_bounces(scene, "classic_zeta", law="kelvin_voigt")
    law = get_law("kelvin_voigt")
    zeta = -np.log(0.6) / np.sqrt(np.pi**2 + np.log(0.6) ** 2)
    np.testing.assert_allclose(seq["p"], zeta, rtol=1e-15)
    expected = law.impact(zeta, seq["xi"]).e_n * seq["v"]
    np.testing.assert_allclose(seq["v_out"], expected, rtol=1e-12)
    assert seq["states"][-1] != "separation" and all(s == "separation" for s in seq["states"][:-1])
    with pytest.raises(ValueError, match="model 'exact' is not a model of law 'kelvin_voigt'"):
        predict_bounces(scene, "exact", law="kelvin_voigt")
