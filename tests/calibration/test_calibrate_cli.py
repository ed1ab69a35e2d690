"""``contactalpha calibrate FILE``: text, JSON, figures, one-line errors; matplotlib only on request."""

import json
import subprocess
import sys

from contactalpha.calibration import hypotheses, sequence
from contactalpha.cli import main


def _file(tmp_path):
    t = sequence.simulate(
        hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": 1e8}, 0.05, 9.81, 2.0, 0.0, 10
    ).touchdowns
    path = tmp_path / "drop.csv"
    path.write_text("t (s)\n" + "\n".join(repr(float(x)) for x in t) + "\n")
    return path


def test_calibrate_command_prints_and_writes(tmp_path, capsys):
    path = _file(tmp_path)
    out_json = tmp_path / "r.json"
    code = main(
        [
            "calibrate",
            str(path),
            "--mass",
            "0.05",
            "--radius",
            "0.02",
            "--hypothesis",
            "hc_eps",
            "--hypothesis",
            "constant_e",
            "--json",
            str(out_json),
            "--figures",
            str(tmp_path / "fig"),
        ]
    )
    text = capsys.readouterr().out
    assert code == 0
    assert "selected: hc_eps" in text
    report = json.loads(out_json.read_text())
    assert report["selected"] == "hc_eps"
    assert abs(report["laws"]["hc_eps"]["values"]["eps"] - 0.8) < 1e-6
    for name in ("fig_restitution.png", "fig_residuals.png"):
        assert (tmp_path / name).stat().st_size > 1000


def test_bad_input_is_one_line_exit_2(tmp_path, capsys):
    assert main(["calibrate", str(tmp_path / "missing.csv"), "--mass", "0.05"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("contactalpha: error:") and err.count("\n") == 1
    path = _file(tmp_path)
    assert main(["calibrate", str(path), "--mass", "0.05", "--law", "nope"]) == 2
    assert "law = 'nope'" in capsys.readouterr().err


def test_calibration_does_not_import_matplotlib(tmp_path):
    path = _file(tmp_path)
    code = (
        "import sys, contactalpha as ca\n"
        f"ca.calibrate({str(path)!r}, mass=0.05, hypotheses=['constant_e'], intervals=False)\n"
        "print('matplotlib' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
