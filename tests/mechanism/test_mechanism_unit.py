"""Parts of the mechanism package that need no engine: crossing, row algebra, files, errors."""

import math

import numpy as np
import pytest

from contactalpha.cli import main
from contactalpha.mechanism.contact import approach, pressing_accel
from contactalpha.mechanism.crossing import rebound_speed
from contactalpha.mechanism.mujoco_row import effective_impedance
from contactalpha.mechanism.write import check_output, write_drake, write_mjcf


def test_rebound_speed_of_a_sampled_parabola():
    """Free flight g(t) = -0.01 + 0.5 t - 4.905 t^2 sampled at 1e-3 s: the crossing's slope exactly."""
    t = np.arange(0.0, 0.2, 1e-3)
    g = -0.01 + 0.5 * t - 0.5 * 9.81 * t**2
    g[:5] = -np.linspace(0.0, 0.01, 5)  # penetrating before
    root = (0.5 - math.sqrt(0.25 - 4 * 4.905 * 0.01)) / (2 * 4.905)
    speed, when = rebound_speed(t, g)
    assert when == pytest.approx(root, rel=1e-12)
    assert speed == pytest.approx(0.5 - 9.81 * root, rel=1e-12)


def test_rebound_speed_without_rebound_is_nan():
    assert all(math.isnan(x) for x in rebound_speed([0, 1, 2], [0.0, -1.0, -2.0]))
    assert all(math.isnan(x) for x in rebound_speed([0, 1, 2], [1.0, 2.0, 3.0]))


def test_approach_of_a_two_dof_row():
    """m_eff = 1/(J M^-1 J^T) against the 2x2 inverse written out; speed from qvel and back."""
    M = np.array([[2.0, 0.3], [0.3, 0.5]])
    J = np.array([0.4, -1.2])
    det = 2.0 * 0.5 - 0.3 * 0.3
    inv = (0.5 * 0.4**2 - 2 * 0.3 * 0.4 * -1.2 + 2.0 * 1.2**2) / det
    m_eff, v, qvel = approach(J, M, None, 0.7)
    assert m_eff == pytest.approx(1.0 / inv, rel=1e-14)
    assert -(J @ qvel) == pytest.approx(0.7, rel=1e-14)
    assert approach(J, M, qvel, None)[1] == pytest.approx(0.7, rel=1e-14)
    assert pressing_accel(J, M, [0.0, -1.0]) == pytest.approx(-(J @ np.linalg.solve(M, [0.0, -1.0])))


def test_approach_refuses_bad_input():
    M, J = np.eye(2), np.array([1.0, 0.0])
    with pytest.raises(ValueError, match="exactly one"):
        approach(J, M, None, None)
    with pytest.raises(ValueError, match="speed = -1"):
        approach(J, M, None, -1.0)
    with pytest.raises(ValueError, match="closing speed"):
        approach(J, M, [1.0, 0.0], None)
    with pytest.raises(ValueError, match="moves no joint"):
        approach(np.zeros(2), M, None, 1.0)


def test_effective_impedance():
    """d_e = A/(A + (1-d)/d diagA): d itself where diagA = A; the issue's pendulum (0.664 vs 1.99)."""
    assert effective_impedance(0.9, 1.7, 1.7) == pytest.approx(0.9, rel=1e-15)
    assert effective_impedance(0.9, 1.99, 0.664) == pytest.approx(1.99 / (1.99 + 0.664 / 9), rel=1e-15)
    assert effective_impedance(0.9, 1.99, 0.664) == pytest.approx(0.964, abs=5e-4)
    with pytest.raises(ValueError, match="impedance = 1.0"):
        effective_impedance(1.0, 1.0, 1.0)


MJCF = """<mujoco><worldbody><geom name="a" type="plane" size="1 1 1"/>
<body><freejoint/><geom name="b" type="sphere" size="0.1"/></body></worldbody>
<contact><pair geom1="b" geom2="a" solref="0.01 1"/></contact></mujoco>"""


def test_write_mjcf_replaces_the_pair_and_keeps_the_original(tmp_path):
    src = tmp_path / "m.xml"
    src.write_text(MJCF)
    out = write_mjcf(src, tmp_path / "t.xml", ("a", "b"), {"solref": (-1e4, -20.0), "condim": "1"})
    assert src.read_text() == MJCF
    text = out.read_text()
    assert text.count("<pair") == 1 and 'solref="-10000.0 -20.0"' in text and 'condim="1"' in text
    with pytest.raises(ValueError, match="is the model file itself"):
        check_output(src, src)


def test_write_mjcf_elsewhere_makes_assets_absolute(tmp_path):
    (tmp_path / "src").mkdir()
    src = tmp_path / "src" / "m.xml"
    src.write_text(MJCF.replace("<worldbody>", '<compiler meshdir="meshes"/><worldbody>'))
    out = write_mjcf(src, tmp_path / "t.xml", ("a", "b"), {})
    assert f'meshdir="{tmp_path / "src" / "meshes"}"' in out.read_text()


SDF = """<?xml version="1.0"?><sdf version="1.9" xmlns:drake="http://drake.mit.edu"><model name="m">
<link name="l"><collision name="a"><geometry><sphere><radius>1</radius></sphere></geometry>
<drake:proximity_properties><drake:mu_dynamic>0.3</drake:mu_dynamic></drake:proximity_properties>
</collision><collision name="b"><geometry><sphere><radius>1</radius></sphere></geometry></collision></link>
</model></sdf>"""


def test_write_drake_sets_both_geometries_and_keeps_friction(tmp_path):
    src = tmp_path / "m.sdf"
    src.write_text(SDF)
    out = write_drake(src, tmp_path / "t.sdf", ("a", "b"), {"point_contact_stiffness": 2e5})
    text = out.read_text()
    assert text.count("<drake:point_contact_stiffness>200000.0<") == 2
    assert "<drake:mu_dynamic>0.3<" in text
    assert src.read_text() == SDF
    with pytest.raises(ValueError, match="'c': 0 <collision>"):
        write_drake(src, tmp_path / "u.sdf", ("a", "c"), {})


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--pair", "a", "b", "--e-n", "0.5", "--speed", "1"], "is not a file"),
        (["--pair", "a", "b", "--e-n", "1.5", "--speed", "1"], "e_n = 1.5"),
    ],
)
def test_cli_errors_are_one_line(tmp_path, capsys, argv, message):
    code = main(["tune", str(tmp_path / ("missing.xml" if "is not" in message else "m.xml")), *argv])
    err = capsys.readouterr().err
    assert code == 2
    assert message in err and len(err.strip().splitlines()) == 1


def test_written_files_keep_comments_and_carry_a_stamp(tmp_path):
    src = tmp_path / "m.xml"
    src.write_text(MJCF.replace("<worldbody>", "<!-- the user's note --><worldbody>"))
    text = write_mjcf(src, tmp_path / "t.xml", ("a", "b"), {}, stamp="tune of m.xml").read_text()
    assert "<!-- the user's note -->" in text and "tune of m.xml (contactalpha" in text


def test_malformed_model_is_a_value_error(tmp_path):
    src = tmp_path / "m.sdf"
    src.write_text("<sdf><model>")
    with pytest.raises(ValueError, match="not well-formed XML"):
        write_drake(src, tmp_path / "t.sdf", ("a", "b"), {})
