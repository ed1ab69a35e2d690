"""A read-only install with no writable numba cache folder still runs (issue 34, R6)."""

import os
import shutil
import subprocess
import sys

import numba
import pytest

from contactalpha.provenance import PACKAGE_DIR

# Small cached kernels (the array path of influence_factor), quick to compile.
PROBE = (
    "import numpy as np; from contactalpha.engine.scaling import influence_factor\n"
    "print(repr(float(influence_factor(np.array([0.5, 1.0]), 1e5, 0.5, 9.81)[1])))"
)


@pytest.mark.skipif(numba.config.DISABLE_JIT, reason="NUMBA_DISABLE_JIT=1: nothing is cached")
def test_no_writable_cache_folder_compiles_for_the_process_and_says_so_once(tmp_path):
    dst = tmp_path / "src" / "contactalpha"
    shutil.copytree(PACKAGE_DIR, dst, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    # A file where every folder numba could write would have to be: nothing can be created there,
    # not even by root (for whom a chmod'ed read-only copy stays writable).
    for folder in [dst, *(p for p in dst.rglob("*") if p.is_dir())]:
        (folder / "__pycache__").write_text("")
    blocker = tmp_path / "blocker"
    blocker.write_text("")
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CACHE")}
    env.update(
        PYTHONPATH=str(tmp_path / "src"),
        NUMBA_NUM_THREADS="1",
        HOME=str(blocker / "home"),
        XDG_CACHE_HOME=str(blocker / "cache"),
        TMPDIR=str(tmp_path),
    )
    run = subprocess.run(
        [sys.executable, "-c", PROBE], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr[-2000:]
    from contactalpha.engine.scaling import influence_factor

    assert float(run.stdout) == float(influence_factor(1.0, 1e5, 0.5, 9.81))
    assert run.stderr.count("NUMBA_CACHE_DIR") == 1 and "Traceback" not in run.stderr
    assert not list(tmp_path.glob("contactalpha-numba-*"))  # the process's folder is gone with it
