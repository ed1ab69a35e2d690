"""Every shipped table is checked against its law, grid and checksum on load (issue 34, R2)."""

import json
import shutil

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine import table as engine_table
from contactalpha.engine.table import (
    ARRAY_NAMES,
    DEFAULT_FILE,
    KINEMATIC_ARRAY_NAMES,
    KINEMATIC_FILE,
    SHIPPED_GRIDS,
    AlphaTable,
    checksum,
    read_table_file,
)
from contactalpha.engine.table_build import save_table
from contactalpha.laws import get_law
from contactalpha.laws import table as law_table


def raw(path, names):
    with np.load(path) as z:
        return {k: np.ascontiguousarray(z[k]) for k in names}, json.loads(str(z["meta"]))


def test_the_shipped_alpha_tables_record_their_checksum_and_the_shipped_grid():
    for path, names in ((DEFAULT_FILE, ARRAY_NAMES), (KINEMATIC_FILE, KINEMATIC_ARRAY_NAMES)):
        arrays, meta = raw(path, names)
        assert meta["sha256"] == checksum(arrays)
        assert {key: meta[key] for key in SHIPPED_GRIDS[path]} == SHIPPED_GRIDS[path]
        read_table_file(path, names)


def test_the_shipped_grids_are_the_workflows_configured_ones():
    yaml = pytest.importorskip("yaml")
    config = yaml.safe_load((DEFAULT_FILE.parents[3] / "config.yaml").read_text())
    for section, path in (("models", DEFAULT_FILE), ("restitution", KINEMATIC_FILE)):
        table = config[section]["table"]
        assert {key: table[key] for key in SHIPPED_GRIDS[path]} == SHIPPED_GRIDS[path]


@pytest.fixture
def shipped_path(tmp_path, monkeypatch):
    """A copy of the energetic table's path that the package treats as its own."""
    path = (tmp_path / "alpha_table.npz").resolve()
    monkeypatch.setitem(SHIPPED_GRIDS, path, SHIPPED_GRIDS[DEFAULT_FILE])
    monkeypatch.setattr(engine_table, "_CACHE", {})
    return path


def test_a_table_of_another_grid_at_the_packages_path_is_refused(shipped_path):
    arrays, meta = raw(DEFAULT_FILE, ARRAY_NAMES)
    coarse = dict(meta, n_eta=41, n_p=21)  # as the workflow's test config builds it
    save_table(AlphaTable(**arrays, meta=coarse), shipped_path)
    with pytest.raises(ValueError, match=r"built with \{'n_eta': 41, 'n_p': 21.* not have the documented"):
        ca.alpha_tabulated(0.5, 0.2, path=shipped_path)
    shutil.copy(DEFAULT_FILE, shipped_path)
    assert ca.alpha_tabulated(0.5, 0.2, path=shipped_path) == ca.alpha_tabulated(0.5, 0.2)


def test_a_table_whose_numbers_changed_is_refused_by_its_checksum(tmp_path):
    arrays, meta = raw(DEFAULT_FILE, ARRAY_NAMES)
    path = save_table(AlphaTable(**arrays, meta=meta), tmp_path / "t.npz")
    arrays["s_c"][3, 3] *= 1.0 + 1e-6
    old = checksum(raw(DEFAULT_FILE, ARRAY_NAMES)[0])
    with open(path, "wb") as fh:  # the old checksum with new numbers
        np.savez_compressed(fh, **arrays, meta=json.dumps(meta | {"sha256": old}))
    with pytest.raises(ValueError, match=f"exact-alpha table {path}: checksum .* differs"):
        ca.alpha_tabulated(0.5, 0.2, path=path)


def test_a_table_without_a_recorded_checksum_is_refused(tmp_path):
    arrays, meta = raw(KINEMATIC_FILE, KINEMATIC_ARRAY_NAMES)
    meta.pop("sha256")
    path = tmp_path / "k.npz"
    with open(path, "wb") as fh:
        np.savez_compressed(fh, **arrays, meta=json.dumps(meta))
    with pytest.raises(ValueError, match="differs from the recorded None"):
        ca.alpha_tabulated(0.5, 0.2, path=path, restitution="kinematic")


@pytest.fixture
def law_data(tmp_path, monkeypatch):
    """A copy of the package's law tables that the laws read instead."""
    for law in ("kelvin_voigt", "hertz_tsuji"):
        shutil.copy(law_table.DATA / f"law_table_{law}.npz", tmp_path)
    monkeypatch.setattr(law_table, "DATA", tmp_path)
    monkeypatch.setattr(law_table, "_PACKED", {})
    return tmp_path


def test_another_laws_table_in_a_laws_place_is_refused(law_data):
    ht = get_law("hertz_tsuji")
    right = float(ht.fast_damping(0.5, 0.2))
    assert right == pytest.approx(float(ht.damping_for(0.5, 0.2).damping), rel=1e-6)
    law_table._PACKED.clear()
    shutil.copy(law_data / "law_table_kelvin_voigt.npz", law_data / "law_table_hertz_tsuji.npz")
    with pytest.raises(ValueError, match="holds law 'kelvin_voigt', expected 'hertz_tsuji'"):
        ht.fast_damping(0.5, 0.2)
    with pytest.raises(ValueError, match="holds law 'kelvin_voigt'"):
        ca.contact_parameters(e_N=np.array([0.3, 0.5, 0.8]), mass=1.0, stiffness=1e5, approach_speed=0.5,
                              accel=9.81, law="hertz_tsuji")  # fmt: skip


def test_a_law_table_of_another_grid_is_refused(law_data):
    arrays, meta = law_table.load_law_tables(law_data / "law_table_hertz_tsuji.npz")
    law_table.save_law_tables(arrays, dict(meta, n_eta=199), law_data / "law_table_hertz_tsuji.npz")
    with pytest.raises(ValueError, match=r"has grid \{'n_eta': 199.*expected \{'n_eta': 139"):
        get_law("hertz_tsuji").fast_damping(0.5, 0.2)
