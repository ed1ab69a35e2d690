import json
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from contactalpha.io import json_text, jsonable, write_json_atomic
from contactalpha.provenance import result_attrs
from contactalpha.version import __version__


def test_json_text_writes_numpy_values_as_numbers_and_non_finite_as_null():
    obj = {"a": np.float64(0.5), 3: (np.int64(2), np.nan), "arr": np.array([1.0, np.inf]), "p": Path("x/y")}
    assert json.loads(json_text(obj)) == {"a": 0.5, "3": [2, None], "arr": [1.0, None], "p": "x/y"}


def test_json_text_refuses_what_it_cannot_write():
    with pytest.raises(TypeError):
        json_text({"f": object()})


def test_jsonable_keeps_plain_data():
    plain = {"k": [1, 2.5, "s", None, True]}
    assert jsonable(plain) == plain


def test_write_json_atomic_is_readable_by_everyone_and_leaves_no_temporary(tmp_path):
    path = write_json_atomic(tmp_path / "r.json", {"x": float("nan"), "y": 1})
    assert path.read_text() == '{\n "x": null,\n "y": 1\n}\n'
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~mask
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]


def test_result_attrs_name_the_package_version_and_keep_the_config():
    attrs = result_attrs({"b": 1, "a": [0.1, 2]}, "a step")
    assert attrs["contactalpha_version"] == __version__
    assert json.loads(attrs["config"]) == {"a": [0.1, 2], "b": 1}
    assert attrs["config"].index('"a"') < attrs["config"].index('"b"')
    assert "a step" in attrs["history"] and attrs["git_commit"]
