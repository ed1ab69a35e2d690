"""contact_force (paper Eq. 41) refuses what is not a finite real penetration or rate."""

import numpy as np
import pytest

import contactalpha as ca


@pytest.mark.parametrize(
    "delta, delta_dot, match",
    [
        (np.nan, 0.1, r"delta = nan is outside the valid range \(-inf, inf\)"),
        (np.inf, 0.1, "delta = inf"),
        (None, 0.1, "delta = None is not a number"),
        (1e-5, np.nan, "delta_dot = nan"),
        (1e-5, -np.inf, "delta_dot = -inf"),
        (1e-5, None, "delta_dot = None"),
        (np.array([1e-5 + 0j]), 0.1, r"delta = \(1e-05\+0j\) is complex"),
        (1e-5, np.array([0.1 + 2j]), "delta_dot = .* is complex"),
    ],
)
def test_non_finite_none_or_complex_state_is_rejected(delta, delta_dot, match):
    with pytest.raises(ValueError, match=match):
        ca.contact_force(delta, delta_dot, 0.5, 1.4e8, 0.6, 0.3, model="hu_guo")


def test_complex_eps_is_rejected_not_cut_to_its_real_part():
    for model in ("exact", "hu_guo"):
        with pytest.raises(ValueError, match="eps = .* is complex"):
            ca.alpha(np.array([0.5 + 0.1j]), 0.2, model=model)


def test_valid_state_still_gives_eq_41():
    a = ca.alpha(0.6, 0.3, model="hu_guo")
    F = ca.contact_force(np.array([-1e-5, 2e-5]), -0.1, 0.5, 1.4e8, 0.6, 0.3, model="hu_guo")
    np.testing.assert_allclose(F, [0.0, 1.4e8 * 2e-5**1.5 * (1 - a * 0.1 / 0.5)], rtol=1e-14)
