"""MuJoCo's step table and the batch at the step (``stepping.table``, ``scene.stepped_batch``).

The table is checked against the step map's exact phase mean (``delivered.over_phase``) in
physical units, not through the table's own code: at its nodes, and through the batch inverse's
answers at random scenes.
"""

import math
import shutil

import numpy as np
import pytest

from contactalpha import contact_parameters
from contactalpha.laws import get_law
from contactalpha.stepping import mujoco_map
from contactalpha.stepping.delivered import over_phase
from contactalpha.stepping.registry import stepper
from contactalpha.stepping.table import (
    ERROR_TOL,
    F_MAX,
    F_MEAN,
    F_MIN,
    load_step_table,
    step_table,
    table_path,
)

S = stepper("mujoco")
# The accuracy docs/stepping.md states for the table's rows (measured max 1.05e-3 in the study).
TABLE_ACCURACY = 2e-3
GRID = S.table.grid
H = 0.002


@pytest.fixture(scope="module")
def table():
    return step_table("mujoco", S.table)


def test_the_table_is_the_maps_phase_mean_at_its_nodes_in_physical_units(table):
    # A node (x, xi, zeta) is the scene of mass m, stiffness k = m omega^2 at step x / omega,
    # speed v and load A omega v: the map's mean there must be the node's (scale invariance).
    rng = np.random.default_rng(3)
    law = get_law("mujoco_soft")
    checked = 0
    while checked < 12:
        i, kx, j = (
            rng.integers(1, GRID.n_x + 1),
            rng.integers(0, GRID.n_xi + 1),
            rng.integers(0, GRID.n_c + 1),
        )
        cell = table.table[i, kx, j]
        if not np.isfinite(cell[F_MEAN]):
            continue
        x, xi, zeta = GRID.steps()[i], GRID.loads()[kx], GRID.dampings()[j]
        m, omega, v = 0.3, 40.0, 0.7
        A = float(law.scaled_load(xi))
        p = mujoco_map.pack(omega**2, 2.0 * zeta * omega, 0.9)
        st = over_phase("mujoco", p, x / omega, v, A * omega * v)
        assert st.mean == pytest.approx(cell[F_MEAN], abs=1e-7)
        assert st.minimum == pytest.approx(cell[F_MIN], abs=1e-7)
        assert st.maximum == pytest.approx(cell[F_MAX], abs=1e-7)
        del m
        checked += 1


def test_the_step_zero_row_is_the_continuous_law(table):
    law = get_law("mujoco_soft")
    for kx in (0, 7, 20):
        for j in (0, 10, 30):
            e = law.restitution(GRID.dampings()[j], GRID.loads()[kx], "kinematic")
            assert table.table[0, kx, j, F_MEAN] == pytest.approx(float(e), abs=1e-12)


def scenes(n, seed, pushed=False):
    """Drops under gravity (``pushed``: pressed by 1-4 times the weight more, slower)."""
    rng = np.random.default_rng(seed)
    m = np.exp(rng.uniform(np.log(0.05), np.log(10.0), n))
    steps = rng.uniform(10.0, 60.0, n)
    k = m * (np.pi / (steps * H)) ** 2
    v = rng.uniform(0.2, 1.0, n) if pushed else rng.uniform(0.5, 2.5, n)
    a = 9.81 * (rng.uniform(2.0, 5.0, n) if pushed else np.ones(n))
    e = rng.uniform(0.3, 0.9, n)
    return m, k, v, a, e


@pytest.mark.parametrize("pushed", [False, True])
def test_a_batch_at_the_step_delivers_its_targets_by_the_map(pushed):
    # Under gravity alone the table answers most rows; pressed harder, most are solved exactly.
    m, k, v, a, e = scenes(8, seed=5, pushed=pushed)
    cp = contact_parameters(
        mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=H
    )
    st = cp.stepped
    assert np.all(cp.ok)
    assert np.sum(st.source == "table") >= (0 if pushed else 4)
    for i in range(m.size):
        p = mujoco_map.pack(-cp.block["solref"][0][i], -cp.block["solref"][1][i], cp.block["solimp"][0][i])
        exact = over_phase("mujoco", p, H, v[i], a[i])
        # The table's rows: within the accuracy docs/stepping.md states (its estimate is not a bound).
        bound = TABLE_ACCURACY if st.source[i] == "table" else 1e-6
        assert abs(exact.mean - e[i]) <= bound, (i, exact.mean, e[i], st.source[i])
        assert st.mean_error[i] <= (ERROR_TOL if st.source[i] == "table" else 1e-6)
        # The range one drop sees: the table's, within the mean's accuracy plus its interpolation.
        assert st.minimum[i] == pytest.approx(exact.minimum, abs=0.02)
        assert st.maximum[i] == pytest.approx(exact.maximum, abs=0.02)
        assert st.minimum[i] <= e[i] <= st.maximum[i]


def test_batch_rows_agree_with_one_scenes_exact_answer():
    m, k, v, a, e = scenes(3, seed=9)
    cp = contact_parameters(
        mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=H
    )
    for i in range(3):
        one = contact_parameters(mass=m[i], stiffness=k[i], approach_speed=v[i], accel=a[i], e_N=e[i],
                                 engine="mujoco", timestep=H)  # fmt: skip
        # Both deliver the target; their dampings differ by the table's error over the mean's slope.
        assert cp.stepped.law_damping[i] == pytest.approx(one.stepped.law_damping, rel=2e-2)
        assert cp.block["solref"][0][i] == one.block["solref"][0]
        if cp.stepped.source[i] == "exact":
            assert cp.stepped.law_damping[i] == one.stepped.law_damping
        assert cp.stepped.continuous_mean[i] == pytest.approx(one.stepped.continuous_mean, abs=TABLE_ACCURACY)


def test_an_unreachable_row_is_nan_in_every_number_and_the_others_unchanged():
    m, k, v, a, e = scenes(3, seed=2)
    k2 = k.copy()
    k2[1] = m[1] * (2.5 / H) ** 2  # omega h = 2.5: past the explicit step's stability
    cp = contact_parameters(
        mass=m, stiffness=k2, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=H
    )
    ref = contact_parameters(mass=m[[0, 2]], stiffness=k[[0, 2]], approach_speed=v[[0, 2]], accel=a[[0, 2]],
                             e_N=e[[0, 2]], engine="mujoco", timestep=H)  # fmt: skip
    assert list(cp.ok) == [True, False, True]
    assert "mujoco's step" in cp.reason[1] and "the nearest mean e_N met is" in cp.reason[1]
    assert math.isnan(cp.block["solref"][0][1]) and math.isnan(cp.block["solref"][1][1])
    assert math.isnan(cp.stepped.mean[1]) and math.isnan(cp.stepped.law_damping[1])
    for key in ("solref",):
        for part in range(2):
            np.testing.assert_array_equal(cp.block[key][part][[0, 2]], ref.block[key][part])


def test_an_eps_batch_and_a_batch_of_another_engine_are_solved_exactly():
    m, k, v, a, e = scenes(2, seed=4)
    cp = contact_parameters(
        mass=m, stiffness=k, approach_speed=v, accel=a, eps=e, engine="mujoco", timestep=H
    )
    assert list(cp.stepped.source) == ["exact", "exact"]
    for i in range(2):
        p = mujoco_map.pack(-cp.block["solref"][0][i], -cp.block["solref"][1][i], 0.9)
        assert over_phase("mujoco", p, H, v[i], a[i]).eps_mean == pytest.approx(e[i], abs=1e-6)
    h = 1e-3
    k = m * (np.pi / (30 * h)) ** 2
    cp = contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="drake", timestep=h)
    assert list(cp.stepped.source) == ["exact", "exact"]
    for i in range(2):
        d = cp.block["hunt_crossley_dissipation"][i]
        kk = cp.block["point_contact_stiffness"][i]
        p = stepper("drake").pack(mass=m[i], stiffness_ball=kk, dissipation_ball=d, stiffness_ground=kk,
                                  dissipation_ground=d)  # fmt: skip
        assert over_phase("drake", p, h, v[i], a[i]).mean == pytest.approx(e[i], abs=1e-6)


def test_verify_refuses_a_batch():
    m, k, v, a, e = scenes(2, seed=4)
    with pytest.raises(ValueError, match="verify= takes one scene"):
        contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=H,
                           verify=8)  # fmt: skip


def test_a_changed_table_file_is_refused(tmp_path):
    bad = tmp_path / "step_table_mujoco.npz"
    shutil.copy(table_path("mujoco"), bad)
    with np.load(bad) as z:
        arrays = {name: z[name] for name in z.files}
    arrays["table"] = arrays["table"].copy()
    arrays["table"][5, 5, 5, F_MEAN] += 1e-9
    np.savez_compressed(bad, **arrays)
    with pytest.raises(ValueError, match="checksum"):
        load_step_table(bad, GRID)
    bad.write_bytes(b"not a table")
    with pytest.raises(ValueError, match="cannot be read"):
        load_step_table(bad, GRID)
