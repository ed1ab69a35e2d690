"""The engines' inputs of a fitted law, each checked at the engine's default step, and their text.

``engine_parameters`` gives, for the engines whose contact law is the fitted law's, the adapter's
block at the first impact.  Two checks decide how a block is offered:

- the stiffness: at an end of its search range (the fit ran into the bound: the data do not fix
  it, and a block there is the bound's, not the contact's), no engine value is offered; with a
  profile interval that reaches a bound (``LawFit.bounded``) or held (the data cannot see it),
  the blocks come with that caveat;
- the step: an engine that steps (MuJoCo, Drake, PyBullet) gets the front door's answer at its
  default step (``contact_parameters(..., engine=, timestep="default")``, ``parameters.at_step``) for
  the first impact's e_N: what the block delivers there over the touchdown phase, and the
  block that delivers the e_N as a phase mean, or "unreachable at this step: use h <= ...".
"""

import math
from dataclasses import replace

from contactalpha.adapters.engine_conventions import opensim_dissipation
from contactalpha.adapters.registry import continuous_adapters
from contactalpha.laws import get_law
from contactalpha.parameters.at_step import DEFAULT_STEP, needs_radius
from contactalpha.parameters.block_scene import BlockScene
from contactalpha.parameters.front_door import LAW, contact_parameters
from contactalpha.parameters.result import block_lines

from .fit import AT_BOUND
from .hypotheses import HYPOTHESES

# The words of the at-step answer that reached its target (``parameters.at_step.SteppedAnswer.status``).
REACHED = "ok"


def stiffness_caveat(fit):
    """``(withheld, caveat)``: why the fit's stiffness is not offered, or why it is offered with care.

    Withheld (True) when the fitted stiffness lies at an end of its search range (within
    ``fit.AT_BOUND`` of it, in its fitting coordinate); a caveat when it is held (the data cannot
    see it) or its profile interval reaches an end of the range.  ``(False, "")`` otherwise.
    """
    prm = next(p for p in HYPOTHESES[fit.law].params if p.name == "stiffness")
    k = fit.values["stiffness"]
    lo, hi = prm.fit_bounds
    x = prm.to_fit(k)
    span = f"{prm.lo:g} to {prm.hi:g} {prm.unit}"
    if min(x - lo, hi - x) <= AT_BOUND * (hi - lo):
        return True, (
            f"engine values withheld: the fitted stiffness {k:.6g} {prm.unit} is at an end of its search "
            f"range ({span}); the data do not fix it, and a block there would be the bound's"
        )
    if "stiffness" in fit.fixed:
        return False, f"the stiffness {k:.6g} {prm.unit} is held, not fitted (the data cannot see it)"
    closed = fit.bounded.get("stiffness")
    interval = fit.intervals.get("stiffness", (math.nan, math.nan))
    if closed is not None and all(math.isfinite(v) for v in interval) and not all(closed):
        ends = [f"{v:.3g}" if c else ("<=" if i == 0 else ">=") + f"{v:.3g}"
                for i, (v, c) in enumerate(zip(interval, closed, strict=True))]  # fmt: skip
        return False, (
            f"stiffness not identified: its {int(100 * fit.level)}% interval [{', '.join(ends)}] {prm.unit} "
            "reaches the end of its search range; the engine values hold for the fitted stiffness only"
        )
    return False, ""


def step_statement(engine, stiffness, setup, approach_speed, e_n, radius, given):
    """What ``engine`` does at its default step for the first impact's ``e_n`` (plain data).

    The front door's answer at the step (``contact_parameters(..., timestep="default")``):
    ``{"timestep", "status", "target", "mean", "minimum", "maximum", "steps", "parameters",
    "continuous_mean", "continuous_minimum", "continuous_maximum", "timestep_reachable",
    "nearest"}``; ``{"status": "not checked", "reason"}`` where the front door cannot answer.
    """
    if given:
        return {"status": "not checked", "reason": f"the front door's step answer takes the default "
                f"{', '.join(given)} only"}  # fmt: skip
    try:
        scene = {"mass": setup.mass, "stiffness": stiffness, "approach_speed": approach_speed}
        scene["accel"] = setup.accel
        # Only a map that reads the geometry takes the radius (the front door refuses an unused one).
        sphere = radius if needs_radius(engine) else None
        cp = contact_parameters(e_N=e_n, **scene, engine=engine, timestep=DEFAULT_STEP, radius=sphere)
    except (ValueError, RuntimeError) as exc:
        return {"status": "not checked", "reason": " ".join(str(exc).split())}
    ans = cp.stepped
    return {
        "timestep": ans.timestep, "status": ans.status, "target": ans.target,
        "mean": ans.mean, "minimum": ans.minimum, "maximum": ans.maximum,
        "steps": [ans.steps_min, ans.steps_max],
        "parameters": cp.engines[engine] if ans.status == REACHED else None,
        "continuous_mean": ans.continuous_mean, "continuous_minimum": ans.continuous_minimum,
        "continuous_maximum": ans.continuous_maximum,
        "timestep_reachable": ans.timestep_reachable, "nearest": ans.nearest,
    }  # fmt: skip


def engine_parameters(fit, setup, radius=None):
    """Inputs of the engines that run the fitted law, at its first impact, in each engine's units.

    Only engines whose contact law is the fitted law's (``hypotheses.Hypothesis.contact_law``:
    OpenSim and Exudyn for the Hunt-Crossley n = 3/2 laws, MuJoCo for ``mujoco_soft_damping``,
    Drake for ``hunt_crossley_linear_damping``, PyBullet for ``kelvin_voigt_damping``) are listed;
    each block is the adapter's own (``adapters.contract.EngineAdapter.parameters``), with the
    fit's given settings (MuJoCo's impedance), and ``at_step`` holds each stepping engine's
    ``step_statement``.  A law whose damping is a constant of the material holds for every
    bounce; the others hold for the first impact's approach speed only.  A stiffness at an end
    of its search range gives no blocks (``status`` says why; ``stiffness_caveat``).
    """
    s = fit.sequence
    law = HYPOTHESES[fit.law]
    v1, e1 = float(s.v_in[0]), float(s.e_n[0])
    if not (s.v_out.size and e1 > 0.0):
        return {"status": "the first contact does not separate: no restitution to convert"}
    withheld, caveat = stiffness_caveat(fit)
    damping, stiffness = law.engine_inputs(fit.values, setup.mass, setup.accel, v1)
    contact_law = get_law(law.contact_law)
    mine = continuous_adapters(contact_law)
    if withheld and mine:
        return {"status": caveat, "withheld": True, "at_approach_speed": v1, "e_n": e1}
    scene = BlockScene(setup.mass, float(stiffness), v1, radius)
    given = {name: fit.values[name] for name in fit.given}
    engines = {a.name: a.parameters(float(damping), scene, **_settings(a, given)) for a in mine}
    changed = [k for k, v in given.items() if v != law.given.get(k)]
    at_step = {
        a.name: step_statement(a.name, float(stiffness), setup, v1, e1, radius, changed)
        for a in mine
        if a.timestep(a.settings) is not None
    }
    out = {
        "at_approach_speed": v1,
        "e_n": e1,
        "contact_law": contact_law.name,
        contact_law.damping: float(damping),
        **given,
        "engines": engines,
        "at_step": at_step,
        "caveat": caveat,
        "note": f"{contact_law.damping} (and the engines' damping) hold for this approach speed; "
        "reset them per impact",
    }
    if law.constant_damping:
        out["note"] = "constant damping: the engines' damping holds for every bounce"
    if not engines:
        out["note"] = f"no engine adapter runs {contact_law.name}; its damping {contact_law.damping} is above"
    if "damping" in fit.values and contact_law.name == LAW:
        d = fit.values["damping"]
        out["opensim_constant_dissipation"] = float(opensim_dissipation(d * v1, v1))
        out["note"] = "constant damping: OpenSim's dissipation holds for every bounce"
    return out


def _settings(adapter, given):
    """``{"settings": ...}`` carrying the fit's given settings into an adapter that has them."""
    mine = {k: v for k, v in given.items() if hasattr(adapter.settings, k)}
    return {"settings": replace(adapter.settings, **mine)} if mine else {}


def engine_lines(eng):
    """Text lines of one law's ``engine_parameters``: blocks, caveat, each at-step statement, note."""
    if "engines" not in eng:
        return [f"    engines: {eng.get('status', '')}"]
    out = [f"    # caution: {eng['caveat']}"] if eng.get("caveat") else []
    for engine, block in eng["engines"].items():
        out += [f"    {line}" for line in block_lines(engine, block)]
        if engine in eng.get("at_step", {}):
            out += [f"    {line}" for line in _step_lines(engine, eng["at_step"][engine])]
    if "opensim_constant_dissipation" in eng:
        out.append(
            f"    {'opensim.dissipation (all bounces)':32s} {eng['opensim_constant_dissipation']:.10g}"
        )
    return out + [f"    # {eng['note']}"]


def _step_lines(engine, st):
    if st["status"] == "not checked":
        return [f"# {engine} at its default step: not checked ({st['reason']})"]
    h, e = st["timestep"], st["target"]
    head = f"# {engine} at its default step {h:.6g} s, over a uniformly random touchdown phase:"
    delivers = (
        f"#   the block above delivers a mean e_N of {st['continuous_mean']:.6g} there "
        f"({st['continuous_minimum']:.6g} to {st['continuous_maximum']:.6g} in one drop; the fit's {e:.6g})"
    )
    if st["status"] != REACHED:
        return [
            head,
            delivers,
            f"#   unreachable at this step: use h <= {st['timestep_reachable']:.3g} s (no damping gives a "
            f"mean e_N of {e:.6g} at {h:.6g} s; the nearest is {st['nearest']:.6g})",
        ]
    lo, hi = st["steps"]
    return [
        head,
        delivers,
        f"#   for a mean e_N of {e:.6g} at this step ({st['minimum']:.6g} to {st['maximum']:.6g} in one "
        f"drop, {lo}-{hi} steps in contact), set:",
        *(f"  {line}" for line in block_lines(engine, st["parameters"])),
    ]
