"""The front door: contact_parameters in SI units and `contactalpha params`."""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.cli import main
from contactalpha.parameters.front_door import contact_parameters

BALL = dict(mass=0.5, stiffness=1.4e8, approach_speed=0.5)  # the paper's ball (Sect. 6)


def test_energetic_scene_gives_the_exact_alpha_and_each_engines_parameter():
    cp = contact_parameters(0.8, **BALL, accel=9.81, radius=0.08)
    xi = ca.influence_factor(0.5, 1.4e8, 0.5, 9.81)
    assert cp.xi == xi
    assert cp.damping == ca.alpha(0.8, xi)
    assert cp.source == "table"
    assert cp.damping_name == "alpha"
    assert cp.physical_damping == pytest.approx(cp.damping / 0.5, rel=1e-15) and cp.physical_unit == "s/m"
    assert cp.end_state == "separation"
    assert cp.eps == pytest.approx(0.8, abs=1e-6)
    assert 0 < cp.e_n < cp.eps
    assert cp.engines["opensim"]["dissipation"] == pytest.approx(2 * cp.damping / (3 * 0.5), rel=1e-15)
    assert cp.engines["opensim"]["stiffness"] == pytest.approx(3 * 1.4e8 / np.sqrt(2 * 0.08), rel=1e-15)
    assert cp.engines["exudyn"]["contactStiffness"] == 1.4e8
    from contactalpha.adapters.engine_conventions import exudyn_alpha

    e_res = cp.engines["exudyn"]["restitutionCoefficient"]
    assert exudyn_alpha(e_res, 2) == pytest.approx(cp.damping, rel=1e-12)


def test_kinematic_scene_hits_its_e_n_and_force_is_mass_times_accel():
    cp = contact_parameters(e_N=0.6, **BALL, force=60.0)
    assert cp.accel == 120.0
    assert cp.e_n == pytest.approx(0.6, abs=1e-6)
    assert cp.eps > cp.e_n
    assert cp.damping == ca.alpha(0.6, cp.xi, restitution="kinematic")
    same = contact_parameters(e_N=0.6, **BALL, accel=120.0)
    assert same.damping == cp.damping


def test_outside_the_table_the_solver_answers():
    cp = contact_parameters(0.005, **BALL, force=495.0)
    assert cp.source == "solver"
    assert cp.damping == ca.solve_alpha(0.005, cp.xi).alpha
    assert cp.end_state in ("nonseparation", "creep")


def test_heavy_load_without_separation_reports_zero_e_n():
    cp = contact_parameters(0.3, **BALL, force=495.0)
    assert cp.end_state in ("nonseparation", "creep") and cp.e_n == 0.0


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(eps=0.5, e_N=0.5, accel=1.0), "exactly one of eps"),
        (dict(accel=1.0), "exactly one of eps"),
        (dict(eps=0.5), "exactly one of accel"),
        (dict(eps=0.5, accel=1.0, force=1.0), "exactly one of accel"),
        (dict(eps=1.5, accel=1.0), r"eps = 1.5 is outside"),
        (dict(e_N=0.0, accel=1.0), "no kinematic inverse"),
        (dict(eps=0.5, accel=-1.0), r"accel = -1.0 is outside"),
        (dict(eps=0.5, force=float("nan")), r"force = nan is outside"),
        (dict(eps=0.0, accel=0.0), "needs a load"),
        (dict(eps=0.5, accel=1.0, mass=-1.0), r"mass = -1.0 is outside"),
        (dict(eps=0.5, accel=1.0, approach_speed=0.0), r"approach_speed = 0.0 is outside"),
        (dict(eps=0.5, accel=1.0, radius=0.0), r"radius = 0.0 is outside"),
    ],
)
def test_bad_input_is_a_value_error_naming_the_value(kwargs, match):
    args = dict(BALL)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        contact_parameters(**args)


def test_scalar_influence_factor_is_the_array_paths_number():
    rng = np.random.default_rng(3)
    m, k, v, a = (10 ** rng.uniform(lo, hi, 200) for lo, hi in ((-3, 3), (5, 11), (-3, 1), (-3, 4)))
    arr = ca.influence_factor(m, k, v, a)
    assert all(ca.influence_factor(*map(float, args)) == x for *args, x in zip(m, k, v, a, arr, strict=True))


def test_cli_params(capsys):
    scene = ["--mass", "0.5", "--stiffness", "1.4e8", "--speed", "0.5", "--force", "5.1"]
    argv = ["params", "--e-n", "0.8", *scene]
    assert main(argv) == 0
    out = capsys.readouterr().out
    cp = contact_parameters(e_N=0.8, **BALL, force=5.1)
    assert f"alpha           {cp.damping:.15g}" in out
    assert f"{cp.engines['opensim']['dissipation']:.15g}" in out
    assert main(["params", "--eps", "2", *scene]) == 2
    assert "eps = 2.0 is outside" in capsys.readouterr().err


def test_cli_params_with_a_law(capsys):
    scene = ["--mass", "2", "--stiffness", "2.51e6", "--speed", "0.5", "--accel", "9.81"]
    assert main(["params", "--e-n", "0.6", "--law", "hunt_crossley_linear", *scene]) == 0
    out = capsys.readouterr().out
    cp = contact_parameters(
        e_N=0.6, mass=2, stiffness=2.51e6, approach_speed=0.5, accel=9.81, law="hunt_crossley_linear"
    )
    assert f"alpha           {cp.damping:.15g}" in out and "law             hunt_crossley_linear" in out
    assert cp.e_n == pytest.approx(0.6, abs=1e-9)
    assert main(["params", "--e-n", "0.6", "--law", "hooke", *scene]) == 2
    assert "unknown contact law 'hooke'; valid: hunt_crossley," in capsys.readouterr().err
    assert main(["params", "--e-n", "0.6", "--law", "kelvin_voigt", "--engine", "mujoco", *scene]) == 2
    assert "give --engine or --law, not both" in capsys.readouterr().err
