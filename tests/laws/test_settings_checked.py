"""Every law checks its integrator settings by name, as the default law does (issue 34, R1)."""

import pytest

from contactalpha.laws import LAWS, get_law

FAMILY = [law.name for law in LAWS if law.name != "hunt_crossley"]
BAD = [
    ({"rtol": -1.0}, "rtol = -1.0"),
    ({"atol": -1.0}, "atol = -1.0"),
    ({"rtol": 0.5}, "rtol = 0.5"),
    ({"rtol": [1e-3]}, "rtol = .* not one real number"),
    ({"rtol": "1e-3"}, "rtol = .* not one real number"),
    ({"max_steps": None}, "max_steps = None"),
    ({"max_steps": 2.5}, "max_steps = 2.5"),
    ({"tolerance": 1e-9}, "unknown settings \\['tolerance'\\]"),
]


@pytest.mark.parametrize("law", ["hunt_crossley", *FAMILY])
@pytest.mark.parametrize(("settings", "message"), BAD)
def test_bad_settings_are_refused_by_name(law, settings, message):
    with pytest.raises(ValueError, match=message):
        get_law(law).impact(0.5, 0.2, **settings)
    with pytest.raises(ValueError, match=message):
        get_law(law).damping_for(0.3, 0.2, "kinematic", **settings)


@pytest.mark.parametrize("law", FAMILY)
def test_good_settings_still_pass_and_change_nothing_visible(law):
    a = get_law(law).impact(0.5, 0.2)
    b = get_law(law).impact(0.5, 0.2, rtol=1e-11, atol=1e-13, max_steps=1_000_000)
    assert b.status == "ok" and b.e_n == pytest.approx(a.e_n, abs=1e-9)


def test_kelvin_voigt_with_default_settings_meets_its_closed_form():
    law = get_law("kelvin_voigt")
    # The numbers: the closed form gives 0.038196; rtol = -1 gave 0.102308 with status ok.
    closed_form = float(law.fast_restitution(0.5, 0.2, "kinematic"))
    assert law.impact(0.5, 0.2).e_n == pytest.approx(closed_form, abs=1e-9)
