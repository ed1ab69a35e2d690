"""Study of issue 46 for PyBullet's rigid contact: restitution and threshold at its 1/240 s step.

Run: PYTHONPATH=src nice -n 10 python benchmarks/study_impulse.py [PHASES] [FIGURE.png] [ENGINES] [PHYSX.png]

ENGINES: comma-separated, of pybullet_impulse and physx (default both; physx needs SAPIEN).

1. **What users get today** (the issue's table): the three scenes (0.1 kg at 0.3 m/s; 1 kg at
   1 m/s pushed by 5 m g; 5 kg at 2 m/s; a 5 cm sphere) with the target as the pair's restitution
   and as each body's, PyBullet's default threshold, mean e_N over 64 touchdown phases, measured
   in PyBullet and by the map (``impulse.bullet_map``).
2. **The answer in PyBullet**: 12 scenes (mass, Hertz stiffness, speed, push, target varied);
   ``contact_parameters(..., engine="pybullet_impulse", timestep="default", verify=PHASES)``; the
   measured mean minus the target (done within 1e-3) and the measured range minus the predicted
   one (done within 2e-3), beside what the raw coefficient delivers.
3. **Drops from rest** at three loads and two restitutions (0.5 kg, 1e7 N/m^1.5, 3 m/s): the
   touchdown schedule's bounces and last touchdown in PyBullet against ``predict_bounces``; and
   the constant answer (restitution and threshold of step 2) for comparison.
4. **The figure**: delivered e_N against approach speed for one loaded contact, map only.
5. **PhysX 5 through SAPIEN** (0.01 s): the issue's PhysX rows, and step 2's 12 scenes.
6. **Drops from rest in PhysX**: step 3's six scenes with the touchdown schedule at five steps
   (0.01 s to 1 ms), bounces and last touchdown against ``predict_bounces``, and each scene's
   slowest predicted flight (a rebound flying less than a step is not seen).
7. **PhysX's figure** (``PHYSX.png``, default ``docs/assets/impulse_physx.png``): step 4's for
   SAPIEN at 0.01 s, measured in SAPIEN at 128 phases a speed: the raw coefficient at SAPIEN's
   bounce threshold and at 0, and the package's answer.
"""

import math
import sys
import time

import numpy as np

import contactalpha as ca
from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.pybullet_impulse import ADAPTER, ImpulseSettings, block, drop_sequence
from contactalpha.impulse import bullet_map as bm
from contactalpha.impulse.delivered import phase_drops, phase_stats, read_bounces
from contactalpha.impulse.inverse import restitution_for, threshold_for
from contactalpha.parameters.impulse_schedule import touchdown_schedule
from contactalpha.scene.ball import Scene
from contactalpha.scene.bounces import predict_bounces

H = bm.DEFAULT_TIMESTEP
G = 9.81
ISSUE_SCENES = [(0.3, 0.1, 0.3, 0.0), (0.5, 1.0, 1.0, 5 * 1.0 * G), (0.8, 5.0, 2.0, 0.0)]
# (mass kg, Hertz stiffness N/m^1.5, v m/s, push N, target e_N, radius m): tests/impulse's scenes
TARGET_SCENES = [
    (0.5, 1e7, 1.0, 0.0, 0.5, 0.05),
    (0.1, 1e6, 2.0, 0.0, 0.8, 0.03),
    (2.0, 1e8, 1.5, 10.0, 0.6, 0.05),
    (1.0, 1e7, 0.8, 20.0, 0.3, 0.05),
    (5.0, 1e8, 3.0, 0.0, 0.9, 0.1),
    (0.05, 1e6, 0.6, 0.2, 0.7, 0.02),
    (0.3, 1e7, 1.2, 3.0, 0.4, 0.05),
    (10.0, 1e9, 2.5, 100.0, 0.75, 0.1),
    (0.2, 1e6, 0.9, 0.0, 0.2, 0.05),
    (1.0, 1e8, 4.0, 0.0, 0.95, 0.05),
    (20.0, 1e9, 1.0, 200.0, 0.55, 0.15),
    (0.5, 1e7, 0.5, 2.0, 0.65, 0.05),
]
DROP_SCENES = [(0.0, 0.6), (0.0, 0.85), (5.0, 0.6), (5.0, 0.85), (20.0, 0.6), (20.0, 0.75), (20.0, 0.85)]


def _engine_mean(pair, m, v, force, r=0.05, phases=64):
    scene = DropScene(m, 1e7, v, G, force, r)
    settings = ImpulseSettings(phases=phases)
    samples = ADAPTER.run(
        ADAPTER.build_drop(scene, block(pair, bm.VELOCITY_THRESHOLD), settings), scene, settings
    )
    ADAPTER.measure(samples, scene)
    return float(samples.extra["e_n_phases"].mean())


def issue_table():
    print("\n## 1. What users get today (PyBullet 3.2.7, 1/240 s, mean over 64 phases; engine / map)\n")
    print("| what the user sets | " + " | ".join(f"target {t}" for t, *_ in ISSUE_SCENES) + " |")
    print("|---|---|---|---|")
    for label, combine in (("the pair's value", lambda t: t), ("each body's value", lambda t: t * t)):
        cells = []
        for t, m, v, force in ISSUE_SCENES:
            a = G + force / m
            mapped = phase_stats(bm.make_params(combine(t), 0.05), H, v, a, 64).mean
            cells.append(f"{_engine_mean(combine(t), m, v, force):.3f} / {mapped:.3f}")
        print(f"| restitution = target as {label} | " + " | ".join(cells) + " |")


def physx_issue_table():
    """The issue's PhysX rows: SAPIEN's bounce threshold (2 m/s) and 0, the target on both materials."""
    from contactalpha.adapters.physx_sapien import ADAPTER as PHYSX
    from contactalpha.adapters.physx_sapien import PhysxSettings
    from contactalpha.impulse import physx_map as pm
    from contactalpha.impulse.kernels import PHYSX as CODE

    print("\n## 1b. PhysX 5 (SAPIEN 3.0.3, 0.01 s), mean over 64 phases; engine / map\n")
    print("| what the user sets | " + " | ".join(f"target {t}" for t, *_ in ISSUE_SCENES) + " |")
    print("|---|---|---|---|")
    for thr in (pm.BOUNCE_THRESHOLD, 0.0):
        cells = []
        for t, m, v, force in ISSUE_SCENES:
            scene = DropScene(m, 1e7, v, G, force, 0.05)
            settings = PhysxSettings(phases=64, threshold=thr, steps=60)
            samples = PHYSX.run(PHYSX.build_drop(scene, PHYSX.block(t, thr), settings), scene, settings)
            PHYSX.measure(samples, scene)
            mapped = phase_stats(pm.make_params(t, thr), pm.DEFAULT_TIMESTEP, v, scene.accel, 64, CODE).mean
            cells.append(f"{samples.extra['e_n_phases'].mean():.3f} / {mapped:.3f}")
        print(f"| restitution = target, bounce threshold {thr:g} m/s | " + " | ".join(cells) + " |")


def target_table(phases, engine="pybullet_impulse"):
    print(f"\n## 2. The answer in {engine} ({phases} phases and the map's two extreme phases)\n")
    print(
        "| m (kg) | k (N/m^1.5) | v (m/s) | push (N) | target | restitution (pair) | threshold (m/s) "
        "| predicted mean [min, max] | engine mean [min, max] | mean - target | range vs predicted "
        "| raw coefficient delivers | check (s) |"
    )
    print("|" + "---|" * 13)
    worst_mean = worst_range = 0.0
    for m, k, v, force, target, r in TARGET_SCENES:
        cp = ca.contact_parameters(
            e_N=target,
            mass=m,
            stiffness=k,
            approach_speed=v,
            force=force + m * G,
            radius=r,
            engine=engine,
            timestep="default",
            verify=phases,
        )
        st, ver = cp.stepped, cp.stepped.verify
        d_mean = ver["mean"] - target
        d_range = max(abs(ver["minimum"] - st.minimum), abs(ver["maximum"] - st.maximum))
        worst_mean, worst_range = max(worst_mean, abs(d_mean)), max(worst_range, d_range)
        print(
            f"| {m:g} | {k:.0e} | {v:g} | {force:g} | {target:g} | {st.damping:.4f} "
            f"| {cp.block.get('restitutionVelocityThreshold', cp.block.get('bounce_threshold')):.4f} "
            f"| {st.mean:.4f} [{st.minimum:.4f}, {st.maximum:.4f}] "
            f"| {ver['mean']:.4f} [{ver['minimum']:.4f}, {ver['maximum']:.4f}] "
            f"| {d_mean:+.1e} | {d_range:.1e} "
            f"| {st.continuous_mean:.4f} [{st.continuous_minimum:.4f}, {st.continuous_maximum:.4f}] "
            f"| {ver['seconds']:.2f} |"
        )
    print(f"\nworst |mean - target| {worst_mean:.2e}; worst range difference {worst_range:.2e}")


def drop_table():
    m, k, v, r = 0.5, 1e7, 3.0, 0.05
    print("\n## 3. Drops from rest (0.5 kg, 1e7 N/m^1.5, first touchdown 3 m/s)\n")
    print(
        "| push (N) | eps | predicted bounces | last touchdown (s) | schedule: bounces | last touchdown "
        "| rebound speeds vs predicted | constant answer: bounces | last touchdown | check (s) |"
    )
    print("|" + "---|" * 10)
    for force, eps in DROP_SCENES:
        start = time.perf_counter()
        pred = predict_bounces(
            Scene(mass=m, radius=r, stiffness=k, approach_speed=v, force=force, eps=eps, gravity=G), "exact"
        )
        last = pred.time_to_rest - pred.contact_durations[-1]
        sched = touchdown_schedule(m, k, v, eps=eps, force=force + m * G, radius=r)
        scene = DropScene(m, k, v, G, force, r)
        z, w = drop_sequence(scene, sched, 1.2 * last + v / sched.accel)
        got = read_bounces(z, w, sched.accel, H)
        n = min(got.count, pred.bounces)
        du = float(np.max(np.abs(got.rebound_speeds[:n] - pred.rebound_speeds[:n])))
        cp = ca.contact_parameters(
            eps=eps,
            mass=m,
            stiffness=k,
            approach_speed=v,
            force=force + m * G,
            radius=r,
            engine="pybullet_impulse",
            timestep="default",
        )
        const = _constant_drop(scene, cp.block, 1.2 * last + v / sched.accel)
        t_sched = got.landings[-1] - v / sched.accel
        t_const = const.landings[-1] - v / sched.accel if const.count else math.nan
        print(
            f"| {force:g} | {eps:g} | {pred.bounces} | {last:.4f} | {got.count} "
            f"| {t_sched:.4f} ({t_sched / last - 1:+.1e}) "
            f"| {du:.1e} m/s | {const.count} | {t_const:.4f} ({t_const / last - 1:+.1e}) "
            f"| {time.perf_counter() - start:.2f} |"
        )


PHYSX_DROP_STEPS = [0.01, 1.0 / 120.0, 1.0 / 240.0, 0.002, 0.001]


def physx_drop_table():
    from contactalpha.adapters import physx_sapien

    m, k, v, r = 0.5, 1e7, 3.0, 0.05
    print("\n## 6. Drops from rest in PhysX (touchdown schedule; bounces, last touchdown vs predicted)\n")
    steps = " | ".join(f"{h * 1e3:.3g} ms" for h in PHYSX_DROP_STEPS)
    print(
        "| push (N) | eps | predicted bounces | last touchdown (s) | slowest flight (ms) "
        f"| {steps} | check (s) |"
    )
    print("|" + "---|" * (6 + len(PHYSX_DROP_STEPS)))
    for force, eps in DROP_SCENES[:6]:
        start = time.perf_counter()
        pred = predict_bounces(
            Scene(mass=m, radius=r, stiffness=k, approach_speed=v, force=force, eps=eps, gravity=G), "exact"
        )
        last = pred.time_to_rest - pred.contact_durations[-1]
        a = G + force / m
        flight = 2.0 * pred.rebound_speeds[: pred.bounces].min() / a
        cells = []
        for h in PHYSX_DROP_STEPS:
            sched = touchdown_schedule(
                m, k, v, eps=eps, force=force + m * G, radius=r, engine="physx", timestep=h
            )
            z, w = physx_sapien.drop_sequence(DropScene(m, k, v, G, force, r), sched, 1.2 * last + v / a)
            got = read_bounces(z, w, a, h, physx_sapien.FREE_RTOL, physx_sapien.position_resolution(z, r))
            n = min(got.count, pred.bounces)
            du = float(np.max(np.abs(got.rebound_speeds[:n] - pred.rebound_speeds[:n])))
            t = got.landings[-1] - v / a
            cells.append(f"{got.count} ({(t / last - 1) * 100:+.2f} %, {du:.1e} m/s)")
        print(
            f"| {force:g} | {eps:g} | {pred.bounces} | {last:.4f} | {flight * 1e3:.1f} | {' | '.join(cells)} "
            f"| {time.perf_counter() - start:.2f} |"
        )


def _constant_drop(scene, blk, duration):
    """Bounces of a drop from rest with a constant restitution and threshold (the front door's block)."""
    import pybullet as pb

    settings = ImpulseSettings(phases=1)
    model = ADAPTER.build_drop(scene, blk, settings)
    c, b, a = model.client, model.ball, scene.accel
    z, w = scene.approach_speed**2 / (2 * a), 0.5 * a * H
    pb.resetBasePositionAndOrientation(b, [0, 0, scene.radius + z], [0, 0, 0, 1], physicsClientId=c)
    pb.resetBaseVelocity(b, [0, 0, w], [0, 0, 0], physicsClientId=c)
    zs, ws = [z], [w]
    for _ in range(int(duration / H)):
        if scene.force:
            pb.applyExternalForce(b, -1, [0, 0, -scene.force], [0, 0, 0], pb.LINK_FRAME, physicsClientId=c)
        pb.stepSimulation(physicsClientId=c)
        zs.append(pb.getBasePositionAndOrientation(b, physicsClientId=c)[0][2] - scene.radius)
        ws.append(pb.getBaseVelocity(b, physicsClientId=c)[0][2])
    pb.disconnect(c)
    return read_bounces(np.array(zs), np.array(ws), a, H)


def figure(path):
    """Delivered e_N against approach speed: the loaded contact, the raw coefficient, the package's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m, k, eps, r = 0.5, 1e7, 0.7, 0.05
    v_c = float(ca.critical_speed(eps, m, k, G))
    speeds = np.geomspace(1.1 * v_c, 3.0, 48)
    loaded = np.array(
        [ca.contact_parameters(eps=eps, mass=m, stiffness=k, approach_speed=s, accel=G).e_n for s in speeds]
    )
    thr = threshold_for(v_c, H, G)
    rows = {"raw": [], "package": []}
    for s, target in zip(speeds, loaded, strict=True):
        raw = phase_drops(bm.make_params(target, r), H, s, G, 1024)[0]
        ans = restitution_for(target, H, s, G, r, thr)
        ours = (
            phase_drops(bm.make_params(ans.restitution, r, thr), H, s, G, 1024)[0]
            if ans.status == "ok"
            else None
        )
        rows["raw"].append((raw.mean(), raw.min(), raw.max()))
        rows["package"].append((ours.mean(), ours.min(), ours.max()) if ours is not None else (np.nan,) * 3)
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    ax.plot(speeds, loaded, "k-", lw=2, label="loaded contact (target; the per-step schedule delivers it)")
    for key, color, label in (
        ("raw", "tab:red", "restitution = target, threshold 0.2 m/s"),
        ("package", "tab:blue", "the package's restitution and threshold"),
    ):
        arr = np.array(rows[key])
        ax.plot(speeds, arr[:, 0], color=color, label=f"{label}: mean")
        ax.fill_between(speeds, arr[:, 1], arr[:, 2], color=color, alpha=0.2, label=f"{label}: one drop")
    ax.axvline(v_c, color="0.5", ls=":", label=f"critical speed {v_c:.3f} m/s")
    ax.set_xscale("log")
    ax.set_xlabel("approach speed (m/s)")
    ax.set_ylabel("delivered $e_N$")
    ax.set_title("PyBullet at 1/240 s: 0.5 kg, Hertz 1e7 N/m$^{1.5}$, eps 0.7, gravity", fontsize=10)
    ax.set_ylim(0.0, 1.15)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"\nfigure: {path}")


def physx_figure(path, phases=128, n_speeds=24):
    """As ``figure`` for PhysX at 0.01 s, measured in SAPIEN (``phases`` drops a speed and setting).

    The raw coefficient (the loaded contact's e_N on both materials) at SAPIEN's bounce threshold
    (2 m/s) and at 0, and the package's restitution and threshold, each dropped at ``phases``
    touchdown phases; prints the largest difference of SAPIEN's mean and range from the map's.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contactalpha.adapters.physx_sapien import ADAPTER as PHYSX
    from contactalpha.adapters.physx_sapien import PhysxSettings
    from contactalpha.impulse import physx_map as pm
    from contactalpha.impulse.kernels import PHYSX as CODE

    h = pm.DEFAULT_TIMESTEP
    m, k, eps, r = 0.5, 1e7, 0.7, 0.05
    v_c = float(ca.critical_speed(eps, m, k, G))
    speeds = np.geomspace(1.1 * v_c, 3.0, n_speeds)
    loaded = np.array(
        [ca.contact_parameters(eps=eps, mass=m, stiffness=k, approach_speed=s, accel=G).e_n for s in speeds]
    )
    thr = threshold_for(v_c, h, G)
    keys = ("raw", "raw0", "package")
    rows = {key: [] for key in keys}
    worst = 0.0
    start = time.perf_counter()
    for s, target in zip(speeds, loaded, strict=True):
        ans = restitution_for(target, h, s, G, r, thr, engine="physx")
        for key, (e, t) in zip(keys, ((target, pm.BOUNCE_THRESHOLD), (target, 0.0), (ans.restitution, thr)),
                               strict=True):  # fmt: skip
            if not math.isfinite(e):
                rows[key].append((np.nan,) * 3)
                continue
            scene = DropScene(m, k, s, G, 0.0, r)
            settings = PhysxSettings(phases=phases, threshold=t, steps=20)
            samples = PHYSX.run(PHYSX.build_drop(scene, PHYSX.block(e, t), settings), scene, settings)
            PHYSX.measure(samples, scene)
            got = samples.extra["e_n_phases"]
            mapped = phase_drops(pm.make_params(e, t), h, s, G, phases, CODE)[0]
            worst = max(worst, float(np.max(np.abs(got - mapped))))
            rows[key].append((got.mean(), got.min(), got.max()))
    seconds = time.perf_counter() - start
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    ax.plot(speeds, loaded, "k-", lw=2, label="loaded contact (target; the per-step schedule delivers it)")
    for key, color, label in (
        ("raw", "tab:red", "restitution = target, threshold 2 m/s (SAPIEN's)"),
        ("raw0", "tab:orange", "restitution = target, threshold 0"),
        ("package", "tab:blue", "the package's restitution and threshold"),
    ):
        arr = np.array(rows[key])
        ax.plot(speeds, arr[:, 0], color=color, marker=".", label=f"{label}: mean")
        ax.fill_between(speeds, arr[:, 1], arr[:, 2], color=color, alpha=0.2, label=f"{label}: one drop")
    ax.axvline(v_c, color="0.5", ls=":", label=f"critical speed {v_c:.3f} m/s")
    ax.set_xscale("log")
    ax.set_xlabel("approach speed (m/s)")
    ax.set_ylabel("delivered $e_N$ (measured in SAPIEN)")
    ax.set_title("PhysX 5 (SAPIEN) at 0.01 s: 0.5 kg, Hertz 1e7 N/m$^{1.5}$, eps 0.7, gravity", fontsize=10)
    ax.set_ylim(0.0, 1.15)  # the package's one-drop band runs higher near the critical speed
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    n_drops = 3 * n_speeds * phases
    print(f"\nfigure: {path} ({n_drops} SAPIEN drops of 20 steps, {seconds:.1f} s; SAPIEN's e_N per drop "
          f"within {worst:.1e} of the map's; the package's one drop at most "
          f"{np.nanmax(np.array(rows['package'])[:, 2]):.3g})")  # fmt: skip


def main():
    phases = int(sys.argv[1]) if len(sys.argv) > 1 else 512
    path = sys.argv[2] if len(sys.argv) > 2 else "docs/assets/impulse_pybullet.png"
    engines = sys.argv[3].split(",") if len(sys.argv) > 3 else ["pybullet_impulse", "physx"]
    physx_path = sys.argv[4] if len(sys.argv) > 4 else "docs/assets/impulse_physx.png"
    start = time.perf_counter()
    if "pybullet_impulse" in engines:
        issue_table()
        target_table(phases)
        drop_table()
        figure(path)
    if "physx" in engines:
        physx_issue_table()
        target_table(phases, "physx")
        physx_drop_table()
        physx_figure(physx_path)
    print(f"\nwhole study {time.perf_counter() - start:.1f} s (shared loaded 2-core machine)")


if __name__ == "__main__":
    main()
