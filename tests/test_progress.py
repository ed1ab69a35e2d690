"""Long work says what it does on stderr after a while; short work and --quiet say nothing."""

import io
import time

from contactalpha.progress import Progress


def test_short_work_prints_nothing():
    out = io.StringIO()
    with Progress("job", after=60.0, stream=out) as progress:
        progress("stage 1")
        progress("stage 2")
    assert out.getvalue() == ""


def test_long_work_prints_the_current_stage_then_each_new_one():
    out = io.StringIO()
    with Progress("job", after=0.05, stream=out) as progress:
        progress("stage 1")
        deadline = time.monotonic() + 30.0
        while "stage 1" not in out.getvalue() and time.monotonic() < deadline:
            time.sleep(0.01)
        progress("stage 2")
    progress("after the end")
    lines = out.getvalue().splitlines()
    assert [line.split(" (")[0] for line in lines] == ["job: stage 1", "job: stage 2"]
    assert all(line.endswith(" s)") for line in lines)


def test_calibrate_tells_each_drop():
    from contactalpha.adapters.base import Adapter, Delivered
    from contactalpha.laws import get_law

    class Linear(Adapter):  # a fake engine: e_N = 0.9 - damping / 10
        name, law, settings = "linear", get_law("kelvin_voigt"), None

        def parameters(self, damping, scene, settings=None):
            return {"damping": damping}

        def delivered(self, scene, damping, settings=None):
            return Delivered(0.9 - damping / 10.0, 0.0, None, True)

    stages = []
    params, ref, _ = Linear().calibrate(None, 0.8, start=0.5, progress=stages.append)
    assert stages[0] == "linear drop 1, zeta = 0.5"
    assert len(stages) == ref.iterations + 1  # the start, then every secant step
