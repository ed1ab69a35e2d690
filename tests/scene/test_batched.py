"""The batched front door: arrays of scenes give every engine's parameters as arrays."""

import numpy as np
import pytest

from contactalpha.engine.solver import solve_alpha
from contactalpha.parameters.batch import batched_parameters
from contactalpha.parameters.front_door import contact_parameters


def scenes(n=64, seed=1):
    rng = np.random.default_rng(seed)
    return {
        "mass": rng.uniform(0.1, 2.0, n),
        "stiffness": 10.0 ** rng.uniform(6.0, 9.0, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 50.0, n),
        "e_N": rng.uniform(0.05, 0.95, n),
    }


def test_arrays_give_the_scalar_calls_numbers():
    s = scenes()
    out = contact_parameters(**s)
    for i in range(0, 64, 7):
        one = contact_parameters(**{k: float(v[i]) for k, v in s.items()})
        assert out.xi[i] == pytest.approx(one.xi, rel=1e-14)
        for engine, values in one.engines.items():
            for name, value in values.items():
                assert np.broadcast_to(out.engines[engine][name], (64,))[i] == pytest.approx(value, rel=1e-12)


def test_batched_alpha_delivers_the_target_through_the_solver():
    s = scenes(6, seed=3)
    out = contact_parameters(**s)
    for i in range(6):
        sol = solve_alpha(float(s["e_N"][i]), float(out.xi[i]), restitution="kinematic")
        assert out.damping[i] == pytest.approx(sol.alpha, rel=1e-6)


def test_outside_the_table_is_nan_not_a_number():
    out = batched_parameters([1.0, 1.0], [1e8, 1e8], [1.0, 1.0], [10.0, 10.0], [0.5, 0.001])
    assert list(out.ok) == [True, False]
    assert np.isnan(out.engines["opensim"]["dissipation"][1]) and np.isfinite(out.damping[0])


def test_bad_input_names_the_value():
    with pytest.raises(ValueError, match="mass"):
        batched_parameters([1.0, -1.0], 1e8, 1.0, 10.0, 0.5)
    with pytest.raises(ValueError, match=r"e_N\[1\] = 1.5"):
        batched_parameters(1.0, 1e8, 1.0, 10.0, [0.5, 1.5])


def test_n1_laws_batched_damping_is_the_laws_exact_inverse():
    from contactalpha.laws import get_law

    law = get_law("kelvin_voigt")
    out = batched_parameters([0.5, 0.5], [1e4, 2e4], [0.5, 1.0], [9.81, 30.0], [0.5, 0.8], law=law)
    assert sorted(out.engines) == ["pybullet"]
    for i in range(2):
        exact = law.damping_for([0.5, 0.8][i], float(out.xi[i]), "kinematic").damping
        assert out.damping[i] == pytest.approx(float(exact), rel=1e-7)
        c = 2 * out.damping[i] * ([1e4, 2e4][i] * 0.5) ** 0.5
        assert out.engines["pybullet"]["pair_damping"][i] == pytest.approx(c, rel=1e-14)


def test_a_scene_whose_length_scale_is_beyond_the_doubles_refuses_the_batch():
    # The load factor's row kernel flags the scale; the batch then raises length_scale's error.
    mass = np.array([1.0, 1e-300, 1.0])
    stiffness = np.array([1e8, 1e300, 1e8])
    speed = np.array([1.0, 1e-300, 1.0])
    with pytest.raises(
        ValueError, match=r"mass = 1e-300 kg, stiffness = 1e\+300 .*beyond the range of double"
    ):
        contact_parameters(mass=mass, stiffness=stiffness, approach_speed=speed, accel=9.81, e_N=0.5)
