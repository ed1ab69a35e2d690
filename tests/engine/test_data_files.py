"""Shipped and user data files: a corrupted or cut-short file is refused naming itself (issue 29, N8, N11)."""

import dataclasses
import shutil

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.engine.table import (
    DEFAULT_FILE,
    KINEMATIC_ARRAY_NAMES,
    KINEMATIC_FILE,
    load_table,
    read_table_file,
)
from contactalpha.engine.table_build import save_kinematic_table, save_table
from contactalpha.models import closed_form, shen


def _corrupt(path, how):
    raw = path.read_bytes()
    if how == "truncated":
        path.write_bytes(raw[: len(raw) // 2])
    elif how == "empty":
        path.write_bytes(b"")
    else:  # "garbage"
        path.write_bytes(b"\x00\xff" * 64)


@pytest.mark.parametrize("how", ["truncated", "empty", "garbage"])
@pytest.mark.parametrize("shipped", [DEFAULT_FILE, KINEMATIC_FILE], ids=["energetic", "kinematic"])
def test_a_corrupted_table_names_itself(tmp_path, shipped, how):
    """BadZipFile / EOFError without the file's name before."""
    path = tmp_path / shipped.name
    shutil.copy(shipped, path)
    _corrupt(path, how)
    restitution = "kinematic" if shipped == KINEMATIC_FILE else "energetic"
    with pytest.raises(ValueError, match=rf"exact-alpha table {path} cannot be read"):
        ca.alpha_tabulated(0.5, 0.2, path=path, restitution=restitution)


@pytest.mark.parametrize("how", ["truncated", "empty", "garbage"])
@pytest.mark.parametrize(
    "module, loader, what",
    [(shen, "load_refit", "refit constants"), (closed_form, "load_constants", "closed-form constants")],
    ids=["shen_refit.json", "closed_form.json"],
)
def test_a_corrupted_constants_file_names_itself(tmp_path, monkeypatch, module, loader, what, how):
    """JSONDecodeError without the file's name before."""
    from importlib.resources import files

    data = tmp_path / "data"
    data.mkdir()
    for shipped in (files("contactalpha") / "data").iterdir():
        if shipped.name.endswith(".json"):
            (data / shipped.name).write_bytes(shipped.read_bytes())
            _corrupt(data / shipped.name, how)
    monkeypatch.setattr(module, "files", lambda package: tmp_path)
    getattr(module, loader).cache_clear()
    try:
        with pytest.raises(ValueError, match=rf"{what} {data}/\S+\.json cannot be read"):
            getattr(module, loader)()
    finally:
        monkeypatch.undo()
        getattr(module, loader).cache_clear()
    assert getattr(module, loader)()  # the shipped file again


@pytest.mark.parametrize("name", ["s_c", "n_c", "b_c", "n_ty"])
def test_a_table_cut_short_is_refused_when_it_is_loaded(tmp_path, name):
    """Issue 29, N11: numba does not check bounds, so a cut-short array was read past its end."""
    table = load_table()
    cut = dataclasses.replace(table, **{name: getattr(table, name)[:-3]})
    path = save_table(cut, tmp_path / "cut.npz")
    with pytest.raises(ValueError, match=rf"exact-alpha table {path}: array {name} has shape"):
        ca.alpha_tabulated(0.5, 0.2, path=path)
    with pytest.raises(ValueError, match="cut short"):
        ca.jit_alpha_tabulated(path=path)


def test_a_kinematic_table_with_a_wrong_node_count_is_refused(tmp_path):
    arrays, meta = read_table_file(KINEMATIC_FILE, KINEMATIC_ARRAY_NAMES)
    geom = arrays["k_geom"].copy()
    geom[2] += 5  # five eta nodes more than the coefficients hold
    path = save_kinematic_table({**arrays, "k_geom": geom, "meta": meta}, tmp_path / "k.npz")
    with pytest.raises(ValueError, match=rf"exact-alpha table {path}: array k_tx has shape"):
        ca.alpha_tabulated(0.5, 0.2, path=path, restitution="kinematic")


def test_the_shipped_tables_pass_the_shape_check():
    for path, names in ((DEFAULT_FILE, None), (KINEMATIC_FILE, KINEMATIC_ARRAY_NAMES)):
        if names is None:
            assert np.isfinite(load_table(path).s_c).all()
        else:
            read_table_file(path, names)
