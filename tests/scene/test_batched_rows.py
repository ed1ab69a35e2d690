"""Batched scenes of every law: a row without an answer is flagged, the others keep their numbers."""

import numpy as np
import pytest
from scipy.optimize import brentq

from contactalpha.laws import LAWS
from contactalpha.parameters.batch import batched_parameters
from contactalpha.parameters.front_door import contact_parameters

# Stiffness of each law's scenes, in its own units (MuJoCo's per unit mass with mass 1).
STIFFNESS = {"hunt_crossley": 1e5, "hertz_tsuji": 1e5, "mujoco_soft": 1e4}


@pytest.mark.parametrize("law", [law.name for law in LAWS])
def test_a_row_whose_load_factor_rounds_to_one_is_flagged_and_the_others_keep_their_bits(law):
    k = STIFFNESS.get(law, 1e5)
    good = batched_parameters(1.0, k, 0.5, np.array([9.81, 100.0]), 0.5, law=law)
    mixed = batched_parameters(1.0, k, 0.5, np.array([9.81, 1e30, 100.0]), 0.5, law=law)
    assert list(mixed.ok) == [True, False, True]
    assert np.isnan(mixed.damping[1]) and np.isnan(mixed.xi[1])
    np.testing.assert_array_equal(mixed.damping[[0, 2]], good.damping)
    np.testing.assert_array_equal(mixed.xi[[0, 2]], good.xi)
    for engine, values in mixed.engines.items():
        for name, x in values.items():
            if isinstance(x, np.ndarray) and x.shape == (3,):
                np.testing.assert_array_equal(x[[0, 2]], good.engines[engine][name])


def _linear_load_factor(mass, stiffness, speed, accel):
    """xi of an n = 1 law without impedance, from its definition: x_m solves x^2 = 1 + 2 A x."""
    A = accel * np.sqrt(mass / stiffness) / speed
    x_m = brentq(lambda x: x * x - 1.0 - 2.0 * A * x, 1.0, 2.0 + 2.0 * A, xtol=1e-15, rtol=1e-15)
    w = A * x_m
    return w / (0.5 + w)


def test_batched_load_factor_of_a_linear_law_is_its_definition():
    mass, stiffness, speed = np.array([0.5, 2.0, 1.0]), np.array([1e4, 3e4, 5e3]), np.array([0.3, 1.0, 0.1])
    accel = np.array([9.81, 30.0, 2.0])
    out = batched_parameters(mass, stiffness, speed, accel, 0.5, law="kelvin_voigt")
    for i in range(3):
        xi = _linear_load_factor(mass[i], stiffness[i], speed[i], accel[i])
        assert out.xi[i] == pytest.approx(xi, rel=1e-12)


def test_a_batch_of_forces_divides_each_force_by_its_own_mass():
    mass, force = np.array([0.5, 2.0, 8.0]), np.array([5.0, 5.0, 5.0])
    out = contact_parameters(e_N=0.5, mass=mass, stiffness=1e5, approach_speed=0.5, force=force)
    for i in range(3):
        scene = {"mass": float(mass[i]), "stiffness": 1e5, "approach_speed": 0.5}
        one = contact_parameters(e_N=0.5, accel=5.0 / mass[i], **scene)
        assert out.xi[i] == pytest.approx(one.xi, rel=1e-14)
    assert len(set(np.round(out.xi, 12))) == 3


@pytest.mark.parametrize("target", [np.array([True, True]), np.array(["0.5", "0.4"]), [0.5, "0.4"]])
def test_batched_targets_must_be_numbers(target):
    with pytest.raises(ValueError, match="e_N = .* not a number"):
        batched_parameters(1.0, 1e5, 0.5, 9.81, target)


def test_a_batched_target_out_of_range_is_named_as_the_restitution():
    with pytest.raises(ValueError, match=r"eps\[1\] = 1.5 is outside"):  # and its first bad index
        batched_parameters(1.0, 1e5, 0.5, 9.81, [0.5, 1.5], restitution="energetic")


def test_a_batched_radius_array_gives_each_scene_its_stiffness():
    radius = np.array([0.01, 0.04])
    scene = {"e_N": 0.5, "mass": 1.0, "stiffness": 1e5, "approach_speed": 0.5, "accel": 9.81}
    out = contact_parameters(radius=radius, **scene)
    for i in range(2):
        one = contact_parameters(radius=float(radius[i]), **scene)
        expected = one.engines["opensim"]["stiffness"]
        assert out.engines["opensim"]["stiffness"][i] == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("law", ["kelvin_voigt", "mujoco_soft", "hunt_crossley_linear"])
def test_a_radius_that_no_engine_of_the_law_reads_is_refused(law):
    with pytest.raises(ValueError, match="radius = .* not used by law"):
        batched_parameters([1.0, 1.0], 1e4, 0.5, 9.81, 0.5, law=law, radius=[0.01, 0.02])


def test_lammps_reads_the_radius_of_a_hertz_tsuji_batch():
    out = batched_parameters([1.0, 1.0], 1e4, 0.5, 9.81, 0.5, law="hertz_tsuji", radius=[0.01, 0.02])
    assert list(out.engines["lammps"]["diameter"]) == [0.02, 0.04]


def test_one_scene_of_another_law_refuses_a_radius_too():
    with pytest.raises(ValueError, match="radius = 0.01 is not used by law 'kelvin_voigt'"):
        contact_parameters(
            e_N=0.5, mass=1.0, stiffness=1e4, approach_speed=0.5, accel=9.81, radius=0.01, law="kelvin_voigt"
        )
