"""Issue 43's stack and boxes in PyBullet's and Drake's engine loops, measured in the raw engines.

For each scene, engine, step and target: the loop's answer (``solve_damping`` on the loop's
midpoint phases) and the mean e_N of raw drops written on the engine alone (``tests/mechanism``'s
``pybullet_scenes``, ``test_drake_scenes``: fresh worlds, free falls from a few steps up, e_N
read in free flight) over 256 touchdown phases on an even grid shifted by one uniform draw, with
the one-drop spread over sqrt(256) (an upper bound of a shifted grid's error).  A target no
damping reaches is reported with the loop's nearest mean.

Run: ``PYTHONPATH=src python benchmarks/study_scenes.py`` (PyBullet and Drake installed).
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
SPEED = 1.0


def _row(scene, engine, h, target, ans, raw, seconds):
    d = ans.delivered
    mean, err = raw if raw else (math.nan, math.nan)
    print(f"| {scene} | {engine} | {h:.3g} | {target:g} | {ans.status} | {ans.solref[1]:.6g} | {d.mean:.5f} | "
          f"{mean:.5f} ± {err:.5f} | {mean - target:+.5f} | {seconds:.1f} |", flush=True)  # fmt: skip


def pybullet_stack(tmp, h):
    urdf = tmp / "stack.urdf"
    urdf.write_text(ps.STACK)
    z = ps.resting_height(pb, urdf, h)

    def place(p, c, body, tau):
        p.resetBasePositionAndOrientation(body, [0, 0, z], [0, 0, 0, 1], physicsClientId=c)
        p.resetJointState(
            body, 0, SPEED * tau - 0.5 * G * tau * tau, start_rate(SPEED, tau, h), physicsClientId=c
        )

    for target in TARGETS:
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


def pybullet_box(tmp, h):
    urdf = tmp / "box.urdf"
    urdf.write_text(ps.BOX)

    def place(p, c, body, tau):
        p.resetBasePositionAndOrientation(body, [0, 0, 0.05 + SPEED * tau - 0.5 * G * tau * tau], [0, 0, 0, 1],
                                          physicsClientId=c)  # fmt: skip
        p.resetBaseVelocity(body, [0, 0, start_rate(SPEED, tau, h)], [0, 0, 0], physicsClientId=c)

    for target in TARGETS:
        clock = time.process_time()
        loop = PybulletLoop(urdf, (GROUND, "box"), [1, 0, 0, 0, 0, 0, 0.05], [0, 0, 0, 0, 0, -SPEED], timestep=h,
                            base="floating")  # fmt: skip
        ans = solve_damping(loop, target, (1e4, 1.0))
        loop.close()
        seconds = time.process_time() - clock
        raw = None
        if ans.status == "ok":
            values = {("floor", -1): ans.solref, ("robot", -1): ans.solref}
            raw = ps.raw_drops(pb, urdf, h, PHASES, place, values, (("floor", -1), ("robot", -1)))
        _row("flat box", "PyBullet", h, target, ans, raw, seconds)


def drake_box(tmp, h):
    src = tmp / "box.sdf"
    src.write_text(ds._sdf())
    ds.STEP = h
    for target in TARGETS:
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


def main():
    print(
        "| scene | engine | step (s) | target | loop | damping | loop mean | raw mean ± spread/16 "
        f"({PHASES} phases) | raw − target | CPU s (loop) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    with TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for h in (1e-3, 1 / 240):
            pybullet_stack(tmp, h)
            pybullet_box(tmp, h)
        drake_box(tmp, 1e-3)
    np.seterr(all="ignore")


if __name__ == "__main__":
    main()
