import json
import os
import re
import signal
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contactalpha.io import (
    TMP_PATTERN,
    TMP_TAG,
    claim_workdir,
    json_text,
    jsonable,
    remove_stale_temporaries,
    stale_temporaries,
    write_json_atomic,
)
from contactalpha.provenance import git_commit, result_attrs
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
    commit = git_commit()  # this checkout's HEAD (+dirty), tested in test_provenance.py
    assert attrs["git_commit"] == commit and re.fullmatch(r"[0-9a-f]{40}(\+dirty)?|unknown", commit)
    assert re.fullmatch(rf"\S+Z a step \(contactalpha {re.escape(__version__)}\)", attrs["history"])


def _killed_inside_a_write(path):
    """Run write_atomic(path) in a child process that is killed (SIGKILL) halfway through the write."""
    code = (
        "import os, signal, sys\n"
        "from contactalpha.io import write_atomic\n"
        "def write(tmp):\n"
        "    open(tmp, 'wb').write(b'half')\n"
        "    os.kill(os.getpid(), signal.SIGKILL)\n"
        "write_atomic(sys.argv[1], write)\n"
    )
    done = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, timeout=120)
    assert done.returncode == -signal.SIGKILL


def test_a_kill_inside_a_write_leaves_a_temporary_that_the_next_write_removes(tmp_path):
    target = tmp_path / "r.json"
    _killed_inside_a_write(target)
    (left,) = tmp_path.iterdir()
    assert left.name.startswith(".r.json.") and left.read_bytes() == b"half"
    assert stale_temporaries(tmp_path) == [left]
    write_json_atomic(target, {"y": 1})
    assert [p.name for p in tmp_path.iterdir()] == ["r.json"]


def test_temporaries_of_live_writers_other_hosts_and_other_targets_are_kept(tmp_path):
    target = tmp_path / "r.json"
    _killed_inside_a_write(target)
    (dead,) = tmp_path.iterdir()
    host, pid = TMP_PATTERN.match(dead.name)["host"], os.getpid()
    keep = [
        tmp_path / f".r.json.{TMP_TAG}-{host}-{pid}.abc.tmp",  # this process: alive
        tmp_path / f".r.json.{TMP_TAG}-{host}x-{dead.name.split('-')[-1]}",  # another host
        tmp_path / f".other.h5.{dead.name.split('.', 3)[-1]}",  # another target
    ]
    for path in keep:
        path.write_bytes(b"")
    assert stale_temporaries(tmp_path, target="r.json") == [dead]
    write_json_atomic(target, {})
    assert sorted(tmp_path.iterdir()) == sorted([target, *keep])
    assert remove_stale_temporaries(tmp_path) == [keep[2]]  # the other target's writer is dead too


def test_claim_workdir_clears_a_killed_runs_locks_but_not_a_live_ones(tmp_path):
    locks = tmp_path / ".snakemake" / "locks"
    locks.mkdir(parents=True)
    for name in ("0.input.lock", "0.output.lock"):
        (locks / name).write_text("results/surface.h5\n")
    (tmp_path / "results").mkdir()
    code = (
        "import sys, time\n"
        "from contactalpha.io import claim_workdir\n"
        "print(claim_workdir(sys.argv[1])[0], flush=True)\n"
        "time.sleep(600)\n"
    )
    run = subprocess.Popen([sys.executable, "-c", code, str(tmp_path)], stdout=subprocess.PIPE, text=True)
    try:
        assert run.stdout.readline().strip() == "True"  # the live run's own claim (no other run: clears)
        assert claim_workdir(tmp_path) == (False, [])  # a second run while the first lives: nothing touched
        for name in ("0.input.lock", "0.output.lock"):
            (locks / name).write_text("results/surface.h5\n")
        assert claim_workdir(tmp_path) == (False, [])
        assert sorted(p.name for p in locks.iterdir()) == ["0.input.lock", "0.output.lock"]
    finally:
        run.kill()  # SIGKILL, as kill -9
        run.wait()
    _killed_inside_a_write(tmp_path / "results" / "surface.h5")
    held, removed = claim_workdir(tmp_path)
    assert held and [p.name for p in removed[:2]] == ["0.input.lock", "0.output.lock"] and len(removed) == 3
    assert list(locks.iterdir()) == [] and list((tmp_path / "results").iterdir()) == []
    assert claim_workdir(tmp_path) == (True, [])  # held by this process from now on
