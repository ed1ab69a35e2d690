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


def test_a_global_option_after_the_command_says_where_it_goes():
    run = subprocess.run(
        [sys.executable, "-m", "contactalpha", "alpha", "0.3", "0.2", "--rtol", "1e-10"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 2 and run.stderr.count("\n") == 1
    assert "--rtol" in run.stderr and "before the command" in run.stderr
