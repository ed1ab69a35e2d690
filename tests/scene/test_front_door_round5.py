"""Issue 44's front-door defects: the radius, the target's name, the batch's load and shapes, JSON numbers."""

import json
import math
import warnings

import numpy as np
import pytest

import contactalpha as ca
from contactalpha import cli
from contactalpha.adapters.stepped import ContactStepsWarning
from contactalpha.stepping.delivered import over_phase
from contactalpha.stepping.registry import stepper

PYBULLET = dict(mass=0.5, stiffness=2e4, approach_speed=0.5, accel=9.81, e_N=0.5, engine="pybullet")


@pytest.mark.parametrize("radius", [-1.0, 0.0, math.nan, math.inf])
def test_a_pybullet_radius_that_is_not_positive_is_refused_by_name(radius):
    # S4: -1.0 gave status ok with mean 0.5 and maximum 1.579; nan named the map's internal array "p".
    with pytest.raises(ValueError, match=r"^radius = .* outside the valid range \(0.0, inf\)"):
        ca.contact_parameters(**PYBULLET, timestep="default", radius=radius)
    with pytest.raises(ValueError, match=r"^radius = .* outside the valid range"):
        ca.contact_parameters(**PYBULLET, radius=radius)


def test_a_batchs_bad_pybullet_radius_is_refused_by_its_index():
    with pytest.raises(ValueError, match=r"^radius\[1\] = -1.0 is outside the valid range"):
        ca.contact_parameters(**(PYBULLET | {"mass": [0.5, 0.6]}), timestep="default", radius=[0.05, -1.0])


def test_a_radius_array_of_the_wrong_length_is_named():
    with pytest.raises(
        ValueError, match=r"^radius has shape \(2,\), which does not broadcast with mass's shape \(3,\)"
    ):
        ca.contact_parameters(
            **(PYBULLET | {"mass": [0.5, 0.6, 0.7]}), timestep="default", radius=[0.05, 0.05]
        )
    with pytest.raises(
        ValueError, match=r"^e_N has shape \(2,\), which does not broadcast with mass's shape \(3,\)"
    ):
        ca.contact_parameters(
            mass=[0.5, 0.6, 0.7], stiffness=1e4, approach_speed=0.5, accel=9.81, e_N=[0.5, 0.6]
        )


def test_pybullet_takes_the_radius_with_and_without_the_step():
    # S10b: without timestep the radius was refused ("not used by law 'kelvin_voigt'").
    plain = ca.contact_parameters(**PYBULLET)
    with_radius = ca.contact_parameters(**PYBULLET, radius=0.05)
    assert with_radius.block == plain.block and with_radius.block["contactDamping"] > 0.0
    # A law none of whose engines reads the geometry still refuses it.
    with pytest.raises(ValueError, match="not used by law 'mujoco_soft'"):
        ca.contact_parameters(**(PYBULLET | {"engine": "mujoco"}), radius=0.05)


@pytest.mark.parametrize("target", [1.0, 1.5])
def test_a_target_of_one_at_the_step_is_refused_naming_e_n(target):
    # S15: 1.0 was refused as "target = 1.0" (the map's name), 1.5 as "e_N = 1.5".
    with pytest.raises(ValueError, match=r"^e_N = 1\.[05] is outside the valid range"):
        ca.contact_parameters(**(PYBULLET | {"engine": "mujoco", "e_N": target}), timestep="default")


def test_a_batch_at_the_step_needs_a_load_in_every_row_as_one_scene_does():
    # S14: the batch solved the accel = 0 row at the step (ok, reason "") where one scene refuses.
    scene = dict(
        mass=[0.5, 0.6], stiffness=2e4, approach_speed=0.5, e_N=0.5, engine="mujoco", timestep="default"
    )
    with pytest.raises(ValueError, match=r"timestep needs a load pressing the bodies together"):
        ca.contact_parameters(**(scene | {"mass": 0.5, "e_N": 0.5}), accel=0.0)
    with pytest.raises(ValueError, match=r"load pressing the bodies together in every row: accel\[1\] = 0.0"):
        ca.contact_parameters(**scene, accel=[9.81, 0.0])
    with pytest.raises(ValueError, match=r"in every row: force\[0\] = 0.0"):
        ca.contact_parameters(**scene, force=[0.0, 1.0])


def test_a_batchs_solref_and_solimp_have_the_engines_shape():
    # S11: (nworld, 2) and (nworld, 5), as MJX's and MuJoCo Warp's geom_solref/geom_solimp.
    m = np.array([0.5, 0.6, 0.7])
    for timestep in (None, "default"):
        cp = ca.contact_parameters(
            mass=m, stiffness=1e4, approach_speed=0.5, accel=9.81, e_N=0.5, engine="mujoco", timestep=timestep
        )
        solref, solimp = cp.block["solref"], cp.block["solimp"]
        assert solref.shape == (3, 2) and solimp.shape == (3, 5)
        np.testing.assert_array_equal(solref[:, 0], -1e4 / m)
        np.testing.assert_array_equal(solref[:, 1], -cp.block["damping"])
        np.testing.assert_array_equal(solimp, np.tile([0.9, 0.9, 0.001, 0.5, 2.0], (3, 1)))
        for i in range(3):  # each row is what one scene's call gives
            one = ca.contact_parameters(
                mass=float(m[i]),
                stiffness=1e4,
                approach_speed=0.5,
                accel=9.81,
                e_N=0.5,
                engine="mujoco",
                timestep=timestep,
            )
            assert tuple(solref[i]) == pytest.approx(one.block["solref"], rel=1e-6)  # the batch: its table
            assert tuple(solimp[i]) == one.block["solimp"]


def test_a_batch_flags_the_worlds_with_fewer_than_five_steps_in_contact():
    # S12: at MuJoCo's 2 ms and k = 1e4 N/m, 1 kg spans 14 steps, 0.25 kg 6, 0.1 kg 3, 0.05 kg 2.
    m = np.array([1.0, 0.1, 0.25, 0.05])
    with pytest.warns(
        ContactStepsWarning, match=r"2 of 4 world\(s\) have fewer than 5 steps in contact \(rows 1, 3;"
    ):
        cp = ca.contact_parameters(
            mass=m,
            stiffness=1e4,
            approach_speed=1.0,
            accel=9.81,
            e_N=0.5,
            engine="mujoco",
            timestep="default",
        )
    assert cp.ok.all()
    assert list(cp.stepped.few_steps) == [1, 3]
    # Independently: the map's own drops at the answers' parameters.
    for i in range(4):
        block = {"solref": tuple(cp.block["solref"][i]), "solimp": tuple(cp.block["solimp"][i])}
        p = stepper("mujoco").from_block(block, float(m[i]), None)
        steps = over_phase("mujoco", p, 0.002, 1.0, 9.81).steps_min
        assert (steps < 5) == (i in (1, 3)), (i, steps)


def test_params_engine_timestep_json_gives_the_prediction_as_numbers(capsys):
    # S9: the mean, range and steps were only inside the prose notes.
    argv = [
        "params",
        "--engine",
        "mujoco",
        "--e-n",
        "0.5",
        "--mass",
        "0.5",
        "--stiffness",
        "1e4",
        "--speed",
        "0.5",
        "--accel",
        "9.81",
        "--timestep",
        "default",
        "--json",
    ]
    assert cli.main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    st = data["stepped"]
    one = ca.contact_parameters(
        mass=0.5, stiffness=1e4, approach_speed=0.5, accel=9.81, e_N=0.5, engine="mujoco", timestep="default"
    ).stepped
    for key in ("mean", "minimum", "maximum", "steps_min", "steps_max", "timestep", "damping"):
        assert st[key] == getattr(one, key), key
    assert abs(st["mean"] - 0.5) < 1e-6 and st["minimum"] < 0.5 < st["maximum"] and st["steps_min"] >= 10
    p = stepper("mujoco").from_block(data["parameters"], 0.5, None)
    assert over_phase("mujoco", p, 0.002, 0.5, 9.81).mean == pytest.approx(st["mean"], abs=1e-5)


def test_a_target_with_no_rebound_warns_that_the_bodies_will_not_separate(capsys):
    # S20: eps = 0.7 at xi = 0.71 ends in non-separation (e_N = 0), with no word.
    scene = dict(mass=1.0, stiffness=1e4, approach_speed=0.5, accel=11.824684)
    with pytest.warns(UserWarning, match="the bodies will not separate") as caught:
        cp = ca.contact_parameters(eps=0.7, **scene)
    assert type(caught[0].message).__name__ == "NoSeparationWarning"
    assert cp.xi == pytest.approx(0.71, abs=1e-6) and cp.end_state == "nonseparation" and cp.e_n == 0.0
    with warnings.catch_warnings():
        warnings.filterwarnings("error", "the bodies will not separate")  # a rebound: no warning
        assert ca.contact_parameters(eps=0.9, **scene).end_state == "separation"
    argv = [
        "params",
        "--eps",
        "0.7",
        "--mass",
        "1",
        "--stiffness",
        "1e4",
        "--speed",
        "0.5",
        "--accel",
        "11.824684",
    ]
    with pytest.warns(UserWarning, match="the bodies will not separate"):
        assert cli.main(argv) == 0
    assert "no rebound: the bodies will not separate" in capsys.readouterr().out


def _separates_by_scipy(zeta, mass, stiffness, speed, accel, impedance=0.9):
    """MuJoCo's soft law by SciPy: delta'' = a - max(0, d a + b delta' + s delta); True if it leaves."""
    from scipy.integrate import solve_ivp

    s, b = stiffness / mass, 2.0 * zeta * math.sqrt(stiffness / mass)

    def rhs(t, y):
        return [y[1], accel - max(0.0, impedance * accel + b * y[1] + s * y[0])]

    def leaves(t, y):
        return y[0] + 1e-12 * speed / math.sqrt(s)  # below the surface's own scale: out of contact

    leaves.terminal, leaves.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 200.0 / math.sqrt(s)), [0.0, speed], events=leaves, rtol=1e-11, atol=1e-14)
    return sol.t_events[0].size > 0


def test_critical_speed_of_mujocos_law_next_to_its_boundary():
    # S13: the bisection met the boundary, where the damping's inverse misses its tolerance, and gave NaN.
    from contactalpha.scene.threshold import critical_speed, critical_speed_status

    v_crit = critical_speed(0.2, 1.0, 1e4, 30.0, law="mujoco_soft")
    assert math.isfinite(v_crit) and critical_speed_status(0.2, 1.0, 1e4, 30.0, law="mujoco_soft")[1] == "ok"
    for factor, leaves in ((1.001, True), (0.999, False)):
        cp = ca.contact_parameters(
            eps=0.2, mass=1.0, stiffness=1e4, approach_speed=factor * v_crit, accel=30.0, law="mujoco_soft"
        )
        assert _separates_by_scipy(cp.damping, 1.0, 1e4, factor * v_crit, 30.0) is leaves, factor


def test_critical_speed_at_a_step_limit_says_what_to_change():
    from contactalpha.scene.threshold import critical_speed

    with pytest.warns(
        RuntimeWarning, match=r"step limit exceeded \(max_steps = 1\): give a larger max_steps"
    ):
        assert math.isnan(critical_speed(0.8, 0.5, 1.4e8, 9.81, max_steps=1))


@pytest.mark.parametrize(
    ("scene", "hint"),
    [
        (dict(approach_speed=1e-6, e_N=0.5), "give a faster approach or a smaller load"),
        (dict(approach_speed=0.5, e_N=1e-4), "give e_N >= 0.001"),
    ],
)
def test_a_scene_the_laws_inverse_does_not_resolve_says_what_to_change(scene, hint):
    # S15: both failed with RuntimeError "... root tolerance not reached".
    with pytest.raises(ValueError, match=hint) as err:
        ca.contact_parameters(mass=0.5, stiffness=2e4, accel=9.81, engine="mujoco", **scene)
    assert type(err.value).__name__ == "UnreachableTarget"
    # Farther from the edge, as the message says, the same scene is solved.
    nearer = {"approach_speed": 1e-4} if scene["approach_speed"] < 1e-3 else {"e_N": 1e-3}
    cp = ca.contact_parameters(mass=0.5, stiffness=2e4, accel=9.81, engine="mujoco", **(scene | nearer))
    assert cp.e_n == pytest.approx((scene | nearer)["e_N"], rel=1e-6)


def test_a_pybullet_batch_at_the_step_solves_each_row_with_its_own_mass():
    # Planted bug (issue 44): the batch built with row 0's mass for every row passed all front-door
    # cases; each row here has its own mass, and is the one-scene answer for its scene.
    m = np.array([0.2, 0.5, 1.3])
    scene = dict(stiffness=1e4, approach_speed=0.5, accel=9.81, e_N=0.5, engine="pybullet", radius=0.05)
    cp = ca.contact_parameters(mass=m, **scene, timestep=5e-4)
    assert cp.ok.all()
    for i in range(3):
        one = ca.contact_parameters(mass=float(m[i]), **scene, timestep=5e-4)
        assert one.stepped.status == "ok"
        for key in ("contactStiffness", "contactDamping"):
            assert cp.block[key][i] == pytest.approx(one.block[key], rel=1e-6), (i, key)
        assert cp.stepped.mean[i] == pytest.approx(0.5, abs=1e-6)
        assert cp.stepped.steps_min[i] == one.stepped.steps_min
    # The rows differ: a mass-blind batch could not give all three.
    assert np.ptp(cp.block["contactDamping"]) > 0.1 * cp.block["contactDamping"].max()
