"""docs/adding-an-engine.md, followed to the letter, gives a complete engine: ``--refine`` included.

In a copy of the package the page's toy adapter becomes ``adapters/toy.py`` and the registry gets
its line; nothing else changes.  ``contactalpha params --engine toy --refine`` then runs in a fresh
process, and what it prints is checked against a drop stepped here, independently of the adapters.
"""

import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "adding-an-engine.md"
HEADER = "# src/contactalpha/adapters/toy.py"
SCENE = {"e-n": 0.5, "mass": 0.5, "stiffness": 1.0e5, "speed": 0.5, "accel": 9.81}  # 7 steps in contact
TIMESTEP, PHASES = 1e-3, 4  # the page's ToySettings


def page_adapter():
    """The page's toy adapter: the python block whose first line names the file."""
    blocks = re.findall(r"^```python\n(.*?)^```$", PAGE.read_text(), flags=re.S | re.M)
    found = [b for b in blocks if b.startswith(HEADER + "\n")]
    assert len(found) == 1, f"{PAGE.name} must hold one block starting with {HEADER!r}"
    return found[0]


def snapshot(tree):
    """{relative path: bytes} of the package's files (no caches)."""
    return {
        p.relative_to(tree).as_posix(): p.read_bytes()
        for p in sorted(tree.rglob("*"))
        if p.is_file() and "__pycache__" not in p.parts
    }


def add_toy_engine(package):
    """The page's two steps: the module, and its import and ``ADAPTERS`` line in the registry."""
    (package / "adapters" / "toy.py").write_text(page_adapter())
    registry = package / "adapters" / "registry.py"
    text = registry.read_text()
    anchor = "        pybullet_kv.ADAPTER,\n"
    assert text.count(anchor) == 1
    text = text.replace(anchor, anchor + "        toy.ADAPTER,\n")
    first_import = "from contactalpha.adapters import "
    assert text.count(first_import) == 1
    text = text.replace(first_import, "from contactalpha.adapters import toy\n" + first_import)
    registry.write_text(text)


def stepped_e_n(c, k=SCENE["stiffness"], m=SCENE["mass"], v_minus=SCENE["speed"], a=SCENE["accel"]):
    """Mean e_N over touchdown phases of the toy's step, found here: the rebound speed at the floor
    from the flight parabola through the first state back above it (semi-implicit Euler)."""
    h, out = TIMESTEP, []
    for p in np.arange(PHASES) / PHASES:
        tc = p * h  # the parabola meets z = 0 at -v_minus a time tc after the first state
        w = -v_minus + a * tc
        z, v = -(w * tc - 0.5 * a * tc * tc), w + 0.5 * a * h
        touched = False
        for _ in range(100_000):
            f = max(0.0, -k * z - c * v) if z < 0.0 else 0.0
            v_new = v + h * (f / m - a)
            z_new = z + h * v_new
            if touched and z > 0.0:  # back above the floor: a free step, on the flight parabola
                s = v_new - 0.5 * a * h  # the parabola's speed at the step's end
                out.append(math.sqrt(s * s + 2.0 * a * z_new) / v_minus)
                break
            touched |= z_new < 0.0
            z, v = z_new, v_new
    return float(np.mean(out))


def test_the_page_adds_a_complete_engine_in_two_files(tmp_path):
    package = tmp_path / "src" / "contactalpha"
    shutil.copytree(ROOT / "src" / "contactalpha", package)  # numba's cache comes along
    before = snapshot(package)
    add_toy_engine(package)
    after = snapshot(package)
    changed = sorted(p for p in after.keys() | before.keys() if after.get(p) != before.get(p))
    assert changed == ["adapters/registry.py", "adapters/toy.py"]

    argv = ["params", "--engine", "toy", "--refine"] + [f"--{k}={v}" for k, v in SCENE.items()]
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "src")}
    run = subprocess.run(
        [sys.executable, "-m", "contactalpha", *argv], capture_output=True, text=True, env=env, timeout=600
    )
    assert run.returncode == 0, run.stderr
    printed = dict(re.findall(r"^toy\.(\w+)\s+(\S+)$", run.stdout, flags=re.M))
    assert float(printed["k"]) == SCENE["stiffness"]
    refined = re.search(r"refined on toy's drops: zeta = (\S+), delivers (\S+)", run.stdout)
    assert refined, run.stdout
    zeta, delivered = float(refined.group(1)), float(refined.group(2))
    c = float(printed["c"])
    assert c == pytest.approx(2.0 * zeta * math.sqrt(SCENE["stiffness"] * SCENE["mass"]), rel=1e-12)
    # The refined damping delivers the target in a drop stepped here; the law's does not.
    assert abs(delivered - SCENE["e-n"]) <= 1e-3
    assert abs(stepped_e_n(c) - SCENE["e-n"]) <= 1e-3
    law = re.search(r"law kelvin_voigt: zeta = (\S+) \(law\)", run.stdout)
    c_law = 2.0 * float(law.group(1)) * math.sqrt(SCENE["stiffness"] * SCENE["mass"])
    assert abs(stepped_e_n(c_law) - SCENE["e-n"]) > 1e-3
