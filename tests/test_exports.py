"""The package's front door: every name in ``_EXPORTS`` is the object its module defines."""

import importlib

import pytest

import contactalpha

# Names a user of the issues' front doors calls as ``contactalpha.<name>`` (issues 11 and 12).
FRONT_DOOR = ("contact_parameters", "advise", "critical_speed", "predict_bounces", "Scene", "solve_alpha")


@pytest.mark.parametrize("name", sorted(contactalpha._EXPORTS))
def test_every_export_is_its_modules_object(name):
    module = importlib.import_module(f"contactalpha.{contactalpha._EXPORTS[name]}")
    assert getattr(contactalpha, name) is getattr(module, name)
    assert name in contactalpha.__all__ and name in dir(contactalpha)


def test_front_door_names_are_exported():
    assert set(FRONT_DOOR) <= set(contactalpha._EXPORTS)


def test_unknown_name_raises_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        contactalpha.nope  # noqa: B018


def test_exported_advisor_and_threshold_work_together():
    """critical_speed's scene, advised just above and below v_crit, separates and does not (values)."""
    m, k, a, eps = 0.5, 1.4e8, 9.81, 0.8
    v = contactalpha.critical_speed(eps, m, k, a)
    costs = {name: 1e-6 for name in importlib.import_module("contactalpha.models").MODELS}
    above = contactalpha.advise(eps, m, k, v * 1.01, accel=a, costs=costs)
    below = contactalpha.advise(eps, m, k, v * 0.99, accel=a, costs=costs)
    assert above.exact_state == "separation" and below.exact_state != "separation"
