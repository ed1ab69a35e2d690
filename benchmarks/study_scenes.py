"""Issue 43's stack and boxes in PyBullet's and Drake's engine loops, measured in the raw engines.

For each scene, engine, step and target: the loop's answer (``solve_damping`` on the loop's
midpoint phases) and the mean e_N of raw drops written on the engine alone (``tests/mechanism``'s
``pybullet_scenes``, ``test_drake_scenes``: fresh worlds, free falls from a few steps up, e_N
read in free flight) over 256 touchdown phases on an even grid shifted by one uniform draw, with
the one-drop spread over sqrt(256) (an upper bound of a shifted grid's error).  A target no
damping reaches is reported with the loop's nearest mean.

Run: ``PYTHONPATH=src python benchmarks/study_scenes.py [pybullet] [drake] [drake_stack] [fine]``
(PyBullet and Drake installed; default all).
"""

import math
import sys
import time
from pathlib import Path
from tempfile import TemporaryDirectory

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "mechanism"))

import numpy as np  # noqa: E402
import pybullet as pb  # noqa: E402
import pybullet_scenes as ps  # noqa: E402
import test_drake_scenes as ds  # noqa: E402
from raw_reading import G, start_rate  # noqa: E402

from contactalpha.mechanism.drake_loop import DrakeLoop  # noqa: E402
from contactalpha.mechanism.engine_loop import solve_damping  # noqa: E402
from contactalpha.mechanism.pybullet_floating import GROUND  # noqa: E402
from contactalpha.mechanism.pybullet_loop import PybulletLoop  # noqa: E402

TARGETS = (0.3, 0.6, 0.9)
PHASES = 256
FINE = 2.5e-4  # s
SPEED = 1.0


def _row(scene, engine, h, target, ans, raw, seconds):
    d = ans.delivered
    mean, err = raw if raw else (math.nan, math.nan)
    head = f"| {scene} | {engine} | {h:.3g} | {target:g} | {ans.status} | {ans.solref[1]:.6g} | {d.mean:.5f}"
    print(f"{head} | {mean:.5f} ± {err:.5f} | {mean - target:+.5f} | {seconds:.1f} |", flush=True)


def pybullet_stack(tmp, h, targets=TARGETS):
    urdf = tmp / "stack.urdf"
    urdf.write_text(ps.STACK)
    z = ps.resting_height(pb, urdf, h)

    def place(p, c, body, tau):
        p.resetBasePositionAndOrientation(body, [0, 0, z], [0, 0, 0, 1], physicsClientId=c)
        p.resetJointState(
            body, 0, SPEED * tau - 0.5 * G * tau * tau, start_rate(SPEED, tau, h), physicsClientId=c
        )

    for target in targets:
        clock = time.process_time()
        loop = PybulletLoop(urdf, ("low", "top"), [1, 0, 0, 0, 0, 0, z, 0.0], [0, 0, 0, 0, 0, 0, -SPEED],
                            timestep=h, base="floating", set_on=("top",))  # fmt: skip
        ans = solve_damping(loop, target, (1e4, 10.0))
        loop.close()
        seconds = time.process_time() - clock
        raw = None
        if ans.status == "ok":
            raw = ps.raw_drops(
                pb, urdf, h, PHASES, place, {("robot", 1): ans.solref}, (("robot", -1), ("robot", 1))
            )
        _row("stack", "PyBullet", h, target, ans, raw, seconds)


def pybullet_box(tmp, h, targets=TARGETS):
    urdf = tmp / "box.urdf"
    urdf.write_text(ps.BOX)

    def place(p, c, body, tau):
        z = 0.05 + SPEED * tau - 0.5 * G * tau * tau
        p.resetBasePositionAndOrientation(body, [0, 0, z], [0, 0, 0, 1], physicsClientId=c)
        p.resetBaseVelocity(body, [0, 0, start_rate(SPEED, tau, h)], [0, 0, 0], physicsClientId=c)

    for target in targets:
        clock = time.process_time()
        qpos, qvel = [1, 0, 0, 0, 0, 0, 0.05], [0, 0, 0, 0, 0, -SPEED]
        loop = PybulletLoop(urdf, (GROUND, "box"), qpos, qvel, timestep=h, base="floating")
        ans = solve_damping(loop, target, (1e4, 1.0))
        loop.close()
        seconds = time.process_time() - clock
        raw = None
        if ans.status == "ok":
            values = {("floor", -1): ans.solref, ("robot", -1): ans.solref}
            raw = ps.raw_drops(pb, urdf, h, PHASES, place, values, (("floor", -1), ("robot", -1)))
        _row("flat box", "PyBullet", h, target, ans, raw, seconds)


def drake_box(tmp, h, targets=TARGETS):
    src = tmp / "box.sdf"
    src.write_text(ds._sdf())
    ds.STEP = h
    for target in targets:
        clock = time.process_time()
        loop = DrakeLoop(src, ("floor", "box"), ds._pose(0.0), [0, 0, 0, 0, 0, -SPEED], timestep=h)
        ans = solve_damping(loop, target, (1e4, 1.0))
        seconds = time.process_time() - clock
        raw = None
        if ans.status == "ok":
            tuned = tmp / "tuned.sdf"
            tuned.write_text(ds._sdf(*ans.solref))
            raw = ds._raw(tuned, PHASES)
        _row("flat box (4 corner spheres)", "Drake", h, target, ans, raw, seconds)


def _raw_drake_stack(path, h, n, seed=9):
    """Raw Drake: the 0.5 kg sphere let fall onto the resting 1 kg one (phases on a shifted grid);
    the gap is the centres' distance less the radii (closed form), read in free flight."""
    import pydrake.all as dk
    from raw_reading import done, flight_e

    builder = dk.DiagramBuilder()
    plant, _ = dk.AddMultibodyPlantSceneGraph(builder, h)
    plant.set_contact_model(dk.ContactModel.kPoint)
    plant.set_discrete_contact_approximation(dk.DiscreteContactApproximation.kLagged)
    dk.Parser(plant).AddModels(str(path))
    plant.Finalize()
    diagram = builder.Build()
    low, top = plant.GetBodyByName("low"), plant.GetBodyByName("top")
    shift = np.random.default_rng(seed).random()
    out = []
    for i in range(n):
        sim = dk.Simulator(diagram)
        ctx = plant.GetMyMutableContextFromRoot(sim.get_mutable_context())
        tau = (3.0 + (i + shift) / n) * h
        pose = plant.GetFreeBodyPose(ctx, top)
        up = [0, 0, SPEED * tau - 0.5 * G * tau * tau]
        plant.SetFreeBodyPose(ctx, top, dk.RigidTransform(pose.rotation(), pose.translation() + up))
        plant.SetFreeBodySpatialVelocity(
            ctx, top, dk.SpatialVelocity(np.zeros(3), [0, 0, start_rate(SPEED, tau, h)])
        )
        sim.Initialize()
        gaps = []
        for j in range(1, 3000):
            p1 = plant.EvalBodyPoseInWorld(ctx, low).translation()
            p2 = plant.EvalBodyPoseInWorld(ctx, top).translation()
            gaps.append(float(np.linalg.norm(p2 - p1)) - 0.15)
            if done(gaps):
                break
            sim.AdvanceTo(j * h)
        out.append(flight_e(gaps, h))
    return float(np.mean(out)), float(np.std(out, ddof=1) / math.sqrt(n))


def drake_stack(tmp, h):
    import pydrake.all as dk
    import test_engine_loops as el

    src = tmp / "stack.sdf"
    src.write_text(el.STACK.format(low=0.1 - el.SINK, top=0.25 - el.SINK))
    builder = dk.DiagramBuilder()
    plant, _ = dk.AddMultibodyPlantSceneGraph(builder, h)
    dk.Parser(plant).AddModels(str(src))
    plant.Finalize()
    ctx = plant.CreateDefaultContext()
    qvel = np.zeros(plant.num_velocities())
    qvel[plant.GetBodyByName("top").floating_velocities_start_in_v() + 5] = -SPEED
    for target in (0.2, *TARGETS):
        clock = time.process_time()
        loop = DrakeLoop(src, ("low", "top"), plant.GetPositions(ctx), qvel, timestep=h)
        # 2e4 on each sphere: the lower one's 1e4 N/m with the floor's 2e4, which SINK rests on
        ans = solve_damping(loop, target, (2e4, 1.0))
        seconds = time.process_time() - clock
        raw = None
        if ans.status == "ok":
            tuned = tmp / "stack_tuned.sdf"
            text = src.read_text()
            for name in ("low", "top"):
                text = text.replace(
                    f'<collision name="{name}">',
                    f'<collision name="{name}">' + ds.MATERIAL.format(k=ans.solref[0], d=ans.solref[1]),
                )
            tuned.write_text(text)
            raw = _raw_drake_stack(tuned, h, PHASES)
        _row("stack", "Drake", h, target, ans, raw, seconds)


def main(scenes=None):
    print(
        "| scene | engine | step (s) | target | loop | damping | loop mean | raw mean ± spread/16 "
        f"({PHASES} phases) | raw − target | CPU s (loop) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    with TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        if scenes is None or "pybullet" in scenes:
            for h in (1e-3, 1 / 240):
                pybullet_stack(tmp, h)
                pybullet_box(tmp, h)
        if scenes is None or "drake" in scenes:
            drake_box(tmp, 1e-3)
        if scenes is None or "drake_stack" in scenes:
            drake_stack(tmp, 1e-3)
        if scenes is None or "fine" in scenes:  # 0.9, out of reach at 1 ms, at a quarter of it
            pybullet_stack(tmp, FINE, (0.9,))
            pybullet_box(tmp, FINE, (0.9,))
            drake_box(tmp, FINE, (0.9,))
    np.seterr(all="ignore")


if __name__ == "__main__":
    main(sys.argv[1:] or None)
