"""docs/adding-an-engine.md, followed to the letter, gives a complete engine on every path.

In a copy of the package the page's two modules become ``adapters/toy.py`` and
``mechanism/toy_model.py`` and the registry gets its line; nothing else changes.  The engine then
works in a fresh process on every path: one scene, a batch, a model file (``contactalpha
tune``), the JAX front door, ``--refine``, and at its step (one scene, a batch, ``--verify``): the
page's module registers its step map (``stepping.kernels.register_map``), so ``stepping``'s
kernels run the toy's own step.  What it prints is checked against drops stepped here in plain
Python, independently of the adapters and of ``stepping``.  Each part of the record, removed
(the map's registration too), gives an error naming it.
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


def stepped_e_n(c, k=SCENE["stiffness"], phases=None, h=TIMESTEP, v_minus=SCENE["speed"]):
    """Mean e_N over touchdown ``phases`` of the toy's step ``h``, found here: the rebound speed at the
    floor from the flight parabola through the first state back above it (semi-implicit Euler)."""
    m, a = SCENE["mass"], SCENE["accel"]
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
at = ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1e5, approach_speed=0.5, accel=9.81, engine="toy",
                           timestep=1e-3)
out["step"] = {"c": float(at.block["c"]), "mean": float(at.stepped.mean),
               "continuous": float(at.stepped.continuous_mean), "status": str(at.stepped.status)}
e = np.array([0.5, 0.7, 0.4])
at_b = ca.contact_parameters(e_N=e, mass=0.5, stiffness=1e5, approach_speed=v, accel=9.81, engine="toy",
                             timestep=1e-3)
at_rows = [ca.contact_parameters(e_N=float(a), mass=0.5, stiffness=1e5, approach_speed=float(b), accel=9.81,
                                 engine="toy", timestep=1e-3) for a, b in zip(e, v)]
out["step_batch"] = {"c": at_b.engines["toy"]["c"].tolist(), "mean": at_b.stepped.mean.tolist(),
                     "status": at_b.stepped.status.tolist(), "rows": [float(r.block["c"]) for r in at_rows],
                     "row_means": [float(r.stepped.mean) for r in at_rows], "e": e.tolist(), "v": v.tolist()}
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
    # At its step: the toy's damping whose mean over the touchdown phase is the target, by drops
    # stepped here (the midpoint rule on 1024 phases: within 1e-8 of the phase integral here), and
    # what the continuous law's damping delivers at that step.
    step, midpoints = got["step"], (np.arange(1024) + 0.5) / 1024
    assert step["status"] == "ok" and step["mean"] == pytest.approx(SCENE["e-n"], abs=1e-6)  # MEAN_TOL
    assert stepped_e_n(step["c"], phases=midpoints) == pytest.approx(SCENE["e-n"], abs=1e-6)
    assert stepped_e_n(one["c"], phases=midpoints) == pytest.approx(step["continuous"], abs=1e-7)
    assert abs(step["continuous"] - SCENE["e-n"]) > 1e-2  # the step moves the law's e_N: a real correction
    # A batch at its step: each row that scene's own call bit for bit, its mean by drops stepped here.
    sb = got["step_batch"]
    assert sb["status"] == ["ok"] * 3 and sb["c"] == sb["rows"] and sb["mean"] == sb["row_means"]
    for c, e, v in zip(sb["c"], sb["e"], sb["v"], strict=True):
        assert stepped_e_n(c, phases=midpoints, v_minus=v) == pytest.approx(e, abs=1e-6)

    # A model file: `contactalpha tune` reads the toy's file and writes its block.
    model = tmp_path / "ball.toy"
    model.write_text(json.dumps({"mass": m, "gravity": SCENE["accel"], "timestep": TIMESTEP}))
    argv = ["tune", str(model), "--pair", "floor", "ball", "--e-n", "0.5", "--speed", "0.5",
            "--engine", "toy", "--stiffness", str(k)]  # fmt: skip
    tuned = run_in(src, ["-m", "contactalpha", *argv])
    assert tuned.returncode == 0, tuned.stderr
    written = json.loads((tmp_path / "ball_tuned.toy").read_text())
    assert written["k"] == k and written["c"] == one["c"]  # m_eff = the ball's mass, the load is g
    # --verify at the step: the toy's own drops (its adapter's run, step by step) at 64 phases,
    # the same drops as stepped here.
    argv = ["params", "--engine", "toy", "--timestep", "1e-3", "--verify", "64"]
    verify = run_in(src, ["-m", "contactalpha", *argv, *(f"--{k}={v}" for k, v in SCENE.items())])
    assert verify.returncode == 0, verify.stderr
    c_step = float(dict(re.findall(r"^toy\.(\w+)\s+(\S+)", verify.stdout, flags=re.M))["c"])
    assert c_step == step["c"]
    measured = re.search(r"verified in toy 1\.0 at 64 phases: mean (\S+)", verify.stdout)
    assert measured, verify.stdout
    assert float(measured.group(1)) == pytest.approx(stepped_e_n(c_step, phases=np.arange(64) / 64), abs=5e-7)


def test_the_continuous_law_of_the_toy_delivers_the_target_at_a_fine_step():
    """The law's zeta (the scalar path's block) delivers e_N 0.5 where the step resolves the contact."""
    import contactalpha as ca

    cp = ca.contact_parameters(
        e_N=0.5, mass=0.5, stiffness=1e3, approach_speed=0.5, accel=9.81, law="kelvin_voigt"
    )
    c = 2.0 * float(cp.damping) * math.sqrt(1e3 * 0.5)
    assert stepped_e_n(c, k=1e3, phases=[0.0, 0.5], h=2e-5) == pytest.approx(0.5, abs=2e-3)


REGISTRATION = 'TOY_MAP = register_map("toy", step_toy)\n'


@pytest.fixture(autouse=True)
def _maps_restored(monkeypatch):
    """The page's module registers its map when run here: this process's map table is restored after."""
    from contactalpha.stepping import kernels

    monkeypatch.setattr(kernels, "MAPS", dict(kernels.MAPS))
    monkeypatch.setattr(kernels, "AFFINE", dict(kernels.AFFINE))


def _toy_module(text=None):
    """The page's toy module (or ``text``), run here (its record's Refs stay unresolved)."""
    from contactalpha.stepping import kernels

    # An earlier run's map (in the fixture's copy of the table) leaves the name free.
    for code in [c for c, m in kernels.MAPS.items() if m.name == "toy"]:
        del kernels.MAPS[code]
    namespace = {"__name__": "toy_from_the_page"}
    text = page_modules()["adapters/toy.py"] if text is None else text
    text = text.replace("cache=True", "cache=False")  # nothing compiles here
    exec(compile(text, str(PAGE), "exec"), namespace)  # noqa: S102
    return namespace


@pytest.mark.parametrize("part", PARTS)
def test_removing_a_part_of_the_toys_record_names_it(part):
    record = _toy_module()["ENGINE"]
    assert check_engine(record) is record
    with pytest.raises(TypeError, match=part):
        Engine(**{p: getattr(record, p) for p in PARTS if p != part})


def test_the_page_registers_the_toys_map_with_a_fresh_code():
    from contactalpha.stepping import kernels

    before = dict(kernels.MAPS)
    toy = _toy_module()
    code = toy["STEPPER"].code
    assert code not in before and kernels.MAPS[code].name == "toy"
    assert kernels.MAPS[code].step is toy["step_toy"]
    assert check_engine(toy["ENGINE"]) is toy["ENGINE"]


@pytest.mark.parametrize(
    ("map_line", "why"),
    [
        (
            "TOY_MAP = EngineMap('toy', 100, step_toy)\n",
            r"100 of 'toy' is not a registered step map.*register_map",
        ),
        ("TOY_MAP = EngineMap('toy', 0, step_toy)\n", r"0 is 'mujoco''s step map, not 'toy''s"),
    ],
    ids=["unregistered", "another-engines-code"],
)
def test_removing_the_toys_map_registration_names_it(map_line, why):
    """Without ``register_map`` the record's step map runs no map, or another engine's: refused."""
    page = page_modules()["adapters/toy.py"]
    assert page.count(REGISTRATION) == 1
    text = page.replace(REGISTRATION, "from contactalpha.stepping.kernels import EngineMap\n" + map_line)
    record = _toy_module(text)["ENGINE"]
    with pytest.raises(TypeError, match="step_map: kernel code " + why):
        check_engine(record)


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
    with pytest.raises(TypeError, match=r"parameters.*numpy arrays"):
        check_adapter(_toy_module(old)["ADAPTER"])
