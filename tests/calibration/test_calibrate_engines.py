"""Engine blocks of a calibration: each at its engine's default step; a stiffness at its bound withheld.

Issue 44, S5 and S16: calibrate printed MuJoCo's continuous solref with no word on its 2 ms step,
a solref at the stiffness's search bound, and engine values of an unidentified stiffness without a
caveat; hypotheses within 2 in AIC were printed as a choice.
"""

import json
import math
from dataclasses import replace

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.adapters.registry import ENGINES
from contactalpha.calibration import hypotheses, sequence
from contactalpha.calibration.api import engine_parameters, format_calibration

M, G, V0 = 0.05, 9.81, 2.0


def _calibrated(name, values, **kw):
    t = sequence.simulate(hypotheses.HYPOTHESES[name], values, M, G, V0, 0.0, 12).touchdowns
    return ca.calibrate(t, kind="times", mass=M, radius=0.02, hypotheses=[name], intervals=False, **kw)


@pytest.fixture(scope="module")
def mujoco_cal():
    return _calibrated("mujoco_soft_damping", {"damping": 20.0, "stiffness": 1e5})


def test_mujoco_block_carries_its_answer_at_the_2_ms_step(mujoco_cal):
    eng = mujoco_cal.engines["mujoco_soft_damping"]
    st = eng["at_step"]["mujoco"]
    e1 = eng["e_n"]
    assert st["timestep"] == 0.002 and st["status"] == "ok" and st["target"] == e1
    # The front door's answer at the step for the first impact's e_N, reused, not recomputed.
    cp = ca.contact_parameters(e_N=e1, mass=M, stiffness=1e5 * M, approach_speed=eng["at_approach_speed"],
                               accel=G, engine="mujoco", timestep="default")  # fmt: skip
    assert st["mean"] == pytest.approx(cp.stepped.mean, abs=1e-12) and abs(st["mean"] - e1) < 1e-6
    assert st["parameters"]["solref"] == pytest.approx(cp.block["solref"], rel=1e-9)
    # "The block above" is the front door's continuous block for e1: the delivery stated is its own.
    scene = {"mass": M, "stiffness": 1e5 * M, "approach_speed": eng["at_approach_speed"], "accel": G}
    continuous = ca.contact_parameters(e_N=e1, **scene, engine="mujoco").block
    assert continuous["solref"] == pytest.approx(eng["engines"]["mujoco"]["solref"], rel=1e-6)
    # At 2 ms (4-5 steps in contact) the continuous solref is not the step's: its phase mean is off.
    assert st["parameters"]["solref"][1] != pytest.approx(eng["engines"]["mujoco"]["solref"][1], rel=1e-3)
    assert abs(st["continuous_mean"] - e1) > 1e-3
    report = json.loads(mujoco_cal.to_json())["laws"]["mujoco_soft_damping"]["engines"]["at_step"]["mujoco"]
    assert report["mean"] == st["mean"] and report["timestep_reachable"] is None  # NaN: not searched
    text = format_calibration(mujoco_cal)
    assert "# mujoco at its default step 0.002 s, over a uniformly random touchdown phase:" in text
    assert f"the block above delivers a mean e_N of {st['continuous_mean']:.6g} there" in text
    assert f"mujoco.solref                    {st['parameters']['solref'][0]:.15g}" in text


def test_a_given_impedance_is_not_checked_at_the_step_by_the_default_one():
    cal = _calibrated(
        "mujoco_soft_damping", {"damping": 20.0, "stiffness": 1e5, "impedance": 0.5}, impedance=0.5
    )
    st = cal.engines["mujoco_soft_damping"]["at_step"]["mujoco"]
    assert st == {
        "status": "not checked",
        "reason": "the front door's step answer takes the default impedance only",
    }
    assert "# mujoco at its default step: not checked (the front door's step answer takes the default" in (
        format_calibration(cal)
    )


def test_an_unreachable_step_names_the_step_that_reaches_it():
    cal = _calibrated("kelvin_voigt_damping", {"damping": 2.0, "stiffness": 1e7})
    st = cal.engines["kelvin_voigt_damping"]["at_step"]["pybullet"]
    assert st["status"] == "unreachable" and st["parameters"] is None
    assert 0.0 < st["timestep_reachable"] < st["timestep"] == pytest.approx(1 / 240)
    assert abs(st["nearest"] - st["target"]) > 0.1
    text = format_calibration(cal)
    assert f"unreachable at this step: use h <= {st['timestep_reachable']:.3g} s" in text


def test_a_stiffness_at_its_search_bound_is_not_offered(mujoco_cal):
    fit = mujoco_cal.fits["mujoco_soft_damping"]
    hi = next(p for p in hypotheses.HYPOTHESES[fit.law].params if p.name == "stiffness").hi
    at_bound = replace(fit, values={**fit.values, "stiffness": hi})
    eng = engine_parameters(at_bound, mujoco_cal.setup, mujoco_cal.radius)
    assert "engines" not in eng and eng["withheld"] is True
    assert f"fitted stiffness {hi:.6g} 1/s^2 is at an end of its search range" in eng["status"]
    cal = replace(mujoco_cal, fits={fit.law: at_bound}, engines={fit.law: eng})
    text = format_calibration(cal)
    assert "engine values withheld" in text and "mujoco." not in text


def test_an_unidentified_stiffness_comes_with_a_caveat(mujoco_cal):
    fit = mujoco_cal.fits["mujoco_soft_damping"]
    open_above = replace(fit, intervals={**fit.intervals, "stiffness": (2.5e3, 1e11)},
                         bounded={**fit.bounded, "stiffness": (True, False)})  # fmt: skip
    eng = engine_parameters(open_above, mujoco_cal.setup, mujoco_cal.radius)
    assert eng["caveat"].startswith("stiffness not identified: its 95% interval [2.5e+03, >=1e+11] 1/s^2")
    cal = replace(mujoco_cal, fits={fit.law: open_above}, engines={fit.law: eng})
    lines = format_calibration(cal).splitlines()
    first = next(i for i, line in enumerate(lines) if line.strip().startswith("mujoco."))
    assert lines[first - 1].strip().startswith("# caution: stiffness not identified")
    assert engine_parameters(fit, mujoco_cal.setup, mujoco_cal.radius)["caveat"] == ""


def test_hypotheses_within_2_in_aic_are_a_tie():
    # Ping-pong impact times (2.7 g, e 0.9, 0.1 ms timing noise): the load barely shows in a contact.
    t = sequence.simulate(hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.9, "stiffness": 1e6}, 0.0027, G, 2.4,
                          0.0, 12).touchdowns  # fmt: skip
    t = t + np.random.default_rng(1).normal(0.0, 1e-4, t.size)
    cal = ca.calibrate(t, kind="times", mass=0.0027, hypotheses=["hc_eps", "constant_e"], intervals=False)
    a, b = (cal.fits[n] for n in ("hc_eps", "constant_e"))
    # AIC from its definition, n log(RSS / n) + 2 (p + 1), with the residuals' own RSS.
    aic = [f.n * math.log(float(f.residuals @ f.residuals) / f.n) + 2 * (f.p + 1) for f in (a, b)]
    assert aic == pytest.approx([a.aic, b.aic], abs=1e-9) and abs(aic[0] - aic[1]) < 2.0
    assert cal.tied == ["hc_eps", "constant_e"]
    text = format_calibration(cal)
    assert "\n= hc_eps " in text and "\n= constant_e " in text and "\n* " not in text
    last = text.splitlines()[-1]
    assert last.startswith("selected: none, a tie: hc_eps, constant_e are within 2 of the lowest AIC")
    assert cal.to_dict()["tied"] == ["hc_eps", "constant_e"]


@pytest.mark.integration
def test_the_step_block_delivers_its_mean_in_mujoco(mujoco_cal):
    eng = mujoco_cal.engines["mujoco_soft_damping"]
    st = eng["at_step"]["mujoco"]
    scene = {"mass": M, "stiffness": 1e5 * M, "approach_speed": eng["at_approach_speed"], "accel": G}
    cp = ca.contact_parameters(e_N=eng["e_n"], **scene, engine="mujoco", timestep="default", verify=512)
    measured = cp.stepped.verify
    assert cp.block["solref"] == pytest.approx(st["parameters"]["solref"], rel=1e-9)
    assert measured["mean"] == pytest.approx(st["mean"], abs=2e-3)
    assert st["minimum"] - 1e-3 <= measured["minimum"] and measured["maximum"] <= st["maximum"] + 1e-3


def test_a_held_stiffness_comes_with_a_caveat():
    # Apex heights cannot see constant_e's stiffness: it is held (at 1e8 N/m^1.5 when none is given).
    h = V0**2 / (2 * G) * 0.8 ** (2 * np.arange(8))
    cal = ca.calibrate(h, kind="heights", mass=M, radius=0.02, hypotheses=["constant_e"], intervals=False)
    eng = cal.engines["constant_e"]
    # the registry's, not pinned; an impulse engine has no continuous block
    hunt_crossley = {
        e.name
        for e in ENGINES
        if e.law.name == "hunt_crossley" and getattr(e.adapter, "impulse", None) is None
    }
    assert cal.fits["constant_e"].fixed == ("stiffness",) and set(eng["engines"]) == hunt_crossley
    assert eng["caveat"] == "the stiffness 1e+08 N/m^1.5 is held, not fitted (the data cannot see it)"
    assert f"# caution: {eng['caveat']}" in format_calibration(cal)
