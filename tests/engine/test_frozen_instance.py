"""frozen_instance builds the same frozen dataclass as its __init__, for the scalar fast paths."""

import dataclasses

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine.driver import ImpactResult, frozen_instance


def test_scalar_impact_result_equals_the_array_path_and_stays_frozen():
    r = ca.impact(0.5, 0.3)
    full = ca.impact(np.asarray(0.5), np.asarray(0.3))
    assert type(r) is ImpactResult
    assert r == ImpactResult(**dataclasses.asdict(r))
    assert dataclasses.asdict(r) == {
        k: v.item() if hasattr(v, "item") else v for k, v in dataclasses.asdict(full).items()
    }
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.eps = 0.1


def test_contact_parameters_is_a_frozen_dataclass_with_every_field():
    cp = ca.contact_parameters(0.8, mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=9.81)
    assert cp == type(cp)(**{f.name: getattr(cp, f.name) for f in dataclasses.fields(cp)})
    with pytest.raises(dataclasses.FrozenInstanceError):
        cp.damping = 1.0


def test_frozen_instance_refuses_missing_or_unknown_fields():
    values = dataclasses.asdict(ca.impact(0.5, 0.3))
    with pytest.raises(TypeError, match="takes the fields"):
        frozen_instance(ImpactResult, **{k: v for k, v in values.items() if k != "e_n"})
    with pytest.raises(TypeError, match="takes the fields"):
        frozen_instance(ImpactResult, **dict(values, e_N=0.0))
