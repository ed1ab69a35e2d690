"""The work of an answer at the step is bounded (issue 44, S6, S7): the step search, the steps per contact."""

import math
import time

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.stepping import inverse
from contactalpha.stepping.delivered import MAX_CONTACT_STEPS

# Issue 44's unreachable Drake scene at 1 ms: m kg, k N/m, v m/s, push N on top of gravity, target e_N.
DRAKE = dict(mass=0.541, stiffness=2.58e3, approach_speed=0.148, force=25.3 + 0.541 * 9.81, e_N=0.878)


class _Recorder:
    """A stand-in for ``contactalpha.progress.Progress`` that keeps every stage."""

    stages: list = []

    def __init__(self, label):
        self.label = label

    def __call__(self, stage):
        _Recorder.stages.append(stage)

    def close(self):
        pass


def test_an_unreachable_drake_scene_answers_within_ten_cpu_seconds_with_progress(monkeypatch):
    # S6: 19-23 s of CPU on a warm cache (7 minutes on a loaded machine), without a word.
    monkeypatch.setattr(inverse, "Progress", _Recorder)
    _Recorder.stages = []
    clock = time.process_time()
    ans = ca.contact_parameters(**DRAKE, engine="drake", timestep=1e-3).stepped
    assert time.process_time() - clock < 10.0
    assert ans.status == "unreachable"
    if ans.search:  # a slower machine: the search stopped at its budget, and says so
        assert ans.search.startswith(f"the search stopped at its {inverse.SEARCH_CPU_S:g} s CPU budget")
        return
    h = ans.timestep_reachable
    assert 0.0 < h < 1e-3
    assert _Recorder.stages and all(s.startswith("trying step ") for s in _Recorder.stages)
    assert f"trying step {h:.4g}" in _Recorder.stages
    again = ca.contact_parameters(**DRAKE, engine="drake", timestep=h).stepped
    assert again.status == "ok" and again.mean == pytest.approx(0.878, abs=1e-6)


def test_a_search_past_its_budget_says_where_it_stopped(monkeypatch):
    monkeypatch.setattr(inverse, "SEARCH_CPU_S", 0.0)
    ans = ca.contact_parameters(**DRAKE, engine="pybullet", radius=0.05, timestep=1e-3).stepped
    assert ans.status == "unreachable" and math.isnan(ans.timestep_reachable)
    assert ans.search.startswith("the search stopped at its 0 s CPU budget, before step ")


@pytest.mark.parametrize("h", [1e-7, 1e-12])
def test_a_tiny_step_is_refused_naming_its_steps_per_contact(h):
    # S7: MuJoCo at 1e-7 s or 1e-12 s ran past 2 minutes with no message.
    scene = dict(mass=0.5, stiffness=1e4, approach_speed=0.5, accel=9.81, e_N=0.5)
    steps = math.pi * math.sqrt(0.5 / 1e4) / h  # the undamped contact's half period over the step
    for engine in ("mujoco", "drake"):
        with pytest.raises(ValueError, match=f"gives {steps:,.0f} steps per contact") as err:
            ca.contact_parameters(**scene, engine=engine, timestep=h)
        assert f"above the {MAX_CONTACT_STEPS:,} this package solves for" in str(err.value)
        finest = math.pi * math.sqrt(0.5 / 1e4) / MAX_CONTACT_STEPS
        assert f"a step of at least {finest:.3g} s" in str(err.value)
    # A batch: those rows have no answer, with the count in the reason; the others are solved.
    masses = [0.5, 0.5 * (h / 1e-5) ** 2]  # row 1: 2,221 steps per contact
    cp = ca.contact_parameters(**(scene | {"mass": masses}), engine="mujoco", timestep=h)
    assert not cp.ok[0] and f"gives {steps:,.0f} steps per contact" in cp.reason[0]
    assert cp.ok[1] and cp.stepped.mean[1] == pytest.approx(0.5, abs=1e-6)


def test_a_soft_scene_of_35000_steps_per_contact_at_the_default_step_is_refused():
    k = 1.0 * (math.pi / (35_000 * 0.002)) ** 2  # N/m for 1 kg: 35,000 steps of 2 ms per contact
    with pytest.raises(ValueError, match="gives 35,000 steps per contact"):
        ca.contact_parameters(mass=1.0, stiffness=k, approach_speed=0.5, accel=1e-5, e_N=0.5, engine="mujoco",
                              timestep="default")  # fmt: skip


def test_the_search_never_tries_a_step_past_the_bound(monkeypatch):
    # A search that would scan below MAX_CONTACT_STEPS steps per contact stops there, saying so.
    monkeypatch.setattr(inverse, "MAX_CONTACT_STEPS", 200)
    tried = []
    real = inverse._reaches

    def spy(engine, p, h, *rest):
        tried.append(inverse.contact_steps(inverse.stepper(engine), p, h))
        return False  # nothing reaches: the scan runs to the bound

    monkeypatch.setattr(inverse, "_reaches", spy)
    p = inverse.stepper("mujoco").pack(stiffness=1e6, damping=0.0, impedance=0.9)
    search = inverse.Search("test")
    with search:
        assert math.isnan(inverse.reachable_timestep("mujoco", p, 0.002, 0.5, 9.81, 0.9, search=search))
    assert max(tried) <= 200 and search.note.endswith("would be over 200 steps per contact")
    assert real is not spy and np.all(np.diff(tried) > 0)
