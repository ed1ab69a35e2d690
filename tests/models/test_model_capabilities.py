"""Every registered model against its own capability fields: law, restitutions, domain, eps = 0, load."""

import numpy as np
import pytest

from contactalpha.laws import LAWS
from contactalpha.models import ALL_MODELS, MODELS, REGISTRY, alpha

LAW_NAMES = {law.name for law in LAWS}


@pytest.mark.parametrize("model", REGISTRY, ids=lambda m: m.name)
def test_model_keeps_its_capabilities(model):
    assert ALL_MODELS[model.name] is model
    assert model.law in LAW_NAMES
    assert model.contact_law.name == model.law
    assert (model.name in MODELS) == (model.law == "hunt_crossley")
    assert set(model.restitutions) <= {"energetic", "kinematic"} and model.restitutions
    for restitution in ("energetic", "kinematic"):
        if restitution in model.restitutions:
            value = alpha(
                np.array([0.3, 0.8]), np.array([0.0, 0.2]), model=model.name, restitution=restitution
            )
            assert np.all(np.isfinite(value)) and np.all(value >= 0.0)
            if not model.uses_xi:
                again = alpha(
                    np.array([0.3, 0.8]), np.array([0.5, 0.7]), model=model.name, restitution=restitution
                )
                np.testing.assert_array_equal(again, value)
        else:
            with pytest.raises(ValueError, match=f"model '{model.name}' is defined for .*; restitution="):
                alpha(0.5, 0.2, model=model.name, restitution=restitution)
    first = model.restitutions[0]
    if model.handles_zero:
        assert np.isfinite(alpha(0.0, 0.2, model=model.name, restitution=first))
    else:
        with pytest.raises(ValueError, match="0.0 is outside the valid range"):
            alpha(0.0, 0.2, model=model.name, restitution=first)
    with pytest.raises(ValueError, match="outside the valid range"):
        alpha(1.5, 0.2, model=model.name, restitution=first)


@pytest.mark.parametrize("model", [m for m in REGISTRY if m.name.endswith("_exact")], ids=lambda m: m.name)
@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_exact_models_deliver_their_target_under_load(model, restitution):
    target = np.array([0.1, 0.5, 0.9])
    xi = np.array([0.05, 0.3, 0.8])
    p = alpha(target, xi, model=model.name, restitution=restitution)
    np.testing.assert_allclose(model.contact_law.restitution(p, xi, restitution), target, atol=1e-9)


def test_unknown_model_names_the_choices():
    with pytest.raises(ValueError, match="unknown model 'bullet'; known models: classic_zeta, closed_form"):
        alpha(0.5, 0.1, model="bullet")
