"""The laws' scales from logarithms where plain powers under- or overflow (issue 34, R7), and R8's checks."""

import math

import numpy as np
import pytest

from contactalpha.laws import LAWS, get_law
from contactalpha.parameters.engine_block import engine_block
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.scene.advisor import advise

KV, HT = "kelvin_voigt", "hertz_tsuji"


@pytest.mark.parametrize("law", [law.name for law in LAWS])
def test_length_scale_at_extreme_speeds_is_its_formula_in_logarithms(law):
    law = get_law(law)
    n1 = law.exponent + 1.0
    for m, k, v in ((1.0, 1e5, 1e-300), (2.0, 3e4, 1e150), (0.5, 1e-200, 1e100)):
        log_d = (math.log(n1 / 2.0) + math.log(m) + 2.0 * math.log(v) - math.log(k)) / n1
        assert law.length_scale(m, k, v) == pytest.approx(math.exp(log_d), rel=1e-13, abs=0.0)


@pytest.mark.parametrize("law", [law.name for law in LAWS])
def test_moderate_scales_stay_the_plain_powers(law):
    law = get_law(law)
    n1 = law.exponent + 1.0
    m, k, v, a = 2.0, 3e4, 0.7, 9.81
    d = (n1 / 2.0 * m * v * v / k) ** (1.0 / n1)
    assert law.length_scale(m, k, v) == d
    assert law.load(m, k, v, a) == a * d / (v * v)


def test_a_scale_beyond_the_doubles_is_refused_by_name():
    with pytest.raises(ValueError, match="approach_speed = 1e-300 give law 'kelvin_voigt' a length scale"):
        get_law("kelvin_voigt").length_scale(1e-300, 1e300, 1e-300)


@pytest.mark.parametrize("law", [law.name for law in LAWS])
def test_a_huge_load_has_load_factor_one_not_nan(law):
    assert get_law(law).load_factor(1e300) == 1.0
    assert get_law(law).load_factor(1e30) == 1.0


def test_a_tiny_speed_without_load_keeps_its_length_scale():
    cp = contact_parameters(e_N=0.5, mass=1.0, stiffness=1e5, approach_speed=1e-160, accel=0.0, law=KV)
    assert cp.delta_star == pytest.approx(1e-160 / math.sqrt(1e5), rel=1e-13, abs=0.0)
    assert cp.xi == 0.0


def test_a_huge_speed_without_load_is_unloaded():
    cp = contact_parameters(e_N=0.5, mass=1.0, stiffness=1e5, approach_speed=1e160, accel=0.0, law=KV)
    assert cp.xi == 0.0 and cp.e_n == pytest.approx(0.5, abs=1e-9)


@pytest.mark.parametrize("speed", [1e-30, 1e-160])
def test_a_load_too_large_for_the_speed_names_the_scene_not_xi(speed):
    with pytest.raises(ValueError, match=f"accel = 9.81 m/s\\^2 at approach_speed = {speed!r} m/s"):
        contact_parameters(e_N=0.5, mass=1.0, stiffness=1e5, approach_speed=speed, accel=9.81, law=HT)


@pytest.mark.parametrize("law", [law.name for law in LAWS])
def test_a_negative_damping_has_no_physical_damping(law):
    law = get_law(law)
    with pytest.raises(ValueError, match=f"{law.damping} = -1.0 is outside"):
        law.physical_damping(-1.0, 1.0, 1e5, 0.5)
    with pytest.raises(ValueError, match="damping = -1.0 is outside"):
        law.damping_from_physical(-1.0, 1.0, 1e5, 0.5)


def test_flags_are_bools_not_truthy_text():
    with pytest.raises(ValueError, match="exact = 'no' is not a bool"):
        get_law("kelvin_voigt").fast_damping(0.5, 0.2, exact="no")
    with pytest.raises(ValueError, match="refine = 'yes' is not a bool"):
        engine_block("mujoco", 0.5, 1.0, 1e4, 0.5, 9.81, refine="yes")


@pytest.mark.parametrize(("name", "value"), [("speeds", (0.1, 1.0)), ("costs", {"mujoco_soft_exact": 1.0})])
def test_advise_with_a_law_refuses_what_it_would_ignore(name, value):
    with pytest.raises(ValueError, match=f"{name} = .* is not taken with law 'mujoco_soft'"):
        advise(0.5, 1.0, 1e4, 0.5, accel=9.81, restitution="kinematic", law="mujoco_soft", **{name: value})
    assert np.isfinite(advise(0.5, 1.0, 1e4, 0.5, accel=9.81, restitution="kinematic", law="mujoco_soft").xi)
