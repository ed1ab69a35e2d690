"""contact_parameters(..., engine=, timestep=): parameters for the phase mean at the engine's step."""

import math
import subprocess
import sys

import numpy as np
import pytest

from contactalpha import contact_parameters
from contactalpha.stepping.delivered import at_phases
from contactalpha.stepping.registry import stepper

SCENE = dict(mass=0.5, stiffness=2e4, approach_speed=0.5, accel=9.81)


def _dense(block, h, v, a, key="e_n", n=16384):
    """Mean over n midpoint phases of the block's solref in the map: independent of the quadrature."""
    p = stepper("mujoco").pack(stiffness=-block["solref"][0], damping=-block["solref"][1],
                               impedance=block["solimp"][0])  # fmt: skip
    return at_phases("mujoco", p, h, (np.arange(n) + 0.5) / n, v, a)[key]


@pytest.mark.parametrize(("target", "key"), [({"e_N": 0.5}, "e_n"), ({"eps": 0.7}, "eps")])
def test_the_block_delivers_the_target_as_a_phase_mean(target, key):
    cp = contact_parameters(**SCENE, **target, engine="mujoco", timestep=0.002)
    ans = cp.stepped
    goal = next(iter(target.values()))
    assert ans.status == "ok" and ans.mean == pytest.approx(goal, abs=1e-6)
    e = _dense(cp.block, 0.002, 0.5, 9.81, key)
    assert e.mean() == pytest.approx(goal, abs=5e-5)
    assert ans.minimum <= e.min() and e.max() <= ans.maximum
    assert ans.minimum < goal - 0.02 and ans.maximum > goal + 0.02  # one drop strays at 2 ms
    # The continuous law's parameters miss at this step; the stepped ones do not.
    assert abs(ans.continuous_mean - goal) > 4e-3


def test_default_step_is_the_engines():
    a = contact_parameters(**SCENE, e_N=0.5, engine="mujoco", timestep="default")
    b = contact_parameters(**SCENE, e_N=0.5, engine="mujoco", timestep=0.002)
    assert a.stepped.timestep == 0.002 and a.block == b.block


def test_without_a_step_the_answer_is_the_continuous_one():
    a = contact_parameters(**SCENE, e_N=0.5, engine="mujoco")
    b = contact_parameters(**SCENE, e_N=0.5, engine="mujoco", timestep=None)
    assert a == b and a.stepped is None
    c = contact_parameters(**SCENE, e_N=0.5, engine="mujoco", timestep=0.002)
    assert c.damping == a.damping and c.block["solref"] != a.block["solref"]


def test_an_unreachable_target_says_so_with_a_step_that_reaches():
    cp = contact_parameters(mass=0.5, stiffness=1e6, approach_speed=0.5, accel=9.81, e_N=0.9,
                            engine="mujoco", timestep=0.002)  # fmt: skip
    ans = cp.stepped
    assert ans.status == "unreachable" and math.isnan(ans.mean)
    assert 0.0 < ans.timestep_reachable < 0.002
    again = contact_parameters(mass=0.5, stiffness=1e6, approach_speed=0.5, accel=9.81, e_N=0.9,
                               engine="mujoco", timestep=ans.timestep_reachable)  # fmt: skip
    assert again.stepped.status == "ok"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"timestep": 0.002}, "engine"), ({"engine": "opensim", "timestep": 0.002}, "step map"),
     ({"engine": "mujoco", "timestep": -1.0}, "timestep"),
     ({"engine": "mujoco", "timestep": "fine"}, "timestep"), ({"engine": "mujoco", "verify": 8}, "timestep")],
)  # fmt: skip
def test_bad_step_input_names_the_argument(kwargs, match):
    with pytest.raises(ValueError, match=match):
        contact_parameters(**SCENE, e_N=0.5, **kwargs)


def test_the_command_line_prints_the_predicted_range():
    scene = ["--e-n", "0.5", "--mass", "0.5", "--stiffness", "2e4", "--speed", "0.5", "--accel", "9.81"]
    cmd = [sys.executable, "-m", "contactalpha", "params", *scene, "--engine", "mujoco", "--timestep"]
    out = subprocess.run(cmd, capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    assert "mean e_N      0.5" in out.stdout and "one drop" in out.stdout and "0.002 s" in out.stdout
    bad = subprocess.run(cmd[:-1] + ["--timestep", "0"], capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and "timestep" in bad.stderr and "Traceback" not in bad.stderr


@pytest.mark.integration
def test_verify_runs_mujoco_and_it_agrees():
    pytest.importorskip("mujoco")
    cp = contact_parameters(**SCENE, e_N=0.5, engine="mujoco", timestep=0.002, verify=128)
    v, ans = cp.stepped.verify, cp.stepped
    assert v["phases"] == 128
    assert abs(v["mean"] - 0.5) < 1e-3
    assert abs(v["minimum"] - ans.minimum) < 2e-3 and abs(v["maximum"] - ans.maximum) < 2e-3


@pytest.mark.parametrize(("engine", "radius", "h"), [("pybullet", 0.05, 5e-4), ("drake", None, "default")])
def test_pybullet_and_drake_blocks_deliver_the_target_as_a_phase_mean(engine, radius, h):
    from contactalpha.stepping import drake_map, pybullet_map

    cp = contact_parameters(**SCENE, e_N=0.5, engine=engine, timestep=h, radius=radius)
    ans, b = cp.stepped, cp.block
    assert ans.status == "ok" and ans.mean == pytest.approx(0.5, abs=1e-6)
    if engine == "pybullet":  # the block's per-body values, by hand into the map's slots
        p = pybullet_map.make_params(0.5, b["contactStiffness"], b["contactDamping"], b["contactStiffness"],
                                     b["contactDamping"], radius)  # fmt: skip
    else:
        k, d = b["point_contact_stiffness"], b["hunt_crossley_dissipation"]
        p = drake_map.make_params(0.5, k, d, k, d)
    e = at_phases(engine, p, ans.timestep, (np.arange(16384) + 0.5) / 16384, 0.5, 9.81)["e_n"]
    assert e.mean() == pytest.approx(0.5, abs=5e-5)
    assert abs(ans.continuous_mean - 0.5) > 0.05  # the continuous law's values miss at these steps


def test_pybullet_at_its_default_step_is_out_of_reach_and_says_where_it_is_not():
    cp = contact_parameters(**SCENE, e_N=0.5, engine="pybullet", timestep="default", radius=0.05)
    ans = cp.stepped
    assert ans.timestep == 1 / 240 and ans.status == "unreachable"
    assert 0.0 < ans.timestep_reachable < 1 / 240
    h = ans.timestep_reachable
    again = contact_parameters(**SCENE, e_N=0.5, engine="pybullet", timestep=h, radius=0.05)
    assert again.stepped.status == "ok"
    with pytest.raises(ValueError, match="radius"):
        contact_parameters(**SCENE, e_N=0.5, engine="pybullet", timestep="default")


@pytest.mark.integration
@pytest.mark.parametrize(("engine", "radius", "h"), [("pybullet", 0.05, 5e-4), ("drake", None, "default")])
def test_verify_runs_pybullet_and_drake_and_they_agree(engine, radius, h):
    pytest.importorskip("pybullet" if engine == "pybullet" else "pydrake")
    cp = contact_parameters(**SCENE, e_N=0.5, engine=engine, timestep=h, radius=radius, verify=64)
    v, ans = cp.stepped.verify, cp.stepped
    assert abs(v["mean"] - 0.5) < 1e-3
    assert abs(v["minimum"] - ans.minimum) < 2e-3 and abs(v["maximum"] - ans.maximum) < 2e-3


def test_params_timestep_out_of_reach_exits_3_and_names_a_step_that_reaches(capsys):
    from contactalpha.cli import main

    scene = ["--e-n", "0.9", "--mass", "0.5", "--stiffness", "2e4", "--speed", "1", "--accel", "9.81",
             "--radius", "0.05"]  # fmt: skip
    assert main(["params", "--engine", "pybullet", *scene, "--timestep"]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "the largest step found that reaches the target is" in err
    step = float(err.rsplit(" is ", 1)[1].split()[0])
    cp = contact_parameters(e_N=0.9, mass=0.5, stiffness=2e4, approach_speed=1.0, accel=9.81, radius=0.05,
                               engine="pybullet", timestep=step)  # fmt: skip
    assert cp.stepped.status == "ok" and abs(cp.stepped.mean - 0.9) < 1e-6
