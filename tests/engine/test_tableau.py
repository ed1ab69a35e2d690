import numpy as np

from contactalpha.engine import tableau as t


def test_row_sums_equal_nodes():
    n = t.N_STAGES
    np.testing.assert_allclose(t.A[:n, :n].sum(axis=1), t.C[:n], atol=1e-15)


def test_weights_sum_to_one_and_estimators_to_zero():
    assert abs(t.B.sum() - 1.0) < 1e-14
    assert abs(t.E3.sum()) < 1e-14
    assert abs(t.E5.sum()) < 1e-14


def test_order_conditions_up_to_eight_on_quadrature():
    # sum_i b_i c_i^(q-1) = 1/q for q = 1..8: the quadrature part of order 8.
    for q in range(1, 9):
        assert abs(t.B @ t.C[: t.N_STAGES] ** (q - 1) - 1.0 / q) < 1e-14, q


def test_stage_matrix_is_explicit():
    assert np.all(np.triu(t.A) == 0.0)
