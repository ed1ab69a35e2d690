"""The numba warm-up: after it, the calls the workflow's jobs make compile nothing."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from contactalpha.warmup import ENTRY_POINTS, PARTS, warm_up

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[1]

# Calls of the kind the jobs make, with other sizes and arguments than the warm-up's own; then the
# cache misses of every package kernel are counted. The RK4 baseline is not warmed (no default
# job runs it): calling it must miss, which shows the counter sees a compile.
DISPATCHERS = """
import importlib, pkgutil
from numba.core.registry import CPUDispatcher

def dispatchers():
    for pkg in ("engine", "models", "scene", "baselines"):
        p = importlib.import_module("contactalpha." + pkg)
        for info in pkgutil.iter_modules(p.__path__):
            mod = importlib.import_module(f"contactalpha.{pkg}.{info.name}")
            for name, v in vars(mod).items():
                if isinstance(v, CPUDispatcher) and v.__module__ == mod.__name__:
                    yield f"{mod.__name__}.{name}", v

def misses():
    return sum(sum(v.stats.cache_misses.values()) for _, v in dispatchers())
"""

WORKLOAD = (
    DISPATCHERS
    + """
import json
import numpy as np
import contactalpha as ca
from contactalpha.engine import driver, table
from contactalpha.models import shen
from contactalpha.scene import ball, threshold

ca.impact(np.linspace(0.5, 3.0, 1000), 0.3)
ca.impact(2.0, 0.0)
ca.solve_alpha(np.linspace(0.1, 0.9, 40), 0.05)
ca.solve_alpha(0.3, 0.7, restitution="kinematic")
ca.alpha(np.linspace(0.1, 0.9, 5000), 0.4, model="exact")
ca.alpha(np.linspace(0.1, 0.9, 5000), 0.4, model="exact", restitution="kinematic")
for name in ("hunt_crossley", "shen_published", "closed_form", "exact_unloaded"):
    ca.alpha(np.linspace(0.1, 0.9, 7), 0.1, model=name)
shen.eq40_gradient(np.linspace(0.1, 0.9, 9), 0.3, reading="beta_a0")
driver.trajectory(0.7, 0.5, max_step=0.1)
threshold.critical_speed(np.array([0.2, 0.7]), 1.0, 1e9, 1.0)
ball.simulate(ball.Scene(t_end=0.005, force=60.0), "shen_published", case="B")

after_workload = misses()
from contactalpha.baselines import fixedstep
fixedstep.acceleration(0.1, 0.0, 0.2, 1.0)
print(json.dumps({"workload": after_workload, "control": misses() - after_workload}))
"""
)


def test_unknown_entry_point_is_named():
    with pytest.raises(ValueError, match=r"unknown warm-up entry points \['kernels'\]; valid: .*impact"):
        warm_up(["kernels"])


def test_warm_up_times_every_entry_point_it_was_asked_for():
    calls = []
    seconds = warm_up(["scaling", "models"], progress=lambda name, s: calls.append(name))
    assert list(seconds) == ["scaling", "models"] == calls
    assert all(s >= 0.0 for s in seconds.values())
    assert set(ENTRY_POINTS) >= {"impact", "solver", "tables", "models", "boundary", "scene"}


def test_the_workflows_two_parts_warm_every_entry_point_once():
    names = [name for part in PARTS.values() for name in part]
    assert sorted(names) == sorted(ENTRY_POINTS)


# The calls of the jobs that wait only for the warm-up's "models" part (workflow/rules/warmup.smk:
# the ball's two simulation jobs and the bounce thresholds), on the default config's settings but
# shorter: then a kernel of part "engine", which must still miss.
MODELS_PART_WORKLOAD = (
    DISPATCHERS
    + f"""
import dataclasses, json, yaml
import numpy as np
from contactalpha.engine import driver
from contactalpha.paper.ball.study import default_scene, run_cases, run_first_collision
from contactalpha.studies.adequacy.report import scene_thresholds

config = yaml.safe_load(open({str(ROOT / "config.yaml")!r}))
ball, numerics = config["ball"], {{"rtol": 1e-10, "atol": 1e-12, "max_step": 0.02}}
scene = default_scene(ball["scene"])
short = dataclasses.replace(scene, eps=0.8, force=5.1, t_end=0.05)
run_cases(short, ball["new_model"], ball["cases"]["variants"], **numerics)
first = ball["first_collision"]
run_first_collision(
    scene, [60.0], [0.5], first["classical"], ball["new_model"], first["reference"],
    formulas=first["formulas"], **numerics,
)
scene_thresholds([dict(s) for s in config["adequacy"]["scenes"]])

after_workload = misses()
driver.impact(np.array([1.0, 2.0]), 0.2)  # the array path: driver.impact_rows
print(json.dumps({{"workload": after_workload, "control": misses() - after_workload}}))
"""
)


def _run_json(code, env):
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, check=True, timeout=900, capture_output=True, text=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_after_the_warm_up_the_jobs_calls_compile_nothing(tmp_path):
    # A private, empty numba cache: the warm-up's processes compile, the others must only load.
    # Its two parts run one after the other, as the workflow's jobs, which may start after one.
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "NUMBA_NUM_THREADS": "2"}

    # The warm-up compiles each kernel for one signature: numba compiles a callee again for each
    # literal constant or omitted default argument it is passed, which once tripled the compile.
    def warm(part):
        return DISPATCHERS + (
            f"import json\nfrom contactalpha.warmup import PARTS, warm_up\nwarm_up(PARTS[{part!r}])\n"
            "print(json.dumps({n: len(d.signatures) for n, d in dispatchers() if len(d.signatures) > 1}))"
        )

    assert _run_json(warm("models"), env) == {}
    counts = _run_json(MODELS_PART_WORKLOAD, env)
    assert counts["control"] > 0  # the counter sees a kernel of the other part
    assert counts["workload"] == 0
    assert _run_json(warm("engine"), env) == {}
    counts = _run_json(WORKLOAD, env)
    assert counts["control"] > 0  # the counter sees a kernel the warm-up left cold
    assert counts["workload"] == 0


# Every stepping kernel: the templates' per-engine copies (``stepping.kernels.for_engine``).
STEPPING = """
import json
import numpy as np
from contactalpha.stepping import kernels

def copies():
    # Only the copies: a function that names no map is its own "copy" for every engine.
    return {d for (template, _), d in kernels._COPIES.items() if d is not template}

def compiled():
    return sorted({d.py_func.__qualname__ for d in copies() if d.signatures})

def misses():
    return sum(sum(d.stats.cache_misses.values()) for d in copies())
"""
BATCH_AT_MUJOCOS_STEP = """
import contactalpha as ca
rng = np.random.default_rng(1)
m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), 100))
v, e = rng.uniform(0.3, 3, 100), rng.uniform(0.1, 0.95, 100)
ca.contact_parameters(mass=m, stiffness=m * rng.uniform(1e3, 1e5, 100), approach_speed=v, accel=9.81, e_N=e,
                      engine="mujoco", timestep=0.002)
"""


def test_a_batch_at_mujocos_step_compiles_mujocos_kernels_only_saying_so(tmp_path):
    """On an empty cache the batch compiles its own path's copies for MuJoCo, each compile announced
    on stderr as it starts, and none of another engine's."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    code = STEPPING + BATCH_AT_MUJOCOS_STEP + "print(json.dumps(compiled()))"
    done = subprocess.run([sys.executable, "-c", code], env=env, check=True, timeout=900, capture_output=True,
                          text=True)  # fmt: skip
    names = json.loads(done.stdout.strip().splitlines()[-1])
    assert "rows_kernel__mujoco" in names
    assert all(name.endswith("__mujoco") for name in names), names
    assert "contactalpha:   compiling rows_kernel__mujoco ..." in done.stderr


def test_after_the_stepping_warm_up_every_engines_paths_compile_nothing(tmp_path):
    """``warm_up(["stepping"])`` covers every engine's paths: a fresh process then only loads them."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    warm = (
        STEPPING
        + "from contactalpha.warmup import warm_up\nwarm_up(['stepping'])\nprint(json.dumps(compiled()))"
    )
    warmed = _run_json(warm, env)
    assert {name.rsplit("__", 1)[1] for name in warmed} == {"mujoco", "pybullet", "drake"}
    workload = (
        STEPPING
        + BATCH_AT_MUJOCOS_STEP
        + """
from contactalpha.stepping.delivered import at_phases, over_phase
from contactalpha.stepping.inverse import damping_for
from contactalpha.stepping.registry import STEPPERS
from contactalpha.warmup import _WARM_PARAMS
for s in STEPPERS:
    p = s.pack(**_WARM_PARAMS[s.name])
    over_phase(s.name, p, s.timestep, 0.7, 9.81)
    at_phases(s.name, p, s.timestep, np.array([0.1, 0.2, 0.3]), 0.7, 9.81)
    damping_for(s.name, p, s.timestep, 0.7, 9.81, 0.4)
    s.drop(p, s.timestep, 0.5, 0.7, 9.81, 500)
print(json.dumps({"misses": misses(), "compiled": len(compiled())}))
"""
    )
    counts = _run_json(workload, env)
    assert counts["compiled"] > 0 and counts["misses"] == 0
