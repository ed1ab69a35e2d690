"""The numba warm-up: after it, the calls the workflow's jobs make compile nothing."""

import json
import os
import subprocess
import sys

import pytest

from contactalpha.warmup import ENTRY_POINTS, PARTS, warm_up

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

def misses():
    return sum(sum(v.stats.cache_misses.values()) for _, v in dispatchers())

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


def test_after_the_warm_up_the_jobs_calls_compile_nothing(tmp_path):
    # A private, empty numba cache: the first process compiles, the second must only load.
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "NUMBA_NUM_THREADS": "2"}
    # The warm-up compiles each kernel for one signature: numba compiles a callee again for each
    # literal constant or omitted default argument it is passed, which once tripled the compile.
    warm = DISPATCHERS + (
        "import json\nfrom contactalpha.warmup import warm_up\nwarm_up()\n"
        "print(json.dumps({name: len(d.signatures) for name, d in dispatchers() if len(d.signatures) > 1}))"
    )
    compiled = subprocess.run(
        [sys.executable, "-c", warm], env=env, check=True, timeout=900, capture_output=True, text=True
    )
    assert json.loads(compiled.stdout.strip().splitlines()[-1]) == {}
    done = subprocess.run(
        [sys.executable, "-c", WORKLOAD], env=env, check=True, timeout=900, capture_output=True, text=True
    )
    counts = json.loads(done.stdout.strip().splitlines()[-1])
    assert counts["control"] > 0  # the counter sees a kernel the warm-up left cold
    assert counts["workload"] == 0
