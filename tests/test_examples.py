"""The scripts in examples/ run and print numbers an independent computation confirms."""

import math
import os
import re
import runpy
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import contactalpha as ca
from contactalpha.adapters.engine_conventions import opensim_dissipation

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def _printed(out, label):
    """The first number after ``label`` at the start of a line of ``out``."""
    match = re.search(rf"^{re.escape(label)}\s+([-+0-9.eE]+)", out, re.M)
    assert match, f"{label!r} not printed:\n{out}"
    return float(match.group(1))


def test_drop_test_opensim_gives_parameters_that_deliver_the_measured_e_n(opensim, capsys):
    runpy.run_path(str(EXAMPLES / "drop_test_opensim.py"), run_name="__main__")
    out = capsys.readouterr().out
    v, e_n, k = (_printed(out, s) for s in ("approach speed", "measured e_N", "Hertz stiffness"))
    assert v == pytest.approx(math.sqrt(2 * 9.81 * 0.5), rel=1e-5)
    assert e_n == pytest.approx(math.sqrt(0.3 / 0.5), rel=1e-5)
    assert k == pytest.approx(4 / 3 * 5e6 / 0.75 * math.sqrt(0.03), rel=1e-4)
    alpha, xi = _printed(out, "alpha"), _printed(out, "xi")
    # The table's alpha, integrated over one impact by the engine, gives back the measured e_N.
    assert ca.impact(alpha, xi).e_n == pytest.approx(e_n, abs=1e-5)
    # Simbody's conventions (docs/engines/index.md): E_i = 3 k / sqrt(2 R), c = 2 alpha / (3 v).
    assert _printed(out, "OpenSim stiffness") == pytest.approx(3 * k / math.sqrt(2 * 0.03), rel=1e-5)
    assert _printed(out, "OpenSim dissipation") == pytest.approx(2 * alpha / (3 * v), rel=1e-5)
    assert _printed(out, "OpenSim dissipation") == pytest.approx(opensim_dissipation(alpha, v), rel=1e-5)
    # The drop run inside OpenSim delivers the measured restitution.
    assert _printed(out, "OpenSim delivers e_N") == pytest.approx(e_n, abs=1e-4)


@pytest.mark.integration
def test_c_export_cmake_example_matches_the_python_front_door(tmp_path):
    for tool in ("cmake", "c++"):
        if shutil.which(tool) is None:
            if os.environ.get("CI") == "true":
                pytest.fail(f"CI=true: {tool} is not installed")
            pytest.skip(f"{tool} is not installed")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    build = tmp_path / "build"
    subprocess.run(
        [
            "cmake",
            "-S",
            str(EXAMPLES / "c_export"),
            "-B",
            str(build),
            f"-DPython3_EXECUTABLE={sys.executable}",
        ],
        check=True,
        env=env,
        capture_output=True,
    )
    subprocess.run(["cmake", "--build", str(build)], check=True, env=env, capture_output=True)
    run = subprocess.run([str(build / "drop_test")], capture_output=True, text=True, check=True)
    rows = [list(map(float, line.split())) for line in run.stdout.splitlines()[1:]]
    assert [r[0] for r in rows] == [0.5, 0.25, 0.1]
    for v, xi, alpha, damping in rows:
        cp = ca.contact_parameters(
            e_N=0.5, mass=0.5, stiffness=1.4e8, approach_speed=v, accel=9.81 + 5.1 / 0.5
        )
        mu = cp.physical_damping * 1.4e8  # the C example prints mu = alpha k / v = k d
        assert (xi, alpha, damping) == pytest.approx((cp.xi, cp.damping, mu), rel=1e-12)
        # Independent of the tables: one impact of the engine with that alpha gives e_N = 0.5.
        assert ca.impact(alpha, xi).e_n == pytest.approx(0.5, abs=1e-6)


def test_mujoco_drop_example_delivers_the_target_inside_mujoco(mujoco, capsys):
    runpy.run_path(str(EXAMPLES / "mujoco_drop.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert _printed(out, "approach speed") == pytest.approx(0.5, rel=1e-4)
    # MuJoCo's own drop at a 1e-5 s step, with the law's solref: the target within 1e-3.
    delivered = float(re.search(r"MuJoCo delivers\s+e_N = ([0-9.]+)", out).group(1))
    assert delivered == pytest.approx(0.5, abs=1e-3)
    # The solref is per unit mass: stiffness k/m and damping 2 zeta sqrt(k/m).
    stiffness, damping = (float(x) for x in out.split("solref")[1].split()[:2])
    zeta = _printed(out, "damping ratio")
    assert -stiffness == pytest.approx(2.0e4 / 0.5, rel=1e-12)
    assert -damping == pytest.approx(2 * zeta * math.sqrt(2.0e4 / 0.5), rel=1e-8)


@pytest.mark.integration
def test_domain_randomisation_gives_4096_scenes_and_three_deliver_their_target_in_mujoco(mujoco, capsys):
    runpy.run_path(str(EXAMPLES / "domain_randomisation.py"), run_name="__main__")
    out = capsys.readouterr().out
    assert re.search(r"^scenes\s+4096, with parameters 4096$", out, re.M)
    checks = re.findall(r"target e_N = ([0-9.]+), MuJoCo delivers e_N = ([0-9.]+)", out)
    assert len(checks) == 3
    for target, delivered in checks:
        # MuJoCo's own drop at 20,000 steps per period, with the batch's solref: within 1e-3.
        assert float(delivered) == pytest.approx(float(target), abs=1e-3)


def test_robot_model_tuning_hits_the_target_and_reads_the_leg(mujoco, capsys):
    runpy.run_path(str(EXAMPLES / "robot_model_tuning.py"), run_name="__main__")
    out = capsys.readouterr().out
    sys.path.insert(0, str(ROOT / "tests" / "mechanism"))
    import hand  # the leg's effective mass and load derived by hand

    m_eff, accel = hand.leg()
    assert _printed(out, "effective mass") == pytest.approx(m_eff, rel=1e-11)
    assert _printed(out, "free accel") == pytest.approx(accel, rel=1e-11)
    assert _printed(out, "refined e_N") == pytest.approx(0.5, abs=2e-4)
    # the corrected law's answer misses by less than the free-body mapping's
    assert abs(_printed(out, "delivered e_N") - 0.5) < abs(_printed(out, "free-body e_N") - 0.5)


def test_engine_steps_deliver_the_target_in_drake_and_pybullet(pydrake, pybullet, mujoco, capfd):
    """The arm's m_eff and load by hand; each engine's 16 drops average the target (the law's
    answer does not)."""
    runpy.run_path(str(EXAMPLES / "engine_steps.py"), run_name="__main__")
    out = capfd.readouterr().out
    i_hinge = 0.04 + 1.5 / 9.0  # Iyy + m d^2, d = 1/3 m
    assert _printed(out, "  effective mass") == pytest.approx(i_hinge / 0.25, rel=1e-11)
    assert _printed(out, "  free accel") == pytest.approx(0.5 * 1.5 * 9.81 / 3.0 / i_hinge, rel=1e-11)
    means = [float(x) for x in re.findall(r"engine, mean of 16 drops\s+([0-9.]+)", out)]
    laws = [float(x) for x in re.findall(r"law's answer, phase mean\s+([0-9.]+)", out)]
    assert len(means) == 2 and all(m == pytest.approx(0.6, abs=1e-3) for m in means)
    assert all(abs(law - 0.6) > 0.1 for law in laws)


@pytest.mark.integration
def test_mjx_sysid_recovers_the_recorded_damping(mujoco, capsys):
    """The gradient-descent fit through the JAX front door and MJX finds MuJoCo's own damping."""
    for module in ("jax", "mujoco.mjx"):
        try:
            __import__(module)
        except ImportError as err:
            if os.environ.get("CI") == "true":
                pytest.fail(f"CI=true: {module} is not installed ({err})")
            pytest.skip(f'{module} is not installed; pip install -e ".[batched-engines]"')
    runpy.run_path(str(EXAMPLES / "mjx_sysid.py"), run_name="__main__")
    out = capsys.readouterr().out
    b_true = _printed(out, "damping b true")
    assert b_true == pytest.approx(2 * 0.15 * math.sqrt(2e4 / 0.5))
    assert _printed(out, "damping b by MJX fit") == pytest.approx(b_true, rel=1e-5)
    # calibrate fits the continuous law (and the stiffness) to the discrete engine's recording.
    assert _printed(out, "damping b by calibrate") == pytest.approx(b_true, rel=0.02)
