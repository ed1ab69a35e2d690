"""What ``tune`` refuses, by name: steps, coordinates, outputs, links, large files, unreachable targets."""

import os
import re

import hand
import numpy as np
import pytest
from hand import MODELS

from contactalpha.cli import main
from contactalpha.mechanism import inputs
from contactalpha.mechanism.inputs import check_link, link_inertias
from contactalpha.mechanism.tune import tune
from contactalpha.parameters.reach import EXIT_UNREACHABLE

PENDULUM = str(MODELS / "pendulum.xml")
ARM = MODELS / "arm.urdf"
TUNE = ["tune", PENDULUM, "--pair", "wall", "tip", "--e-n", "0.5", "--qvel", "1.6", "--stiffness", "1e4"]


def _one_line_error(capsys, argv, code=2):
    assert main(argv) == code
    lines = [x for x in capsys.readouterr().err.splitlines() if "compil" not in x]  # numba's first use
    assert len(lines) == 1, lines
    return lines[0]


@pytest.mark.parametrize("h", ["0", "-1e-3", "nan", "inf"])
def test_cli_refuses_a_step_out_of_range(tmp_path, capsys, h):
    out = tmp_path / "t.xml"
    err = _one_line_error(capsys, [*TUNE, "-o", str(out), "--timestep", h])
    assert re.search(r"timestep = \S+ is outside the valid range \(0.0, inf\)", err), err
    assert not out.exists()


def test_cli_refuses_a_step_longer_than_the_contact(mujoco, tmp_path, capsys):
    """The undamped contact time pi sqrt(m_eff/k), with the pendulum's m_eff by hand."""
    out = tmp_path / "t.xml"
    err = _one_line_error(capsys, [*TUNE, "-o", str(out), "--timestep", "10"])
    m_eff = hand.pendulum()[0]
    assert f"pi sqrt(m_eff/k) = {np.pi * np.sqrt(m_eff / 1e4):.3g} s" in err and "timestep = 10.0" in err
    assert not out.exists()


@pytest.mark.parametrize("value", ["nan", "inf"])
def test_cli_refuses_a_configuration_that_is_not_finite(tmp_path, capsys, value):
    err = _one_line_error(capsys, [*TUNE, "-o", str(tmp_path / "t.xml"), "--qpos", value])
    assert f"qpos[0] = {float(value)!r} is not a finite number" in err


def test_cli_names_the_folder_given_as_output(tmp_path, capsys):
    err = _one_line_error(capsys, [*TUNE, "-o", str(tmp_path)])
    assert f"output = {str(tmp_path)!r} is a folder" in err and ".tmp" not in err
    err = _one_line_error(capsys, [*TUNE, "-o", str(tmp_path / "no" / "t.xml")])
    assert f"its folder {str(tmp_path / 'no')!r} does not exist" in err


def test_model_size_is_bounded(tmp_path, capsys):
    """A file one byte above ``MAX_MODEL_BYTES`` (sparse: nothing is written) is refused before reading."""
    big = tmp_path / "big.xml"
    big.write_text("<mujoco/>")
    os.truncate(big, inputs.MAX_MODEL_BYTES + 1)
    err = _one_line_error(capsys, ["tune", str(big), "--pair", "a", "b", "--e-n", "0.5", "--speed", "1"])
    assert f"big.xml' is {(inputs.MAX_MODEL_BYTES + 1) / 1e6:.1f} MB, above the 10 MB tune reads" in err


def _arm(tmp_path, mass=None, inertia=None, suffix=".urdf"):
    text = ARM.read_text()
    if mass is not None:
        text = text.replace('<mass value="1.5"/>', f'<mass value="{mass}"/>')
    if inertia is not None:
        text = text.replace('ixx="0.04" iyy="0.04" izz="0.04"', inertia)
    path = tmp_path / f"arm{suffix}"
    path.write_text(text)
    return path


def test_link_inertias_read_from_urdf_and_sdf(tmp_path):
    """The file's numbers: the arm's 1.5 kg and 0.04 I; an SDF link without <inertial>: SDFormat's 1 kg, I."""
    arm = link_inertias(ARM)
    assert arm["arm"][0] == 1.5 and np.array_equal(arm["arm"][1], 0.04 * np.eye(3))
    assert arm["world"][0] == 0.0
    sdf = tmp_path / "m.sdf"
    sdf.write_text('<sdf version="1.9"><model name="m"><link name="a"/><link name="b"><inertial>'
                   "<mass>2</mass><inertia><ixx>1</ixx><iyy>2</iyy><izz>3</izz><ixy>0.5</ixy></inertia></inertial></link>"
                   "</model></sdf>")  # fmt: skip
    got = link_inertias(sdf)
    assert got["a"][0] == 1.0 and np.array_equal(got["a"][1], np.eye(3))
    assert got["b"][0] == 2.0 and np.array_equal(got["b"][1], [[1, 0.5, 0], [0.5, 2, 0], [0, 0, 3]])


def test_an_empty_sdf_mass_element_reads_as_sdformats_default(tmp_path):
    """<mass/> with no text is SDFormat's 1 kg, as an absent one (it raised a TypeError from float(None))."""
    sdf = tmp_path / "m.sdf"
    sdf.write_text('<sdf version="1.9"><model name="m"><link name="a"><inertial><mass/></inertial></link>'
                   "</model></sdf>")  # fmt: skip
    assert link_inertias(sdf)["a"][0] == 1.0


@pytest.mark.parametrize(
    "mass, inertia, moves, message",
    [
        (0.0, np.eye(3), True, "mass = 0.0 kg; it must be above 0"),
        (-1.5, np.eye(3), False, "mass = -1.5 kg; it must be at least 0"),
        (float("nan"), np.eye(3), True, "mass = nan kg"),
        (1.0, np.diag([1.0, 1.0, 3.0]), False, "are not physical"),  # 3 > 1 + 1
        (1.0, np.diag([-1.0, 1.0, 1.0]), True, "are not physical"),
        (1.0, np.zeros((3, 3)), True, "needs all three above 0"),  # a point mass on a joint
    ],
)
def test_check_link_refuses_by_name(mass, inertia, moves, message):
    with pytest.raises(ValueError, match=re.escape("link 'arm': ")) as err:
        check_link("arm", mass, inertia, moves)
    assert message in str(err.value)


def test_check_link_keeps_what_is_physical():
    check_link("base", 0.0, np.zeros((3, 3)), False)  # a massless link that does not move
    check_link("rod", 1.0, np.diag([1e-6, 1.0, 1.0]), True)  # a thin rod: 1 + 1e-6 >= 1


@pytest.mark.parametrize("mass", ["0", "-1.5"])
@pytest.mark.parametrize("suffix", [".urdf", ".sdf"])
def test_drake_refuses_a_massless_or_negative_link(pydrake, tmp_path, capsys, mass, suffix):
    """The arm (URDF) and the pendulum (SDF) with the moving link's mass 0 or -1.5: refused, naming it."""
    if suffix == ".urdf":
        model, pair, qvel = _arm(tmp_path, mass=mass), ("floor", "tip"), "-1"
    else:
        model = tmp_path / "p.sdf"
        text = (MODELS / "pendulum.sdf").read_text()
        model.write_text(text.replace("<mass>0.5</mass>", f"<mass>{mass}</mass>"))
        pair, qvel = ("wall", "tip"), "1.6"
    out = tmp_path / f"t{suffix}"
    err = _one_line_error(capsys, ["tune", str(model), "--pair", *pair, "--e-n", "0.5", "--qvel", qvel,
                                   "--stiffness", "1e4", "--engine", "drake", "-o", str(out)])  # fmt: skip
    assert f"link 'arm': mass = {float(mass)!r} kg" in err and not out.exists()


def test_drake_takes_a_massless_link_with_a_welded_mass(pydrake, tmp_path):
    """The arm's mass on a link welded to it: one body of 1.5 kg, as MuJoCo fuses it (the arm's m_eff)."""
    text = ARM.read_text()
    inertial = text[text.index("<inertial>") : text.index("</inertial>") + len("</inertial>")]
    weight = f'<link name="weight">{inertial}</link><joint name="w" type="fixed"><parent link="arm"/>' \
             '<child link="weight"/></joint></robot>'  # fmt: skip
    model = tmp_path / "arm.urdf"
    model.write_text(text.replace(inertial, "").replace("</robot>", weight))
    got = tune(model, ("floor", "tip"), 0.5, speed=0.5, stiffness=1e4, engine="drake").contact
    m, d, i_com, tip = 1.5, 1 / 3, 0.04, 0.5
    assert got.effective_mass == pytest.approx((i_com + m * d * d) / tip**2, rel=1e-9)
    model.write_text(model.read_text().replace('<mass value="1.5"/>', '<mass value="0"/>'))
    with pytest.raises(ValueError, match=r"link 'arm' and the links welded to it \['weight'\]: mass = 0.0"):
        tune(model, ("floor", "tip"), 0.5, qvel=[-1.0], stiffness=1e4, engine="drake")


def test_drake_refuses_an_unphysical_inertia(pydrake, tmp_path, capsys):
    model = _arm(tmp_path, inertia='ixx="0.01" iyy="0.01" izz="0.04"')
    with pytest.raises(ValueError, match="link 'arm': principal moments"):
        tune(model, ("floor", "tip"), 0.5, qvel=[-1.0], stiffness=1e4, engine="drake")


@pytest.mark.parametrize("mass", ["0", "-1.5"])
def test_mujoco_refuses_a_massless_or_negative_link(mujoco, tmp_path, mass):
    """MuJoCo's compiler refuses such a model itself; its message names the body."""
    with pytest.raises(ValueError, match="mass and inertia of moving bodies.*'arm'"):
        tune(_arm(tmp_path, mass=mass), ("floor", "tip"), 0.5, qvel=[-1.0], stiffness=1e4, engine="mujoco")


UNREACHABLE = [*TUNE[:-1], "3e5", "--force", "arm", "-20", "0", "0", "--e-n", "0.9", "--timestep", "2e-3",
               "--no-engine-loop"]  # fmt: skip


def test_unreachable_at_the_step_exits_3_and_writes_nothing(mujoco, tmp_path, capsys):
    """MuJoCo at 2 ms, 3-4 steps per contact: the step's phase mean stays above 0.9 at any damping."""
    out = tmp_path / "t.xml"
    err = _one_line_error(capsys, [*UNREACHABLE, "-o", str(out)], code=EXIT_UNREACHABLE)
    assert "no damping reaches e_N 0.9 at mujoco's step 0.002 s" in err and "nothing written" in err
    assert not out.exists()
    assert main([*UNREACHABLE, "-o", str(out), "--force-write"]) == EXIT_UNREACHABLE
    assert "written anyway (--force-write)" in capsys.readouterr().err and out.exists()
    kw = {"qvel": [1.6], "stiffness": 3e5, "forces": {"arm": (-20.0, 0, 0)}, "timestep": 2e-3}
    got = tune(PENDULUM, ("wall", "tip"), 0.9, output=tmp_path / "u.xml", **kw)
    assert not got.reached and got.output is None and not (tmp_path / "u.xml").exists()
    assert got.discrete.inverse.nearest > 0.9 and 0.0 < got.discrete.inverse.timestep_reachable < 2e-3
    assert got.unreachable.startswith("no damping reaches e_N 0.9 at mujoco's step")
