import numpy as np

from contactalpha.engine import codes
from contactalpha.engine.boundary import boundary_kernel
from contactalpha.engine.driver import impact
from contactalpha.engine.kernel import impact_kernel
from contactalpha.engine.scaling import scaled_load
from contactalpha.engine.solver import solve_alpha, solve_table


def _slots(prefix):
    return {name: value for name, value in vars(codes).items() if name.startswith(prefix)}


def test_each_output_layout_numbers_its_slots_once_and_without_gaps():
    for prefix, size in (("OUT_", codes.N_OUT), ("SOL_", codes.N_SOLVE_OUT), ("BND_", codes.N_BND_OUT)):
        assert sorted(_slots(prefix).values()) == list(range(size)), prefix
    assert sorted(_slots("REC_").values()) == list(range(codes.N_REC))


def test_end_states_and_statuses_are_one_to_one():
    assert len(set(codes.END_STATES.values())) == len(codes.END_STATES)
    assert len(set(codes.STATUS.values())) == len(codes.STATUS)
    assert all(codes.END_STATES[code] == name for name, code in codes.STATE_CODES.items())


def test_kernel_row_slots_agree_with_the_public_result():
    out, _ = impact_kernel(
        0.3, float(scaled_load(0.2)), 1e-12, 1e-14, 2_000_000, np.empty((0, codes.N_REC)), np.inf
    )
    r = impact(0.3, 0.2)
    assert out.shape == (codes.N_OUT,)
    assert np.sqrt(out[codes.OUT_EPS2]) == r.eps
    assert codes.END_STATES[int(out[codes.OUT_STATE])] == r.state
    assert codes.STATUS[int(out[codes.OUT_STATUS])] == r.status
    assert out[codes.OUT_X_MAX] == r.x_max
    assert out[codes.OUT_X_END] == r.x_end
    assert out[codes.OUT_STEPS] == r.steps
    assert out[codes.OUT_NFEV] == r.nfev


def test_solver_row_slots_agree_with_the_public_solution():
    table, _ = solve_table([0.5, 0.5], [0.0, 0.3])
    s = solve_alpha([0.5, 0.5], [0.0, 0.3])
    assert table.shape == (2, codes.N_SOLVE_OUT)
    assert np.array_equal(table[:, codes.SOL_ALPHA], s.alpha)
    assert np.array_equal(table[:, codes.SOL_EPS], s.eps_reached)
    assert [codes.END_STATES[int(c)] for c in table[:, codes.SOL_STATE]] == list(s.state)
    assert np.array_equal(table[:, codes.SOL_IMPACTS], s.impacts)
    assert np.array_equal(table[:, codes.SOL_X_MAX], s.x_max)


def test_boundary_search_without_load_ends_as_no_bracket():
    # Without a load every alpha separates: the search climbs past its limit and says so (~8 s).
    alpha_b, eps_b, status = boundary_kernel(0.0, 1e-12, 1e-14, 10**8)
    assert status == codes.NO_BRACKET
    assert np.isnan(alpha_b) and np.isnan(eps_b)
