"""Compiled kernels never outlive the sources they were compiled from (engine/jitcache.py)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numba
import pytest
from numba.core.caching import CacheImpl

import contactalpha as ca
from contactalpha.engine.jitcache import FOLDER_PREFIX, PackageSourceLocator
from contactalpha.provenance import PACKAGE_DIR, source_files, source_hash

# One impact through the cached kernels (compiled, not the first call's Python twin: firstcall.py);
# prints eps with all its digits.
PROBE = (
    "from contactalpha.engine.driver import impact; from contactalpha.engine.firstcall import compiled_only\n"
    "with compiled_only(): print(repr(float(impact(5.0, 0.2).eps)))"
)
HERTZ_LINE = "HERTZ = 1.25\n"

needs_jit = pytest.mark.skipif(numba.config.DISABLE_JIT, reason="NUMBA_DISABLE_JIT=1: nothing is cached")


def _copy_package(tmp_path):
    dst = tmp_path / "src" / "contactalpha"
    shutil.copytree(PACKAGE_DIR, dst, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return dst


def _start(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CACHE")}
    env.update(PYTHONPATH=str(tmp_path / "src"), NUMBA_NUM_THREADS="1")
    cmd = [sys.executable, "-c", PROBE]
    pipe = subprocess.PIPE
    return subprocess.Popen(cmd, cwd=tmp_path, env=env, stdout=pipe, stderr=pipe, text=True)


def _eps(*procs):
    values = []
    for proc in procs:
        out, err = proc.communicate(timeout=600)
        assert proc.returncode == 0, err
        values.append(float(out))
    return values


def test_kernel_closure_contains_its_callee_modules():
    names = {p.relative_to(PACKAGE_DIR).as_posix() for p in source_files("contactalpha.engine.kernel")}
    callees = {"rk.py", "events.py", "tableau.py", "codes.py"}
    assert {f"engine/{name}" for name in callees | {"kernel.py"}} <= names
    assert "engine/solver.py" not in names  # a caller is no dependency
    assert source_hash("contactalpha.engine.kernel") != source_hash("contactalpha.engine.rk")


@needs_jit
@pytest.mark.integration  # compiles the kernels twice in fresh processes
def test_editing_a_callee_module_recompiles_and_reverting_restores(tmp_path):
    pkg = _copy_package(tmp_path)
    rk = pkg / "engine" / "rk.py"
    original = rk.read_text()
    assert original.count(HERTZ_LINE) == 1
    # Two concurrent cold starts compile into the same empty cache.
    cold = _eps(_start(tmp_path), _start(tmp_path))
    here = float(ca.impact(5.0, 0.2).eps)
    assert cold == [here, here]
    assert abs(here - 0.307317) < 5e-7
    rk.write_text(original.replace(HERTZ_LINE, "HERTZ = 1.3\n"))
    (edited,) = _eps(_start(tmp_path))
    assert abs(edited - 0.306291) < 5e-7  # the new constant runs, not the cached old kernel
    rk.write_text(original)
    (reverted,) = _eps(_start(tmp_path))
    assert reverted == here
    # The kernel module itself was never edited; its cache lives in one folder per code version.
    cache = pkg / "engine" / "__pycache__"
    versions = {p.parent.name for p in cache.glob(f"{FOLDER_PREFIX}*/kernel.*.nbi")}
    assert len(versions) == 2, sorted(p.name for p in cache.iterdir())


def test_users_own_functions_are_left_to_numba(tmp_path):
    user = tmp_path / "user_code.py"
    user.write_text("def f(x):\n    return x\n")
    namespace = {}
    exec(compile(user.read_text(), str(user), "exec"), namespace)
    assert PackageSourceLocator.from_function(namespace["f"], str(user)) is None
    assert CacheImpl._locator_classes[0] is PackageSourceLocator
    # A package function is located in a folder named after its code version.
    kernel_file = PACKAGE_DIR / "engine" / "kernel.py"
    from contactalpha.engine.kernel import impact_kernel

    loc = PackageSourceLocator.from_function(impact_kernel.py_func, str(kernel_file))
    assert Path(loc.get_cache_path()).name == FOLDER_PREFIX + source_hash(kernel_file)[:16]
    assert loc.get_source_stamp() == source_hash(kernel_file)


def test_an_import_added_in_this_process_enters_the_closure(tmp_path):
    # The parsed imports are memoised per file content: an edit in a running process is seen.
    pkg = _copy_package(tmp_path)
    probe = (
        "from pathlib import Path\n"
        "from contactalpha.provenance import source_files\n"
        "def names():\n"
        "    return sorted(p.name for p in source_files('contactalpha.engine.kernel'))\n"
        "before = names()\n"
        f"kernel = Path({str(pkg / 'engine' / 'kernel.py')!r})\n"
        "late = '\\n\\ndef _late():\\n    from .solver import solve_point\\n'\n"
        "kernel.write_text(kernel.read_text() + late)\n"
        "print(before == names(), 'solver.py' in before, 'solver.py' in names())\n"
    )
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "src")}
    done = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["False", "False", "True"]
