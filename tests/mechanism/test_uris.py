"""``package://`` URIs of robot files: the user's folders, ROS_PACKAGE_PATH, PyBullet's rule."""

import pytest

from contactalpha.mechanism import uris

URDF = """<robot name="r"><link name="a"><collision><geometry>
<mesh filename="package://{uri}"/></geometry></collision>
<visual><geometry><mesh filename="local/v.obj"/></geometry></visual></link></robot>"""


def _robot(tmp_path, uri):
    (tmp_path / "robot").mkdir()
    path = tmp_path / "robot" / "r.urdf"
    path.write_text(URDF.format(uri=uri))
    return path


def test_user_folder_wins(tmp_path, monkeypatch):
    monkeypatch.delenv(uris.ENVIRONMENT, raising=False)
    mine = tmp_path / "mine" / "meshes"
    mine.mkdir(parents=True)
    (mine / "m.stl").write_text("solid")
    path = _robot(tmp_path, "arm/meshes/m.stl")
    packages = uris.parse_package_paths([f"arm={tmp_path / 'mine'}"])
    text = uris.resolved_text(path, packages)
    assert f'filename="{mine / "m.stl"}"' in text
    # Every other relative name is made absolute against the robot file's folder.
    assert f'filename="{tmp_path / "robot" / "local" / "v.obj"}"' in text


def test_ros_package_path_then_beside_the_file(tmp_path, monkeypatch):
    ros = tmp_path / "ros"
    (ros / "arm" / "meshes").mkdir(parents=True)
    (ros / "arm" / "meshes" / "m.stl").write_text("solid")
    path = _robot(tmp_path, "arm/meshes/m.stl")
    monkeypatch.setenv(uris.ENVIRONMENT, str(ros))
    assert uris.resolve("package://arm/meshes/m.stl", path.parent) == ros / "arm" / "meshes" / "m.stl"
    # pybullet_data's rule: package://meshes/x beside the URDF.
    (path.parent / "meshes").mkdir()
    (path.parent / "meshes" / "x.obj").write_text("o")
    assert uris.resolve("package://meshes/x.obj", path.parent) == path.parent / "meshes" / "x.obj"


def test_unresolved_uri_names_the_fix(tmp_path, monkeypatch):
    monkeypatch.delenv(uris.ENVIRONMENT, raising=False)
    path = _robot(tmp_path, "arm/meshes/m.stl")
    with pytest.raises(
        ValueError, match=r"no file for package 'arm'; give its folder with --package-path arm=DIR"
    ):
        uris.resolved_text(path)


def test_malformed_package_path_is_refused(tmp_path):
    with pytest.raises(ValueError, match="must be NAME=DIR"):
        uris.parse_package_paths(["arm"])
    with pytest.raises(ValueError, match="is not a folder"):
        uris.parse_package_paths([f"arm={tmp_path / 'none'}"])


def test_using_sets_the_active_folders(tmp_path):
    assert uris.active() == {}
    with uris.using({"arm": tmp_path}):
        assert uris.active() == {"arm": tmp_path}
    assert uris.active() == {}


def test_mujoco_loads_pybullet_datas_panda(mujoco, pybullet):
    # panda.urdf names its meshes package://meshes/...: MuJoCo alone cannot open them.
    import pybullet_data

    from contactalpha.mechanism.mujoco_model import load_model

    path = f"{pybullet_data.getDataPath()}/franka_panda/panda.urdf"
    with pytest.raises(ValueError, match="package:/meshes"):
        mujoco.MjModel.from_xml_path(path)
    m = load_model(path)
    assert m.nbody == 10 and m.nq == 9


CUBE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n"


def test_cli_package_path_resolves_for_mujoco(mujoco, tmp_path, monkeypatch):
    import subprocess
    import sys

    monkeypatch.delenv(uris.ENVIRONMENT, raising=False)
    (tmp_path / "pkg" / "meshes").mkdir(parents=True)
    (tmp_path / "pkg" / "meshes" / "c.obj").write_text(CUBE)
    (tmp_path / "robot").mkdir()
    urdf = tmp_path / "robot" / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" '
        'ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry><mesh filename="package://mypkg/meshes/c.obj"/>'
        "</geometry></collision></link></robot>"
    )

    def run(*extra):
        args = [sys.executable, "-m", "contactalpha", "tune", str(urdf), "--pair", "x", "y", "--e-n", "0.5",
                "--speed", "1", "--engine", "mujoco", *extra]  # fmt: skip
        return subprocess.run(args, capture_output=True, text=True, timeout=120)

    missing = run()
    assert missing.returncode == 2
    assert "no file for package 'mypkg'; give its folder with --package-path mypkg=DIR" in missing.stderr
    found = run("--package-path", f"mypkg={tmp_path / 'pkg'}")
    assert (
        found.returncode == 2 and "geometry 'x' is not in the model" in found.stderr
    )  # loaded: the mesh read
