"""A robot's contact at Drake's and PyBullet's coarse steps: the step's answer, checked in the engines.

The model (examples/data/hinged_arm.urdf) is a 1.5 kg arm on a hinge, falling horizontally onto
the floor; its tip sphere touches down at 0.8 m/s under gravity.  We want the tip to bounce with
Newton's e_N = 0.6 at each engine's usual step: Drake's discrete plant at 1 ms and PyBullet at
1/240 s, with contacts of 16 and 24 steps.  At such steps the law's continuous answer delivers far
less; ``tune`` evaluates it through the engine's step map at the contact's effective mass and
load and writes the map's phase-mean inverse instead.  Each engine then drops the tuned model at
16 touchdown phases: their mean is the target.

Run: python examples/engine_steps.py   (needs ``pip install drake pybullet mujoco``)
"""

import math
import tempfile
from pathlib import Path

import numpy as np

from contactalpha.mechanism import read_contact, tune
from contactalpha.mechanism.drake_model import drake_drop
from contactalpha.mechanism.pybullet_model import pybullet_drop

MODEL = Path(__file__).resolve().parent / "data" / "hinged_arm.urdf"
PAIR = ("floor", "tip")
TARGET = 0.6
QVEL = (1.6,)  # rad/s: the tip, 0.5 m from the hinge, closes at 0.8 m/s
PHASES = (np.arange(16) + 0.5) / 16  # where touchdown falls inside a step

with tempfile.TemporaryDirectory() as tmp:
    for engine, h, steps, suffix in (("drake", 1e-3, 16, ".urdf"), ("pybullet", 1 / 240, 24, ".py")):
        m_eff = read_contact(MODEL, PAIR, qvel=QVEL).effective_mass
        k = m_eff * (math.pi / (steps * h)) ** 2  # an undamped contact of `steps` steps
        out = Path(tmp) / ("arm_tuned" + suffix)
        result = tune(MODEL, PAIR, TARGET, engine=engine, qvel=QVEL, stiffness=k, timestep=h, output=out)
        c, step = result.contact, result.discrete
        if engine == "drake":
            drops = [drake_drop(out, PAIR, c.qpos, c.qvel, time_step=h, phase=f).e_n for f in PHASES]
        else:
            drops = [pybullet_drop(MODEL, PAIR, c.qpos, c.qvel, script=out, timestep=h, phase=f).e_n
                     for f in PHASES]  # fmt: skip
        print(f"{engine} at {h:.4g} s, {steps} steps per contact")
        print(f"  effective mass               {m_eff:.12f}")
        print(f"  free accel                   {c.accel:.12f}")
        print(f"  law's answer, phase mean     {step.continuous.mean:.4f}")
        st = step.inverse.stats
        print(
            f"  step answer, phase mean      {st.mean:.4f} (one drop: {st.minimum:.4f} to {st.maximum:.4f})"
        )
        print(f"  engine, mean of 16 drops     {np.mean(drops):.4f} "
              f"(one drop: {min(drops):.4f} to {max(drops):.4f})")  # fmt: skip
