"""The command line never prints a traceback: one line on stderr, exit 2 (issue 29, N3 and N12)."""

import os
import subprocess
import sys

import pytest

from contactalpha.cli import main


def one_line_error(capsys, argv):
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("contactalpha: error: ") and captured.err.count("\n") == 1, captured.err
    return captured.err


SCENE = ["--mass", "0.5", "--stiffness", "1.4e8", "--speed", "1e-6", "--accel", "9.81"]


@pytest.mark.parametrize(
    "argv",
    [["params", "--e-n", "0.2", *SCENE], ["scene", "0.2", "--kinematic", *SCENE]],
    ids=["params", "scene"],
)
def test_a_failed_solve_is_one_line_and_exit_2(capsys, argv):
    err = one_line_error(capsys, argv)
    assert "exact alpha not found" in err and "0.2" in err


def test_export_c_into_an_existing_file_or_a_path_under_it(capsys, tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("keep")
    err = one_line_error(capsys, ["export-c", str(afile)])
    assert str(afile) in err and "not a folder" in err
    err = one_line_error(capsys, ["export-c", str(afile / "sub")])
    assert str(afile / "sub") in err
    assert afile.read_text() == "keep"


def test_export_c_into_a_read_only_folder(capsys, tmp_path, monkeypatch):
    import contactalpha.io as io

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied", str(tmp_path))

    monkeypatch.setattr(io.tempfile, "mkstemp", refuse)
    err = one_line_error(capsys, ["export-c", str(tmp_path)])
    assert "Permission denied" in err and str(tmp_path) in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into a read-only folder")
def test_export_c_into_a_chmod_read_only_folder(capsys, tmp_path):
    tmp_path.chmod(0o555)
    try:
        err = one_line_error(capsys, ["export-c", str(tmp_path)])
    finally:
        tmp_path.chmod(0o755)
    assert str(tmp_path) in err


def test_export_c_of_an_empty_path_writes_nothing(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    err = one_line_error(capsys, ["export-c", ""])
    assert "empty" in err
    assert list(tmp_path.iterdir()) == []


def test_an_integrator_option_after_the_command_is_taken_as_before_it():
    # Issue 29, N12 (the --rtol message did not say it goes before the command); issue 25 then
    # asked for options after the subcommand: both places now give the same answer.
    def run(args):
        return subprocess.run([sys.executable, "-m", "contactalpha", *args], capture_output=True, text=True)

    before = run(["--rtol", "1e-10", "alpha", "0.3", "0.2"])
    after = run(["alpha", "0.3", "0.2", "--rtol", "1e-10"])
    assert before.returncode == after.returncode == 0
    assert before.stdout == after.stdout and "alpha" in after.stdout
    # A subcommand without integrator settings says where the option goes, on one line.
    misplaced = run(["hertz", "--modulus", "2e11", "--poisson", "0.3", "--radius", "0.01", "--rtol", "1e-10"])
    assert misplaced.returncode == 2 and misplaced.stderr.count("\n") == 1
    assert "--rtol" in misplaced.stderr and "before the command" in misplaced.stderr


def test_a_reader_that_goes_away_is_not_an_error():
    # `contactalpha params ... | head -1`: the pipe closes while the command still prints.
    cmd = [sys.executable, "-m", "contactalpha", "params", "--e-n", "0.5", "--mass", "0.5"]
    cmd += ["--stiffness", "1.4e8", "--speed", "0.5", "--accel", "129.81", "--radius", "0.08"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = proc.stdout.readline()
    proc.stdout.close()  # as head does after its lines
    err = proc.stderr.read()
    assert proc.wait() == 0 and first.startswith("law")
    assert err == ""
