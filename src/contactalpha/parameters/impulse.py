"""The front door for an impulse engine: the restitution and the threshold to set at its step.

``contact_parameters(..., engine="pybullet_impulse", timestep=h)`` (an adapter with ``impulse``
set) first solves the engine's law as without an engine: the loaded contact whose e_N at the
approach speed is the target (or whose eps is given), its eps, and its critical speed
(``threshold.critical_speed``: below it the contact stops bouncing).  Then, on the engine's step
map (``contactalpha.impulse``):

- the velocity threshold at which half the touchdown phases at the critical speed stop bouncing
  (``impulse.inverse.threshold_for``), so the engine stops where the loaded contact stops;
- with it, the pair restitution whose mean e_N over the touchdown phase is the target, each
  body's share of it (``impulse.inverse.per_body``), and the range one drop sees;
- what the raw coefficient (the target as the pair's restitution, the engine's own threshold)
  delivers there: ``stepped.continuous_mean`` and its range.

The answer is always at a step (the engine has no continuous contact): ``timestep`` None or
"default" is the engine's default step.  Arrays solve row by row.
"""

import math
from dataclasses import replace

import numpy as np

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import ADAPTERS, adapter
from contactalpha.impulse.delivered import ImpulseStats, phase_stats
from contactalpha.impulse.inverse import restitution_for, threshold_for
from contactalpha.impulse.registry import impulse_engine
from contactalpha.scene.threshold import critical_speed
from contactalpha.validation import check_count, check_scalar

from .at_step import DEFAULT_STEP, SteppedAnswer
from .verify import VERIFY_RADIUS, phase_mean_error

# Radius of the sphere when the scene gives none, m (the contact breaking threshold reads it).
DEFAULT_RADIUS = VERIFY_RADIUS
# The statistics of an answer that did not reach the target.
NO_STATS = ImpulseStats(math.nan, math.nan, math.nan, math.nan, (0, 0), math.nan, "unreachable")
_ROW = ("eps", "mass", "stiffness", "approach_speed", "e_N", "accel", "force", "radius")


def is_impulse(engine):
    """True when ``engine`` is a registered impulse engine (its adapter sets ``impulse``)."""
    return engine is not None and getattr(adapter(engine), "impulse", None) is not None


def impulse_engines():
    """The registered impulse engines' names."""
    return tuple(a.name for a in ADAPTERS if getattr(a, "impulse", None) is not None)


def resolve_timestep(engine, timestep):
    """The step in s: ``timestep``, or the engine's default for None and ``"default"``."""
    if timestep is None or (isinstance(timestep, str) and timestep == DEFAULT_STEP):
        return adapter(engine).settings.timestep
    if isinstance(timestep, str):
        raise ValueError(f"timestep = {timestep!r} is neither a step in s nor {DEFAULT_STEP!r}")
    return check_scalar("timestep", timestep, 0.0, math.inf, lo_open=True, hi_open=True)


def impulse_parameters(row, law, engine, timestep, verify, continuous):
    """``ContactParameters`` of ``engine`` at its step for the scene ``row`` (``_ROW``'s values).

    ``continuous`` is the front door without an engine (``parameters.front_door.contact_parameters``):
    the loaded contact the answer stands for.
    """
    values = dict(zip(_ROW, row, strict=True))
    shape = np.broadcast_shapes(*(np.shape(x) for x in row if x is not None))
    if shape:
        if verify is not None:
            raise ValueError("verify takes one scene: give scalars")
        flat = {k: (None if x is None else np.broadcast_to(x, shape).ravel()) for k, x in values.items()}
        rows = [
            _one(
                {k: (None if x is None else x[i]) for k, x in flat.items()},
                law,
                engine,
                timestep,
                None,
                continuous,
            )
            for i in range(int(np.prod(shape)))
        ]
        return _stacked(rows, shape)
    return _one(values, law, engine, timestep, verify, continuous)


def _one(values, law, engine, timestep, verify, contact_parameters):
    a = adapter(engine)
    h = resolve_timestep(engine, timestep)
    radius = DEFAULT_RADIUS
    if values["radius"] is not None:
        radius = check_scalar("radius", values["radius"], 0.0, math.inf, lo_open=True, hi_open=True)
    cp = contact_parameters(values["eps"], values["mass"], values["stiffness"], values["approach_speed"],
                            e_N=values["e_N"], accel=values["accel"], force=values["force"],
                            law=a.law if law is None else law)  # fmt: skip
    if cp.accel <= 0.0:
        raise ValueError(
            "an impulse engine's step needs a load pressing the bodies together: accel or force > 0"
        )
    m, k, v, acc = (
        float(values["mass"]),
        float(values["stiffness"]),
        float(values["approach_speed"]),
        cp.accel,
    )
    target = float(cp.e_n) if values["e_N"] is None else float(values["e_N"])
    law_arg = None if law is None and a.law.name == "hunt_crossley" else (a.law if law is None else law)
    v_crit = float(critical_speed(max(float(cp.eps), 1e-4), m, k, acc, law=law_arg))
    eng = impulse_engine(a.impulse)
    thr = threshold_for(v_crit, h, acc)
    ans = restitution_for(target, h, v, acc, radius, thr, engine=eng.name)
    raw = phase_stats(eng.params(target, radius, eng.threshold), h, v, acc, code=eng.code)
    ok = ans.status == "ok" and ans.stats is not None
    st = ans.stats if ans.stats is not None else NO_STATS
    stepped = SteppedAnswer(
        engine=engine, timestep=h, restitution="kinematic", target=target,
        damping=float(ans.restitution), law_damping=float(cp.damping),
        mean=st.mean if ok else math.nan, minimum=st.minimum if ok else math.nan,
        maximum=st.maximum if ok else math.nan, std=st.std if ok else math.nan,
        steps_min=st.steps[0] if ok else 0, steps_max=st.steps[1] if ok else 0, status=ans.status,
        nearest=float(ans.nearest), timestep_reachable=math.nan,
        continuous_mean=raw.mean, continuous_minimum=raw.minimum, continuous_maximum=raw.maximum,
        mean_error=abs(st.mean - target) if ok else math.nan,
    )  # fmt: skip
    blk = a.block(ans.restitution, thr)
    blk["critical_speed"] = v_crit
    cp = cp.replaced(engines={engine: blk}, engine=engine, stepped=stepped)
    if verify is None:
        return cp
    n = check_count("phases", 128 if verify == DEFAULT_STEP else verify, 1, 100_000)
    if not ok:
        raise ValueError("verify needs a restitution that reached the target")
    scene = DropScene(m, k, v, gravity=acc, force=0.0, radius=radius)
    # the uniform phases give the mean; the range adds the phases where the map puts its ends
    settings = replace(a.settings, timestep=h, phases=n, extra_phases=(st.phase_min, st.phase_max))
    samples = a.run(a.build_drop(scene, blk, settings), scene, settings)
    a.measure(samples, scene)
    e = np.asarray(samples.extra["e_n_phases"], dtype=float)
    measured = {"phases": n, "mean": float(e[:n].mean()), "minimum": float(e.min()),
                "maximum": float(e.max()), "sampling_error": phase_mean_error(e[:n]),
                "seconds": float(samples.seconds), "version": a.version()}  # fmt: skip
    return cp.replaced(stepped=replace(stepped, verify=measured))


def _stacked(rows, shape):
    """One ``ContactParameters`` whose block and stepped numbers are arrays of ``shape``."""
    first = rows[0]

    def stack(get):
        return np.array([get(r) for r in rows]).reshape(shape)

    blk = {key: stack(lambda r, key=key: r.block[key]) for key in first.block}
    fields = ("target", "damping", "law_damping", "mean", "minimum", "maximum", "std", "steps_min",
              "steps_max", "status", "nearest", "continuous_mean", "continuous_minimum",
              "continuous_maximum", "mean_error")  # fmt: skip
    stepped = replace(first.stepped, **{f: stack(lambda r, f=f: getattr(r.stepped, f)) for f in fields})
    return first.replaced(engines={first.engine: blk}, stepped=stepped)


def impulse_lines(cp):
    """Text lines of an impulse engine's answer (``contactalpha params --engine NAME``)."""
    ans, blk = cp.stepped, cp.block
    eng = impulse_engine(adapter(ans.engine).impulse)
    lines = [f"at {ans.engine}'s step {ans.timestep:.6g} s, over a uniformly random touchdown phase "
             "(drops read at the plane):"]  # fmt: skip
    if ans.status == "ok":
        threshold = blk.get("restitutionVelocityThreshold", blk.get("bounce_threshold"))
        lines += [
            f"  restitution {ans.damping:.15g} for the pair, {eng.per_body(ans.damping):.15g} on each body "
            f"(the engine's rule: {eng.combine})",
            f"  velocity threshold {threshold:.6g} m/s: the loaded contact stops bouncing below "
            f"{blk['critical_speed']:.6g} m/s",
            f"  mean e_N      {ans.mean:.15g}   (target {ans.target:.15g})",
            f"  one drop      {ans.minimum:.6g} to {ans.maximum:.6g}   (std {ans.std:.3g}; "
            f"{ans.steps_min}-{ans.steps_max} steps with an impulse)",
        ]
    else:
        lines.append(
            f"  {ans.status}: no restitution delivers it; the nearest mean e_N met is {ans.nearest:.6g}"
        )
    lines.append(
        f"  the target itself as the pair's restitution, at the engine's threshold ({eng.threshold:g} m/s), "
        f"delivers {ans.continuous_mean:.6g} ({ans.continuous_minimum:.6g} to {ans.continuous_maximum:.6g})"
    )
    if ans.verify:
        v = ans.verify
        lines.append(
            f"  verified in {ans.engine} {v['version']} at {v['phases']} phases: mean {v['mean']:.6g} "
            f"(sampling error {v['sampling_error']:.1e}), {v['minimum']:.6g} to {v['maximum']:.6g} "
            f"({v['seconds']:.3g} s)"
        )
    return lines
