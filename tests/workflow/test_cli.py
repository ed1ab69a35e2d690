import subprocess
import sys

import pytest

from contactalpha.baselines.reference import impact_scipy
from contactalpha.cli import main


def printed(out):
    """The command's ``name   value`` lines as a dict of strings."""
    return dict(line.rsplit(maxsplit=1) for line in out.strip().splitlines())


def test_alpha_command_prints_the_root_and_its_restitution(capsys):
    assert main(["alpha", "0.5", "0.2"]) == 0
    out = printed(capsys.readouterr().out)
    assert out["end state"] == "separation" and out["status"] == "ok"
    alpha = float(out["alpha"])
    assert alpha == pytest.approx(1.538485516, abs=1e-9)
    assert abs(float(out["eps reached"]) - 0.5) <= 1e-12
    # the SciPy oracle (not the engine) restitutes 0.5 at the printed alpha
    assert impact_scipy(alpha, 0.2, rtol=1e-12, atol=1e-14).eps == pytest.approx(0.5, abs=1e-10)
    assert 1 <= int(out["impacts"]) <= 4 and int(out["steps"]) > 10


def test_impact_command_prints_what_the_scipy_oracle_computes(capsys):
    assert main(["impact", "5", "0.2"]) == 0
    out = printed(capsys.readouterr().out)
    ref = impact_scipy(5.0, 0.2, rtol=1e-12, atol=1e-14)
    assert out["end state"] == ref.state == "nonseparation" and out["status"] == "ok"
    assert float(out["eps"]) == pytest.approx(ref.eps, abs=1e-10)
    assert float(out["x_max"]) == pytest.approx(ref.x_max, rel=1e-10)
    assert float(out["x_end"]) == pytest.approx(ref.x_end, rel=1e-8)


def test_bad_input_is_one_line_and_exit_2(capsys):
    assert main(["alpha", "1.5", "0.2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "eps = 1.5" in err[0] and "[0.0, 1.0]" in err[0]
    assert main(["impact", "-1", "0.2"]) == 2


def test_runs_as_module():
    p = subprocess.run(
        [sys.executable, "-m", "contactalpha", "alpha", "0.3", "0"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert p.returncode == 0 and "alpha        3.087081" in p.stdout
    p = subprocess.run(
        [sys.executable, "-m", "contactalpha", "alpha", "x", "0"], capture_output=True, text=True, check=False
    )
    assert p.returncode == 2 and "'x' is not a number" in p.stderr


@pytest.mark.parametrize(
    "argv, message",
    [
        (["alpha", "0.5", "-1e-3"], "contactalpha: error: xi = -0.001 is outside the valid range [0.0, 1.0)"),
        (["alpha", "0.5", "-1E+2"], "contactalpha: error: xi = -100.0 is outside the valid range"),
        (["impact", "-inf", "0.2"], "contactalpha: error: alpha = -inf is outside the valid range [0.0, inf"),
        (["alpha", "-nan", "0.2"], "contactalpha: error: eps = nan is outside the valid range [0.0, 1.0]"),
        (["--rtol", "-1e-3", "alpha", "0.5", "0.2"], "contactalpha: error: rtol = -0.001 is outside"),
    ],
)
def test_negative_numbers_in_any_float_form_are_values_not_options(capsys, argv, message):
    assert main(argv) == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith(message)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["alpha", "0.5"], "contactalpha alpha: error: give the influence factor once: --xi XI"),
        (["alpha", "x", "0"], "contactalpha alpha: error: argument EPS: 'x' is not a number"),
        (
            ["params", "--mass", "1"],
            "contactalpha params: error: the following arguments are required: --stiffness",
        ),
        (["alpha", "0.5", "0.2", "--bogus"], "contactalpha: error: unrecognized arguments: --bogus"),
        (["solve"], "contactalpha: error: argument command: invalid choice: 'solve'"),
    ],
)
def test_argument_errors_print_one_line_and_exit_2(capsys, argv, message):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith(message) and line.endswith("-h)")
