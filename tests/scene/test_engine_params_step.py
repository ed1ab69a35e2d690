"""``params --engine NAME`` without ``--timestep``: a stepping engine's block says what it does at its step.

Issue 44, S5: every engine block a command prints carries its statement at the engine's default
step (the phase mean and one drop's range, or the step that reaches the target).
"""

import pytest

import contactalpha as ca
from contactalpha.cli import main

SCENE = {"mass": 0.5, "stiffness": 1e4, "approach_speed": 0.5, "force": 5.0}
ARGS = ["params", "--e-n", "0.5", "--mass", "0.5", "--stiffness", "1e4", "--speed", "0.5", "--force", "5"]


def test_mujoco_block_says_what_it_delivers_at_2_ms(capsys):
    assert main([*ARGS, "--engine", "mujoco"]) == 0
    out = capsys.readouterr().out
    ans = ca.contact_parameters(e_N=0.5, **SCENE, engine="mujoco", timestep="default").stepped
    assert ans.status == "ok" and ans.timestep == 0.002
    assert "# at mujoco's step 0.002 s, over a uniformly random touchdown phase" in out
    assert f"the continuous law's parameters would deliver {ans.continuous_mean:.6g}" in out
    assert f"mujoco damping   {ans.damping:.15g}" in out
    assert abs(ans.continuous_mean - 0.5) > 1e-3  # 10-11 steps in contact: the step shows


def test_an_unreachable_step_names_the_step_that_reaches_it(capsys):
    # The ping-pong block: solref (-2835480, -115.2) delivers a mean e_N of 5.25 at 2 ms.
    argv = ["params", "--e-n", "0.9", "--mass", "0.0027", "--stiffness", "7655.8", "--speed", "2.4"]
    assert main([*argv, "--accel", "9.81", "--engine", "mujoco"]) == 0
    out = capsys.readouterr().out
    ans = ca.contact_parameters(e_N=0.9, mass=0.0027, stiffness=7655.8, approach_speed=2.4, accel=9.81,
                                engine="mujoco", timestep="default").stepped  # fmt: skip
    assert ans.status == "unreachable" and ans.continuous_mean == pytest.approx(5.25, abs=0.01)
    assert f"the largest step found that reaches the target: {ans.timestep_reachable:.6g} s" in out
    assert f"would deliver {ans.continuous_mean:.6g}" in out


def test_a_step_that_cannot_be_checked_says_why(capsys):
    assert main([*ARGS, "--engine", "pybullet"]) == 0
    out = capsys.readouterr().out
    assert "# not checked at pybullet's default step: PyBullet's step needs radius=" in out
