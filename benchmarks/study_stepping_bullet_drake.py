"""Study of issue 33 for PyBullet (1/240 s) and Drake's discrete plant (1 ms): the inverse at the step.

The inverse runs at the engine's step and is checked in the engines themselves.

Run: PYTHONPATH=src nice -n 10 python benchmarks/study_stepping_bullet_drake.py [PHASES] [OUT.json]

For each engine, 13 scenes (mass 0.02-20 kg, approach speed 0.05-3 m/s, pushes up to 100 N,
targets e_N 0.1-0.95; the stiffness makes the undamped contact span a chosen number of the
engine's default steps; one scene within 20 % of its critical speed):

1. ``stepping.inverse.damping_for`` gives the engine's own damping (PyBullet: ``contactDamping``;
   Drake: ``hunt_crossley_dissipation``; the same value on both bodies, each at twice the pair's
   stiffness; a 0.05 m sphere) whose phase-mean e_N is the target at the default step, with the
   predicted minimum and maximum over the phase;
2. the installed engine drops the ball at PHASES touchdown phases i/PHASES with those values
   (the adapters' own drop scenes), and e_N is read from its states by
   ``adapters.stepped.measure_steps``;
3. a scene out of reach at the default step is solved again at the step the package proposes
   (``timestep_reachable``) and at the stiffness it proposes (``stiffness_reachable``), and each
   is checked in the engine the same way.

Three more scenes per engine under a heavy load (``HEAVY``: a h / v from 0.25 to 1, where a body
can hop for less than a step) print the measured exit-speed mean (the parabola through the first
sample above the surface) beside the target.

Reported per scene: the measured mean minus the target (done when within 1e-3), measured minimum
and maximum minus the predicted ones (done when within 2e-3), the largest |engine - map| over the
same phases, the critical-speed ratio, and the engine's cost of the check (``--verify``) per
scene and per drop.  The mean over PHASES equispaced phases is itself a rectangle rule of a
function that jumps: it differs from the exact phase mean by up to about jump/PHASES; the
column ``sampled - exact`` gives that part, computed by the map at the same phases.
"""

import math
import sys
import time
import warnings

import numpy as np

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.stepped import measure_steps
from contactalpha.stepping import drake_map, pybullet_map
from contactalpha.stepping.delivered import at_phases, over_phase
from contactalpha.stepping.inverse import damping_for
from contactalpha.stepping.registry import stepper

G = 9.81
# (mass kg, approach speed m/s, push N, target e_N, undamped contact length in default steps)
SCENES = [
    (0.5, 1.0, 0.0, 0.5, 30),
    (0.02, 3.0, 0.0, 0.3, 20),
    (20.0, 0.5, 100.0, 0.4, 40),
    (1.0, 1.5, 10.0, 0.6, 30),
    (0.1, 2.0, 0.5, 0.7, 40),
    (5.0, 1.0, 50.0, 0.2, 25),
    (0.05, 0.5, 0.05, 0.8, 40),
    (2.0, 2.5, 0.0, 0.95, 30),
    (0.3, 1.2, 5.0, 0.35, 15),
    (10.0, 0.05, 0.0, 0.1, 20),
    (10.0, 2.0, 100.0, 0.5, 30),
    (0.2, 0.3, 1.0, 0.1, 25),
    (1.0, 0.8, 0.0, 0.9, 60),
]
# Heavy loads at the default step (issue 44): (mass kg, a h / v, push N, target e_N, contact length
# in default steps); the approach speed is the load times the step over a h / v.
HEAVY = [
    (1.0, 0.25, 50.0, 0.5, 20),
    (1.0, 0.5, 50.0, 0.4, 25),
    (0.2, 1.0, 10.0, 0.3, 30),
]


def stiffness_for(mass, steps, h):
    """The pair stiffness (N/m) whose undamped contact, pi sqrt(m/k), spans ``steps`` steps of ``h``."""
    return mass * (math.pi / (steps * h)) ** 2


def pack(engine, mass, k_pair, radius=0.05):
    """The engine's parameters: both bodies at twice the pair stiffness, damping 0 (the inverse sets it)."""
    s = stepper(engine)
    if engine == "pybullet":
        return s.pack(
            mass=mass,
            stiffness_ball=2 * k_pair,
            damping_ball=0.0,
            stiffness_ground=2 * k_pair,
            damping_ground=0.0,
            breaking=pybullet_map.breaking_threshold(radius),
        )
    return s.pack(
        mass=mass,
        stiffness_ball=2 * k_pair,
        dissipation_ball=0.0,
        stiffness_ground=2 * k_pair,
        dissipation_ground=0.0,
    )


def run_engine(engine, p, h, scene, phases):
    """e_N per phase i/phases in the installed engine, and the seconds it took (build and run)."""
    start = time.perf_counter()
    if engine == "pybullet":
        from contactalpha.adapters.pybullet_kv import ADAPTER, PyBulletSettings

        settings = PyBulletSettings(timestep=h, phases=phases, window=3.0)
        model = ADAPTER.build_drop(
            scene,
            ADAPTER.parameters(0.0, scene),
            settings,
            stiffness_each=(p[pybullet_map.STIFFNESS_BALL], p[pybullet_map.STIFFNESS_GROUND]),
            damping_each=(p[pybullet_map.DAMPING_BALL], p[pybullet_map.DAMPING_GROUND]),
        )
    else:
        from contactalpha.adapters.drake_point import ADAPTER, DrakeSettings

        settings = DrakeSettings(time_step=h, phases=phases, window=3.0)
        model = ADAPTER.build_drop(
            scene,
            ADAPTER.parameters(0.0, scene),
            settings,
            stiffness_each=(p[drake_map.STIFFNESS_BALL], p[drake_map.STIFFNESS_GROUND]),
            dissipation_each=(p[drake_map.DISSIPATION_BALL], p[drake_map.DISSIPATION_GROUND]),
        )
    samples = ADAPTER.run(model, scene, settings)
    seconds = time.perf_counter() - start
    zs, ws = samples.extra["z"], samples.extra["v"]
    e = np.array(
        [measure_steps(zs[i], ws[i], scene.accel, h, scene.approach_speed).e_n for i in range(phases)]
    )
    return e, seconds


def critical_ratio(engine, p, h, v, a):
    """v / v_crit: the approach speed over the speed below which the phase mean no longer bounces."""
    lo, hi = 0.0, v
    if over_phase(engine, p, h, v, a).mean == 0.0:
        return math.nan
    while over_phase(engine, p, h, hi * 0.5 if hi > 1e-6 else hi, a).mean > 0.0 and hi > 1e-6:
        hi *= 0.5
    lo = hi * 0.5
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if over_phase(engine, p, h, mid, a).mean > 0.0:
            hi = mid
        else:
            lo = mid
    return v / hi


def check(engine, p, h, scene, target, phases, remedies=True):
    """Solve at ``h`` and check in the engine; a dict row (``inverse`` the StepInverse)."""
    v, a = scene.approach_speed, scene.accel
    t0 = time.perf_counter()
    inv = damping_for(engine, p, h, v, a, target, remedies=remedies)
    solve_s = time.perf_counter() - t0
    row = {"timestep": h, "status": inv.status, "solve_s": solve_s}
    if inv.status != "ok":
        row.update(nearest=inv.nearest, timestep_reachable=inv.timestep_reachable)
        row["stiffness_reachable"] = inv.stiffness_reachable
        return row, inv
    st = inv.stats
    e, seconds = run_engine(engine, inv.p, h, scene, phases)
    grid = np.arange(phases) / phases
    mapped = at_phases(engine, inv.p, h, grid, v, a)["e_n"]
    row.update(
        damping=inv.damping,
        predicted_mean=st.mean,
        predicted_min=st.minimum,
        predicted_max=st.maximum,
        steps=(st.steps_min, st.steps_max),
        measured_mean=float(e.mean()),
        measured_min=float(e.min()),
        measured_max=float(e.max()),
        mean_minus_target=float(e.mean() - target),
        min_minus_predicted=float(e.min() - st.minimum),
        max_minus_predicted=float(e.max() - st.maximum),
        sampled_minus_exact=float(mapped.mean() - st.mean),
        engine_minus_map=float(np.max(np.abs(e - mapped))),
        verify_s=seconds,
        verify_s_per_drop=seconds / phases,
    )
    return row, inv


def study(engine, phases):
    s = stepper(engine)
    h0 = s.timestep
    rows = []
    heavy = [(m, (G + f / m) * h0 / ahv, f, t, n) for m, ahv, f, t, n in HEAVY]
    for mass, v, force, target, steps in [*SCENES, *heavy]:
        scene = DropScene(mass, stiffness_for(mass, steps, h0), v, G, force)
        p = pack(engine, mass, scene.stiffness)
        row, inv = check(engine, p, h0, scene, target, phases)
        row.update(engine=engine, mass=mass, approach_speed=v, force=force, target=target,
                   contact_steps=steps, a_h_over_v=scene.accel * h0 / v)  # fmt: skip
        if inv.status == "ok":
            row["v_over_v_crit"] = (
                critical_ratio(engine, inv.p, h0, v, scene.accel) if target <= 0.1 else math.nan
            )
        else:
            remedies = {}
            if math.isfinite(inv.timestep_reachable):
                h1 = inv.timestep_reachable
                remedies["timestep"], inv1 = check(engine, p, h1, scene, target, phases)
                if inv1.status == "ok" and target <= 0.1:
                    remedies["timestep"]["v_over_v_crit"] = critical_ratio(engine, inv1.p, h1, v, scene.accel)
            if inv.stiffness_reachable is not None and math.isfinite(inv.stiffness_reachable):
                q = p.copy()
                k = list(s.stiffness_slots)
                q[k] = inv.stiffness_reachable * p[k] / p[k[0]]
                scene = DropScene(mass, scene.stiffness * inv.stiffness_reachable / p[k[0]], v, G, force)
                remedies["stiffness"], _ = check(engine, q, h0, scene, target, phases)
            row["remedies"] = remedies
        rows.append(row)
        report(row)
    return rows


def report(r):
    head = (f"{r['engine']:8s} m={r['mass']:<5g} v={r['approach_speed']:<4.3g} F={r['force']:<5g} "
            f"e*={r['target']:<4g} ah/v={r['a_h_over_v']:.3f}")  # fmt: skip
    if r["status"] == "ok":
        print(
            f"{head} ok  measured {r['measured_mean']:.4f}  mean-target {r['mean_minus_target']:+.1e}"
            f" (sampled-exact {r['sampled_minus_exact']:+.1e})"
            f"  min {r['min_minus_predicted']:+.1e} max {r['max_minus_predicted']:+.1e}"
            f"  |engine-map| {r['engine_minus_map']:.1e}  v/vc {r['v_over_v_crit']:.3f}"
            f"  verify {r['verify_s']:.2f} s"
        )
        return
    print(f"{head} {r['status']} nearest {r['nearest']:.4f}  h* {r['timestep_reachable']:.3g}")
    for name, rem in r.get("remedies", {}).items():
        if rem["status"] != "ok":
            print(f"    at the proposed {name}: {rem['status']}")
            continue
        print(
            f"    at the proposed {name} ({rem['timestep']:.3g} s):"
            f" mean-target {rem['mean_minus_target']:+.1e}"
            f"  min {rem['min_minus_predicted']:+.1e} max {rem['max_minus_predicted']:+.1e}"
            f"  |engine-map| {rem['engine_minus_map']:.1e}  v/vc {rem.get('v_over_v_crit', math.nan):.3f}"
            f"  verify {rem['verify_s']:.2f} s"
        )


def main():
    phases = int(sys.argv[1]) if len(sys.argv) > 1 else 128
    warnings.simplefilter("ignore", DeprecationWarning)
    results = {}
    for engine in ("pybullet", "drake"):
        start = time.perf_counter()
        results[engine] = study(engine, phases)
        print(f"{engine}: {time.perf_counter() - start:.1f} s")
    if len(sys.argv) > 2:
        from contactalpha.io import write_json_atomic
        from contactalpha.provenance import git_commit

        write_json_atomic(sys.argv[2], {"phases": phases, "commit": git_commit(), "results": results})


if __name__ == "__main__":
    main()
