"""``contactalpha params --engine NAME``: one engine's block, in the engine's names."""

import pytest

from contactalpha.cli import main
from contactalpha.laws import get_law
from contactalpha.parameters.engine_block import engine_block

ARGS = ["params", "--e-n", "0.5", "--mass", "0.5", "--stiffness", "1e4", "--speed", "0.5", "--force", "5"]


def test_hertz_engine_block_is_the_front_doors():
    from contactalpha import contact_parameters

    params, notes = engine_block("exudyn", 0.5, 0.5, 1.4e8, 0.5, 20.0)
    cp = contact_parameters(e_N=0.5, mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=20.0)
    assert params == cp.engines["exudyn"] and "hunt_crossley" in notes[0]


def test_linear_engine_block_is_the_laws_inverse_in_the_engines_names():
    params, notes = engine_block("pybullet", 0.5, 0.5, 1.0e4, 0.5, 19.81)
    law = get_law("kelvin_voigt")
    xi = float(law.load_factor(19.81 / ((1.0e4 / 0.5) ** 0.5 * 0.5)))
    zeta = float(law.damping_for(0.5, xi, "kinematic").damping)
    assert params["pair_damping"] == pytest.approx(2 * zeta * (1.0e4 * 0.5) ** 0.5, rel=1e-9)
    assert params["contactStiffness"] == 2.0e4 and "steps at" in notes[-1]


def test_cli_prints_one_engines_block(capsys):
    assert main([*ARGS, "--engine", "drake"]) == 0
    out = capsys.readouterr().out
    assert "drake.hunt_crossley_dissipation" in out and "opensim" not in out


def test_cli_refuses_an_unknown_engine_on_one_line(capsys):
    # --engine takes any name; the registry refuses an unknown one with its list (one home).
    assert main([*ARGS, "--engine", "no_such_engine"]) == 2
    err = capsys.readouterr().err
    assert "outside the valid choices ('opensim', 'exudyn', 'mujoco', 'drake', 'pybullet'," in err
    assert err.count("\n") == 1 and "no_such_engine" in err
