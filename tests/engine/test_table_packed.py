"""The scalar fast path's packed table gives the array path's alpha bit for bit."""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine.table import (
    EPS_MIN,
    XI_MAX,
    alpha_tabulated,
    kinematic_table_arrays,
    pack_table,
    packed_matrix,
    packed_vector,
    scalar_lookup,
    table_arrays,
)
from contactalpha.engine.table_build import random_points


@pytest.mark.parametrize("arrays", [table_arrays, kinematic_table_arrays])
def test_pack_table_round_trips_every_array(arrays):
    tables = arrays()
    flat = pack_table(tables)
    for k, a in enumerate(tables):
        got = packed_matrix(flat, k) if a.ndim == 2 else packed_vector(flat, k)
        np.testing.assert_array_equal(got, a)
        assert got.shape == a.shape


@pytest.mark.parametrize("kind", ["energetic", "kinematic"])
def test_scalar_alpha_is_the_array_alpha_bit_for_bit(kind):
    eps, xi = random_points(2000, seed=5)
    eps = np.concatenate([eps, [EPS_MIN, 1.0, 0.5, 0.999999]])
    xi = np.concatenate([xi, [0.0, XI_MAX, XI_MAX, 0.0]])
    array = ca.alpha(eps, xi, restitution=kind)
    scalar = np.array([ca.alpha(float(e), float(x), restitution=kind) for e, x in zip(eps, xi, strict=True)])
    tabulated = np.array(
        [alpha_tabulated(float(e), float(x), restitution=kind) for e, x in zip(eps, xi, strict=True)]
    )
    np.testing.assert_array_equal(scalar, array)
    np.testing.assert_array_equal(tabulated, array)
    f, flat = scalar_lookup(kind)
    assert np.isnan(f(EPS_MIN / 2, 0.3, flat)) and np.isnan(f(0.5, XI_MAX * 1.001, flat))


def test_scalar_path_outside_the_table_still_words_the_error():
    with pytest.raises(ValueError, match=r"eps = 0.005 .*exact_solve"):
        ca.alpha(0.005, 0.3)
    with pytest.raises(ValueError, match=r"xi = 1.0 "):
        ca.alpha(0.5, 1.0)
    with pytest.raises(ValueError, match="e_N = 0.0 has no kinematic inverse"):
        ca.alpha(0.0, 0.3, restitution="kinematic")
    with pytest.raises(ValueError, match="restitution = 'newton'"):
        ca.alpha(0.5, 0.3, restitution="newton")
