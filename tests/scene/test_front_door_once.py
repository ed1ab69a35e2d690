"""The front door solves each call once: no call back into itself, no block of an engine not asked for.

``contact_parameters`` checks the call and picks one path (``parameters.front_door``); the answer
at an engine's step carries the continuous answer to the step without asking the front door again,
and a call for one engine builds that engine's block only (not every engine of its law, then
dropped).  The answers themselves are checked against independent paths in the other tests here.
"""

import numpy as np
import pytest

from contactalpha.adapters.registry import ADAPTERS, adapter
from contactalpha.parameters import front_door

SCENE = dict(mass=0.5, stiffness=2e4, approach_speed=0.5, accel=9.81)
BATCH = dict(SCENE, mass=np.array([0.4, 0.5, 0.6]))


@pytest.fixture
def front_door_calls(monkeypatch):
    """The number of calls of ``contact_parameters`` by its module-level name (the way it recursed)."""
    calls = []
    real = front_door.contact_parameters

    def counting(*args, **kwargs):
        calls.append(kwargs.get("timestep"))
        return real(*args, **kwargs)

    monkeypatch.setattr(front_door, "contact_parameters", counting)
    return counting, calls


@pytest.mark.parametrize("scene", [SCENE, BATCH], ids=["scalar", "batch"])
@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_the_answer_at_the_step_does_not_call_the_front_door_again(front_door_calls, scene, engine):
    call, calls = front_door_calls
    radius = {"radius": 0.05} if engine == "pybullet" else {}
    cp = call(**scene, e_N=0.5, engine=engine, timestep=0.001, **radius)
    assert calls == [0.001]
    assert np.all(cp.stepped.status == "ok") and np.allclose(cp.stepped.mean, 0.5, atol=1e-6)


@pytest.mark.parametrize("scene", [SCENE, BATCH], ids=["scalar", "batch"])
def test_one_engine_asked_builds_that_engines_block_only(monkeypatch, scene):
    """OpenSim and Exudyn share Hunt-Crossley's law: asking for OpenSim builds no Exudyn block."""
    assert {a.name for a in ADAPTERS if a.law.name == adapter("opensim").law.name} >= {"opensim", "exudyn"}
    built = []
    cls = type(adapter("exudyn"))
    real = cls.parameters

    def counting(self, *args, **kwargs):
        built.append(self.name)
        return real(self, *args, **kwargs)

    monkeypatch.setattr(cls, "parameters", counting)
    cp = front_door.contact_parameters(**scene, e_N=0.5, engine="opensim", radius=0.05)
    assert built == [] and list(cp.engines) == ["opensim"]
    every = front_door.contact_parameters(**scene, e_N=0.5, radius=0.05)
    assert built == ["exudyn"] and set(every.engines) >= {"opensim", "exudyn"}
    np.testing.assert_array_equal(cp.block["dissipation"], every.engines["opensim"]["dissipation"])


def test_the_few_steps_warning_names_the_callers_line():
    """A batch at a coarse step warns of worlds with few contact steps at the caller's line."""
    from contactalpha.adapters.stepped import ContactStepsWarning

    with pytest.warns(ContactStepsWarning, match="fewer than") as record:
        cp = front_door.contact_parameters(**BATCH, e_N=0.5, engine="mujoco", timestep=0.004)
    assert [w.filename for w in record if w.category is ContactStepsWarning] == [__file__]
    assert np.all(cp.stepped.steps_min < 5)
