"""docs/adding-an-engine.md, followed to the letter, gives a complete engine on every path.

In a copy of the package the page's two modules become ``adapters/toy.py`` and
``mechanism/toy_model.py`` and the registry gets its line; nothing else changes.  The engine then
works in a fresh process on every path: one scene, a batch, a model file (``contactalpha
tune``), the JAX front door, ``--refine``; at its step (and ``--verify``) it is refused until
``stepping`` runs a map it does not ship, never run as another engine's.  What it prints is
checked against a drop stepped here, independently of the adapters.  Each part of the record,
removed, gives an error naming it.
"""

import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contactalpha.adapters.contract import check_adapter
from contactalpha.adapters.record import PARTS, Engine, Ref, check_engine

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "adding-an-engine.md"
MODULES = ("adapters/toy.py", "mechanism/toy_model.py")
SCENE = {"e-n": 0.5, "mass": 0.5, "stiffness": 1.0e5, "speed": 0.5, "accel": 9.81}  # 7 steps in contact
TIMESTEP, PHASES = 1e-3, 4  # the page's ToySettings


def page_modules():
    """{path under src/contactalpha: text} of the page's python blocks whose first line names a file."""
    blocks = re.findall(r"^```python\n(.*?)^```$", PAGE.read_text(), flags=re.S | re.M)
    found = {}
    for path in MODULES:
        header = f"# src/contactalpha/{path}\n"
        hits = [b for b in blocks if b.startswith(header)]
        assert len(hits) == 1, f"{PAGE.name} must hold one block starting with {header!r}"
        found[path] = hits[0]
    return found


def snapshot(tree):
    """{relative path: bytes} of the package's files (no caches)."""
    return {
        p.relative_to(tree).as_posix(): p.read_bytes()
        for p in sorted(tree.rglob("*"))
        if p.is_file() and "__pycache__" not in p.parts
    }


def add_toy_engine(package):
    """The page's steps: its modules, and the import and ``ENGINES`` line in the registry."""
    for path, text in page_modules().items():
        (package / path).write_text(text)
    registry = package / "adapters" / "registry.py"
    text = registry.read_text()
    anchor = "        pybullet_kv.ENGINE,\n"
    assert text.count(anchor) == 1
    text = text.replace(anchor, anchor + "        toy.ENGINE,\n")
    first_import = "from contactalpha.adapters import "
    assert text.count(first_import) == 1
    text = text.replace(first_import, "from contactalpha.adapters import toy\n" + first_import)
    registry.write_text(text)


def stepped_e_n(c, k=SCENE["stiffness"], phases=None, h=TIMESTEP):
    """Mean e_N over touchdown ``phases`` of the toy's step ``h``, found here: the rebound speed at the
    floor from the flight parabola through the first state back above it (semi-implicit Euler)."""
    m, v_minus, a = SCENE["mass"], SCENE["speed"], SCENE["accel"]
    out = []
    for p in np.arange(PHASES) / PHASES if phases is None else phases:
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


@pytest.fixture(scope="module")
def toy_package(tmp_path_factory):
    """A copy of the package with the toy engine added as the page says; the files that changed."""
    src = tmp_path_factory.mktemp("toy") / "src"
    package = src / "contactalpha"
    shutil.copytree(ROOT / "src" / "contactalpha", package)  # numba's cache comes along
    before = snapshot(package)
    add_toy_engine(package)
    after = snapshot(package)
    changed = sorted(p for p in after.keys() | before.keys() if after.get(p) != before.get(p))
    return src, changed


def run_in(src, argv, **kwargs):
    env = {**os.environ, "PYTHONPATH": str(src)}
    return subprocess.run(
        [sys.executable, *argv], capture_output=True, text=True, env=env, timeout=600, **kwargs
    )


def test_the_page_adds_a_complete_engine_in_three_files(toy_package):
    src, changed = toy_package
    assert changed == ["adapters/registry.py", "adapters/toy.py", "mechanism/toy_model.py"]

    argv = ["params", "--engine", "toy", "--refine"] + [f"--{k}={v}" for k, v in SCENE.items()]
    run = run_in(src, ["-m", "contactalpha", *argv])
    assert run.returncode == 0, run.stderr
    printed = dict(re.findall(r"^toy\.(\w+)\s+(\S+)", run.stdout, flags=re.M))
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


# Run in the copy: every path but --refine, each printing what the test checks.
PATHS = """
import json, math, sys
import numpy as np
import contactalpha as ca
from contactalpha.adapters.registry import engine

out = {}
one = ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1e5, approach_speed=0.5, accel=9.81, engine="toy")
out["scalar"] = {"zeta": float(one.damping), **{k: float(v) for k, v in one.block.items()}}
e, v = np.array([0.5, 0.7, 0.3]), np.array([0.5, 1.0, 2.0])
scene = dict(mass=0.5, stiffness=1e5, accel=9.81, law="kelvin_voigt")
batch = ca.contact_parameters(e_N=e, approach_speed=v, **scene)
rows = [ca.contact_parameters(e_N=float(a), approach_speed=float(b), **scene).engines["toy"]["c"]
        for a, b in zip(e, v)]
out["batch"] = {"c": batch.engines["toy"]["c"].tolist(), "zeta": batch.damping.tolist(),
                "rows": [float(r) for r in rows]}
s = engine("toy").step_map
p = s.from_block(one.block, 0.5, None)
out["drop"] = [s.drop(p, 1e-3, phase, 0.5, 9.81, 10**5)[0] for phase in (0.0, 0.3, 0.7)]
try:
    import jax
    jax.config.update("jax_enable_x64", True)
    from contactalpha.xla.front import contact_parameters
    got = contact_parameters(0.5, 1e5, 0.5, 9.81, 0.5, law="kelvin_voigt")
    out["jax"] = {k: float(x) for k, x in got["engines"]["toy"].items()}
except ImportError:
    out["jax"] = None
try:
    at = ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1e5, approach_speed=0.5, accel=9.81, engine="toy",
                               timestep=1e-3)
    out["step"] = {"c": float(at.block["c"]), "mean": float(at.stepped.mean)}
except ValueError as err:
    out["step"] = str(err)
print(json.dumps(out))
"""


@pytest.mark.integration
def test_the_toy_engine_works_on_every_path(toy_package, tmp_path):
    src, _ = toy_package
    run = run_in(src, ["-c", PATHS])
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout.splitlines()[-1])
    k, m = SCENE["stiffness"], SCENE["mass"]
    one = got["scalar"]
    # One scene: the block is the law's zeta in the engine's names (the law's own check: below).
    assert one["k"] == k and one["c"] == pytest.approx(2.0 * one["zeta"] * math.sqrt(k * m), rel=1e-15)
    # A batch: each row the batch's zeta in the engine's names, and that scene's own call (whose
    # zeta the law's exact inverse gives, the batch's its table: within 1e-9).
    b = got["batch"]
    assert b["c"] == pytest.approx([2.0 * z * math.sqrt(k * m) for z in b["zeta"]], rel=1e-15)
    assert b["c"] == pytest.approx(b["rows"], rel=1e-9)
    # The toy's step map: its drop is the step stepped here, phase by phase.
    for phase, e in zip((0.0, 0.3, 0.7), got["drop"], strict=True):
        assert e == pytest.approx(stepped_e_n(one["c"], phases=[phase]), rel=1e-12)
    # JAX: the record's batched block, the same numbers.
    if got["jax"] is not None:
        assert got["jax"]["k"] == k and got["jax"]["c"] == pytest.approx(one["c"], rel=1e-9)
    # At its step: refused naming the engine (stepping does not run the toy's map), or right.
    if isinstance(got["step"], str):
        assert "'toy'" in got["step"] and "step map" in got["step"]
    else:
        phases = np.arange(256) / 256
        assert stepped_e_n(got["step"]["c"], phases=phases) == pytest.approx(SCENE["e-n"], abs=2e-3)

    # A model file: `contactalpha tune` reads the toy's file and writes its block.
    model = tmp_path / "ball.toy"
    model.write_text(json.dumps({"mass": m, "gravity": SCENE["accel"], "timestep": TIMESTEP}))
    argv = ["tune", str(model), "--pair", "floor", "ball", "--e-n", "0.5", "--speed", "0.5",
            "--engine", "toy", "--stiffness", str(k)]  # fmt: skip
    tuned = run_in(src, ["-m", "contactalpha", *argv])
    assert tuned.returncode == 0, tuned.stderr
    written = json.loads((tmp_path / "ball_tuned.toy").read_text())
    assert written["k"] == k and written["c"] == one["c"]  # m_eff = the ball's mass, the load is g
    # --verify at the step: refused in one line (exit 2), or measured in the toy.
    argv = ["params", "--engine", "toy", "--timestep", "1e-3", "--verify", "64"]
    verify = run_in(src, ["-m", "contactalpha", *argv, *(f"--{k}={v}" for k, v in SCENE.items())])
    if verify.returncode:
        assert verify.returncode == 2 and "toy" in verify.stderr and len(verify.stderr.splitlines()) == 1
    else:
        assert "verify" in verify.stdout


def test_the_continuous_law_of_the_toy_delivers_the_target_at_a_fine_step():
    """The law's zeta (the scalar path's block) delivers e_N 0.5 where the step resolves the contact."""
    import contactalpha as ca

    cp = ca.contact_parameters(
        e_N=0.5, mass=0.5, stiffness=1e3, approach_speed=0.5, accel=9.81, law="kelvin_voigt"
    )
    c = 2.0 * float(cp.damping) * math.sqrt(1e3 * 0.5)
    assert stepped_e_n(c, k=1e3, phases=[0.0, 0.5], h=2e-5) == pytest.approx(0.5, abs=2e-3)


def _toy_module():
    """The page's toy module, run here (its record's Refs stay unresolved)."""
    namespace = {"__name__": "toy_from_the_page"}
    text = page_modules()["adapters/toy.py"].replace("cache=True", "cache=False")  # nothing compiles here
    exec(compile(text, str(PAGE), "exec"), namespace)  # noqa: S102
    return namespace


@pytest.mark.parametrize("part", PARTS)
def test_removing_a_part_of_the_toys_record_names_it(part):
    record = _toy_module()["ENGINE"]
    assert check_engine(record) is record
    with pytest.raises(TypeError, match=part):
        Engine(**{p: getattr(record, p) for p in PARTS if p != part})


@pytest.mark.parametrize("part", ["parameters", "build_drop", "run", "static_penetration", "timestep"])
def test_removing_a_method_of_the_toys_adapter_names_it(part):
    cls = _toy_module()["ToyAdapter"]
    stripped = type("Stripped", (cls,), {part: None})
    with pytest.raises(TypeError, match=part):
        check_adapter(stripped())


def test_removing_the_toys_units_model_reader_or_math_guard_names_it():
    toy = _toy_module()
    record = toy["ENGINE"]
    no_units = type("NoUnits", (toy["ToyAdapter"],), {"units": {}})()
    with pytest.raises(TypeError, match="units"):
        check_engine(Engine(**{**{p: getattr(record, p) for p in PARTS}, "adapter": no_units}))
    with pytest.raises(ImportError, match="toy_model"):
        Ref("contactalpha.mechanism.toy_model:read_toy").get()  # the page's second module, not added here
    # The page's old toy wrote c with math.sqrt, which the batched front door cannot call.
    page = page_modules()["adapters/toy.py"].replace("cache=True", "cache=False")
    old = page.replace("np.sqrt(scene.stiffness * scene.mass)", "math.sqrt(scene.stiffness * scene.mass)")
    assert old != page
    namespace = {"__name__": "old_toy"}
    exec(compile(old, str(PAGE), "exec"), namespace)  # noqa: S102
    with pytest.raises(TypeError, match=r"parameters.*numpy arrays"):
        check_adapter(namespace["ADAPTER"])
