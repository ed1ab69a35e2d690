"""The command line's last tracebacks and misleading messages (issue 34, R5, R7, R8)."""

import sys

import pytest

from contactalpha.cli import main
from contactalpha.scene.hertz import hertz_stiffness


def one_line_error(capsys, argv):
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("contactalpha: error: ") and captured.err.count("\n") == 1, captured.err
    assert "Traceback" not in captured.err
    return captured.err


SCENE = ["--e-n", "0.5", "--stiffness", "1e4", "--speed", "0.5"]


@pytest.mark.parametrize("engine", ["mujoco", "pybullet", "drake", "opensim", "exudyn"])
def test_a_zero_mass_with_a_force_is_named_not_divided_by(capsys, engine):
    err = one_line_error(capsys, ["params", "--mass", "0", "--force", "1", "--engine", engine, *SCENE])
    assert "mass = 0.0 is outside the valid range" in err


def test_a_nan_force_is_named_as_the_force(capsys):
    err = one_line_error(capsys, ["params", "--mass", "1", "--force", "nan", "--engine", "mujoco", *SCENE])
    assert "force = nan" in err and "gravity" not in err


def test_refine_without_the_engine_installed_says_how_to_install_it(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco now raises ImportError
    argv = ["params", "--mass", "1", "--accel", "9.81", "--engine", "mujoco", "--refine", *SCENE]
    err = one_line_error(capsys, argv)
    assert "pip install" in err and "mujoco" in err


def test_two_rigid_bodies_have_no_hertz_stiffness(capsys):
    argv = ["hertz", "--modulus", "inf", "--modulus-2", "inf", "--poisson", "0.3", "--radius", "0.01"]
    assert "two rigid bodies" in one_line_error(capsys, argv)
    with pytest.raises(ValueError, match="modulus = inf and modulus_2 = inf"):
        hertz_stiffness(float("inf"), 0.3, 0.01, modulus_2=float("inf"))


@pytest.mark.parametrize(
    ("modulus", "radius"), [("1e-320", "1e-300"), ("1e308", "1e300")], ids=["underflow", "overflow"]
)
def test_a_hertz_stiffness_beyond_the_doubles_is_refused_not_printed_as_0_or_inf(capsys, modulus, radius):
    err = one_line_error(capsys, ["hertz", "--modulus", modulus, "--poisson", "0.3", "--radius", radius])
    assert "outside double precision" in err and f"radius = {float(radius)!r}" in err


def test_a_hertz_stiffness_whose_modulus_alone_would_overflow_the_compliance():
    # 1/E* = 2 (1 - nu^2) / E overflows for E = 1e-320; k = (4/3) E/(2 (1 - nu^2)) sqrt(R) does not.
    e = 1e-320  # subnormal: its value is not 1e-320 exactly
    expected = 4.0 / 3.0 * (e / 1e-300) / (2.0 * (1.0 - 0.09)) * 1e150 * 1e-300
    assert hertz_stiffness(e, 0.3, 1e300) == pytest.approx(expected, rel=1e-12, abs=0.0)
    # Inside the doubles the plain product, as before, bit for bit.
    compliance = 0.0 + (1.0 - 0.3 * 0.3) / 210e9 + (1.0 - 0.3 * 0.3) / 210e9
    assert hertz_stiffness(210e9, 0.3, 0.01) == 4.0 / 3.0 * (1.0 / compliance) * 0.01**0.5


def test_a_failed_solve_names_the_restitution_the_user_gave(capsys):
    scene = ["--mass", "0.5", "--stiffness", "1.4e8", "--speed", "1e-6", "--accel", "9.81"]
    assert "e_N = 0.2" in one_line_error(capsys, ["params", "--e-n", "0.2", *scene])
    assert "e_N = 0.2" in one_line_error(capsys, ["scene", "0.2", "--kinematic", *scene])
