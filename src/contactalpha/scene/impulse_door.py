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
from contactalpha.adapters.registry import adapter
from contactalpha.engine.codes import OUT_STATE, OUT_T_END, OUT_V_END, SEPARATION
from contactalpha.engine.driver import ATOL, RTOL
from contactalpha.engine.table import XI_MAX
from contactalpha.impulse import bullet_map
from contactalpha.impulse.delivered import phase_stats
from contactalpha.impulse.inverse import restitution_for, threshold_for
from contactalpha.impulse.schedule import TouchdownSchedule
from contactalpha.validation import check_count, check_scalar

from .ball import Scene, contact_alpha, run_contact
from .stepped import DEFAULT_STEP, VERIFY_RADIUS, SteppedAnswer, phase_mean_error
from .threshold import critical_speed

# Radius of the sphere when the scene gives none, m (the contact breaking threshold reads it).
DEFAULT_RADIUS = VERIFY_RADIUS
# The schedule's table: speeds, and how far above the approach speed it reaches.
SCHEDULE_POINTS = 64
SCHEDULE_HEADROOM = 1.05
_ROW = ("eps", "mass", "stiffness", "approach_speed", "e_N", "accel", "force", "radius")


def is_impulse(engine):
    """True when ``engine`` is a registered impulse engine (its adapter sets ``impulse``)."""
    return engine is not None and getattr(adapter(engine), "impulse", None) is not None


def _impulse_engines():
    from contactalpha.adapters.registry import ADAPTERS

    return tuple(a.name for a in ADAPTERS if getattr(a, "impulse", None) is not None)


def resolve_timestep(engine, timestep):
    """The step in s: ``timestep``, or the engine's default for None and ``"default"``."""
    if timestep is None or (isinstance(timestep, str) and timestep == DEFAULT_STEP):
        return adapter(engine).settings.timestep
    if isinstance(timestep, str):
        raise ValueError(f"timestep = {timestep!r} is neither a step in s nor {DEFAULT_STEP!r}")
    return check_scalar("timestep", timestep, 0.0, math.inf, lo_open=True, hi_open=True)


def impulse_parameters(row, law, engine, timestep, verify):
    """``ContactParameters`` of ``engine`` at its step for the scene ``row`` (``_ROW``'s values)."""
    values = dict(zip(_ROW, row, strict=True))
    shape = np.broadcast_shapes(*(np.shape(x) for x in row if x is not None))
    if shape:
        if verify is not None:
            raise ValueError("verify takes one scene: give scalars")
        flat = {k: (None if x is None else np.broadcast_to(x, shape).ravel()) for k, x in values.items()}
        rows = [
            _one({k: (None if x is None else x[i]) for k, x in flat.items()}, law, engine, timestep, None)
            for i in range(int(np.prod(shape)))
        ]
        return _stacked(rows, shape)
    return _one(values, law, engine, timestep, verify)


def _one(values, law, engine, timestep, verify):
    from .parameters import contact_parameters  # the continuous answer (the front door imports this module)

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
    thr = threshold_for(v_crit, h, acc)
    ans = restitution_for(target, h, v, acc, radius, thr)
    raw = phase_stats(bullet_map.make_params(target, radius), h, v, acc)
    ok = ans.status == "ok"
    st = ans.stats
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
    from contactalpha.adapters.pybullet_impulse import block  # the engine's block (one home)

    blk = block(ans.restitution, thr)
    blk["critical_speed"] = v_crit
    cp = cp.replaced(engines={engine: blk}, engine=engine, stepped=stepped)
    if verify is None:
        return cp
    n = check_count("phases", 128 if verify == DEFAULT_STEP else verify, 1, 100_000)
    if not ok:
        raise ValueError("verify needs a restitution that reached the target")
    scene = DropScene(m, k, v, gravity=acc, force=0.0, radius=radius)
    settings = replace(a.settings, timestep=h, phases=n)
    samples = a.run(a.build_drop(scene, blk, settings), scene, settings)
    a.measure(samples, scene)
    e = np.asarray(samples.extra["e_n_phases"], dtype=float)
    measured = {"phases": n, "mean": float(e.mean()), "minimum": float(e.min()), "maximum": float(e.max()),
                "sampling_error": phase_mean_error(e), "seconds": float(samples.seconds),
                "version": a.version()}  # fmt: skip
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


def touchdown_schedule(
    mass, stiffness, approach_speed, *, eps=None, e_N=None, accel=None, force=None,  # noqa: N803
    radius=None, engine="pybullet_impulse", timestep=None, points=SCHEDULE_POINTS,
):  # fmt: skip
    """The loaded contact per approach speed, for a restitution set each step (``impulse.schedule``).

    The contact is the default law's (Hunt-Crossley, n = 3/2; ``stiffness`` in N/m^1.5) with the
    material's ``eps``, or the one whose e_N at ``approach_speed`` is ``e_N``, under the load
    ``accel`` (or ``force``); the table runs from its critical speed to ``approach_speed``
    (``points`` speeds, log spaced), each with the e_N and the contact duration that
    ``scene.bounces.predict_bounces`` takes for a contact at that speed.

    Returns
    -------
    impulse.schedule.TouchdownSchedule
        At ``engine``'s step ``timestep`` (None or "default": its default); drive it with
        ``impulse.schedule.Rebounder`` before every step.
    """
    from .parameters import contact_parameters

    if not is_impulse(engine):
        raise ValueError(f"engine = {engine!r} is not an impulse engine; valid: {_impulse_engines()}")
    h = resolve_timestep(engine, timestep)
    points = check_count("points", points, 2, 10_000)
    cp = contact_parameters(eps, mass, stiffness, approach_speed, e_N=e_N, accel=accel, force=force)
    m, k, v = float(mass), float(stiffness), float(approach_speed)
    r = DEFAULT_RADIUS if radius is None else check_scalar("radius", radius, 0.0, math.inf, lo_open=True)
    e = float(cp.eps)
    critical = float(critical_speed(e, m, k, cp.accel))
    sc = Scene(mass=m, radius=r, stiffness=k, approach_speed=v, force=0.0, eps=e, gravity=cp.accel)
    speeds = np.geomspace(critical * (1.0 + 1e-9), v * SCHEDULE_HEADROOM, points)
    e_n, durations = np.empty(points), np.empty(points)
    for i, speed in enumerate(speeds):
        name = "exact" if sc.influence(speed) <= XI_MAX else "exact_solve"
        _, out, _, _, ts = run_contact(
            sc, speed, contact_alpha(sc, speed, name, "A"), "A", RTOL, ATOL, np.inf
        )
        e_n[i] = -out[OUT_V_END] if int(out[OUT_STATE]) == SEPARATION else 0.0
        durations[i] = out[OUT_T_END] * ts
    return TouchdownSchedule(speeds, e_n, durations, critical, float(cp.accel), h, r)
