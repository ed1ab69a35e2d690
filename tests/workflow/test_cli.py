import subprocess
import sys

import pytest

from contactalpha.cli import main


def test_alpha_command_prints_alpha_state_and_steps(capsys):
    assert main(["alpha", "0.5", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "alpha        1.538485516" in out
    assert "end state    separation" in out
    assert "steps" in out


def test_impact_command(capsys):
    assert main(["impact", "5", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "end state    nonseparation" in out


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
        (["alpha", "0.5"], "contactalpha alpha: error: the following arguments are required: xi"),
        (["alpha", "x", "0"], "contactalpha alpha: error: argument eps: 'x' is not a number"),
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
