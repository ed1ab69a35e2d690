from functools import cache

import numpy as np
import pytest

from contactalpha.engine import tableau as t

N = t.N_STAGES


def test_row_sums_equal_nodes():
    np.testing.assert_allclose(t.A[:N, :N].sum(axis=1), t.C[:N], atol=1e-15)


def test_weights_sum_to_one_and_estimators_to_zero():
    assert abs(t.B.sum() - 1.0) < 1e-14
    assert abs(t.E3.sum()) < 1e-14
    assert abs(t.E5.sum()) < 1e-14


def test_stage_matrix_is_explicit():
    assert np.all(np.triu(t.A) == 0.0)


# Butcher's order conditions: a method of order p has sum_i b_i Phi_i(tree) = 1 / gamma(tree)
# for every rooted tree with at most p nodes (Hairer, Norsett & Wanner I, Sect. II.2).
@cache
def rooted_trees(n):
    """Rooted trees with ``n`` nodes, each a sorted tuple of its subtrees (1, 1, 2, 4, 9, 20, 48, ...)."""
    if n == 1:
        return ((),)

    def forests(nodes, largest):
        if nodes == 0:
            yield ()
            return
        for size in range(min(nodes, largest), 0, -1):
            for tree in rooted_trees(size):
                for rest in forests(nodes - size, size):
                    yield (tree, *rest)

    return tuple(sorted({tuple(sorted(f)) for f in forests(n - 1, n - 1)}))


def nodes(tree):
    return 1 + sum(nodes(sub) for sub in tree)


def density(tree):
    """gamma(tree): the exact solution's Taylor coefficient is 1 / gamma."""
    g = nodes(tree)
    for sub in tree:
        g *= density(sub)
    return g


def stage_weights(A, tree):
    """Phi_i(tree) for every stage i: the product over subtrees of (A Phi(subtree))_i."""
    phi = np.ones(A.shape[0])
    for sub in tree:
        phi = phi * (A @ stage_weights(A, sub))
    return phi


def order_defect(A, b, order):
    """Largest |b . Phi(tree) - 1/gamma(tree)| over the trees with exactly ``order`` nodes."""
    return max(abs(b @ stage_weights(A, tree) - 1.0 / density(tree)) for tree in rooted_trees(order))


def method_order(A, b, tol=1e-13):
    order = 0
    while order < 10 and order_defect(A, b, order + 1) < tol:
        order += 1
    return order


def test_there_are_200_trees_up_to_order_eight():
    assert [len(rooted_trees(n)) for n in range(1, 9)] == [1, 1, 2, 4, 9, 20, 48, 115]


def test_weights_meet_all_200_order_conditions_of_order_eight_and_not_nine():
    A = t.A[:N, :N]
    for q in range(1, t.ORDER + 1):
        assert order_defect(A, t.B, q) < 2e-15, q
    assert order_defect(A, t.B, t.ORDER + 1) > 1e-6  # exactly order 8


def test_embedded_pair_is_order_eight_minus_order_five_and_minus_order_three():
    # E5 = b - b5 and E3 = b - b3, with b5 of order exactly 5 and b3 of order exactly 3, both on
    # the same 12 stages (the FSAL stage K[12] carries no weight), as in SciPy's DOP853.
    A = t.A[:N, :N]
    assert t.E5[N] == 0.0 and t.E3[N] == 0.0
    assert method_order(A, t.B - t.E5[:N]) == 5
    assert method_order(A, t.B - t.E3[:N]) == 3


def mutants():
    """Copies of (A, B, E5, E3) with one plausible typo each."""
    A, B, E5, E3 = (t.A[:N, :N].copy(), t.B.copy(), t.E5[:N].copy(), t.E3[:N].copy())
    transposed_digits = A.copy()
    transposed_digits[8, 5] = 2.79520996994467083049415600797e1  # 27.592... typed as 27.952...
    swapped_in_row = A.copy()
    swapped_in_row[9, 5], swapped_in_row[9, 6] = swapped_in_row[9, 6], swapped_in_row[9, 5]
    e5_swapped = E5.copy()
    e5_swapped[5], e5_swapped[6] = e5_swapped[6], e5_swapped[5]
    e3_swapped = E3.copy()
    e3_swapped[8], e3_swapped[11] = e3_swapped[11], e3_swapped[8]
    return {
        "A digits": (transposed_digits, B, E5, E3),
        "A row swap": (swapped_in_row, B, E5, E3),
        "E5 swap": (A, B, e5_swapped, E3),
        "E3 swap": (A, B, E5, e3_swapped),
    }


@pytest.mark.parametrize("name", list(mutants()))
def test_the_conditions_catch_a_single_typo(name):
    A, B, E5, E3 = mutants()[name]
    orders = (method_order(A, B), method_order(A, B - E5), method_order(A, B - E3))
    assert orders != (8, 5, 3)
