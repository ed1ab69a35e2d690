"""What ``tune`` does on the engine's own drops after the reduced answer: the loop, refine, check.

``looped`` solves the damping on the engine's drops of the whole model (``loops``), ``refined``
refines MuJoCo's on its drop from touchdown (secant, to ``REFINE_TOL``) and rewrites the file,
``checked`` drops the tuned model from touchdown and reports the delivered e_N and how much the
effective mass moves over the contact (``MassChangeWarning`` above ``MASS_CHANGE_WARN``).
"""

import math
import warnings
from dataclasses import replace

import numpy as np

from contactalpha.adapters.base import refine as secant

from .discrete import ENGINE_STEPS
from .drake_model import drake_drop
from .loops import LOOPS, run_loop
from .mujoco_model import mujoco_drop, reader_joint_names
from .mujoco_row import solref_for
from .pybullet_model import pybullet_drop
from .tune_warnings import MassChangeWarning
from .writers import in_memory_mjcf, write_mujoco

# Relative change of the effective mass over the contact above which ``tune`` warns: the law is
# solved at touchdown's m_eff, and the load factor and MuJoCo's effective impedance move with it.
MASS_CHANGE_WARN = 0.01
# Gap samples per undamped contact time in a Drake check.
DRAKE_SAMPLES = 1000
# |delivered - target| at which refining on the engine's drop stops.
REFINE_TOL = 2e-4


def looped(result, target, base=None):
    """``result`` with the engine loop's answer, run in memory: ``tune`` writes the file after."""
    if result.engine not in LOOPS:  # an engine with no loop of its own (a toy's): the reduced answer
        return replace(
            result, notes=[*result.notes, f"{result.engine} has no engine loop: the reduced model's answer"]
        )
    answer, params, lines = run_loop(result.engine, result.contact, result.parameters, target,
                                     result.timestep, base)  # fmt: skip
    ok = answer.status == "ok"
    why = "" if ok else f"the engine loop did not reach e_N {target:g} ({answer.status})"
    return replace(result, parameters=params, notes=[*result.notes, *lines], loop=answer, reached=ok,
                   unreachable=why)  # fmt: skip


def refined(result, target, timestep):
    """``result`` with MuJoCo's damping ratio refined on its drop from touchdown, the file rewritten."""
    c, tuning = result.contact, result.details

    def delivered(zeta):
        solref = solref_for(tuning, zeta)
        return mujoco_drop(result.output, c.pair, c.qpos, c.qvel, timestep=timestep, forces=c.forces,
                           pair_solref=solref).e_n  # fmt: skip

    ref = secant(delivered, target, tuning.zeta, REFINE_TOL)
    if not math.isfinite(ref.damping):
        raise ValueError(
            f"refining on MuJoCo's drop failed ({ref.status}); the law's answer is {tuning.zeta!r}"
        )
    params = {**result.parameters, "solref": solref_for(tuning, ref.damping)}
    write_mujoco(c, result.output, params)
    notes = [*result.notes, f"refined on MuJoCo's drop from touchdown: zeta {tuning.zeta:.9g} -> "
             f"{ref.damping:.9g} ({ref.status}; the law's value delivered {ref.e_n_start:.6g})"]  # fmt: skip
    return replace(result, parameters=params, notes=notes)


def checked(result, timestep, refined=False):
    """``result`` with the engine's own drop of the tuned model from touchdown: e_N, m_eff's change."""
    c = result.contact
    if result.engine == "mujoco":
        source = result.output if result.output is not None else in_memory_mjcf(c, result.parameters)
        drop = mujoco_drop(source, c.pair, c.qpos, c.qvel, timestep=timestep, forces=c.forces)
    elif result.output is None:
        raise ValueError(f"check with engine {result.engine!r} needs output (the tuned model or script)")
    elif result.engine == "pybullet":
        if c.file_format != "urdf":
            raise ValueError("check with engine 'pybullet' drops a URDF model; this one is not")
        drop = pybullet_drop(c.model, c.pair, c.qpos, c.qvel, script=result.output, timestep=result.timestep,
                             speed=c.approach_speed, joint_names=reader_joint_names(c),
                             forces=c.forces)  # fmt: skip
    else:
        period = math.pi * math.sqrt(c.effective_mass / float(result.parameters["pair_stiffness"]))
        step = result.timestep
        drop = drake_drop(result.output, c.pair, c.qpos, c.qvel, forces=c.forces,
                          report=period / DRAKE_SAMPLES if step is None else step,
                          time_step=0.0 if step is None else step)  # fmt: skip
    change = drop.mass_change
    delivered = drop.e_n
    one = "" if result.timestep is None else (
        " (one drop, touchdown at the start of a step: at a coarse step one drop lies anywhere in the "
        "phase's range, and the mean over the phase is the target)")  # fmt: skip
    notes = [*result.notes, f"{result.engine}'s own drop delivers e_N = {delivered:.6g}{one}"]
    if np.isfinite(change):
        notes.append(f"effective mass moves by {change:.3g} (relative) over the contact")
        if change > MASS_CHANGE_WARN:
            warnings.warn(
                f"the effective mass moves by {change:.3g} over the contact (above {MASS_CHANGE_WARN}): "
                + ("refined on this drop, it holds for this touchdown state only" if refined
                   else "the law is solved at touchdown's value: refine on the engine's drop (refine=True)"
                   if result.engine == "mujoco" else
                   f"the law and the step map are solved at touchdown's value; {result.engine} delivers "
                   f"{delivered:.4g}"),
                MassChangeWarning, stacklevel=3,
            )  # fmt: skip
    return replace(result, notes=notes, delivered=delivered, mass_change=change, drop=drop)


def step_of(engine, contact, timestep):
    """The step ``tune`` works at when no step map ran: MuJoCo's model step, the engines' defaults."""
    if timestep is not None:
        return float(timestep)
    if engine in ENGINE_STEPS:
        return ENGINE_STEPS[engine].default_step
    return float(contact.engine_row["timestep"])  # MuJoCo: the model's
