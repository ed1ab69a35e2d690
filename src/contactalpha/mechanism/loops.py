"""The engine loops as ``tune`` runs them: one record per engine, MuJoCo's, PyBullet's and Drake's.

Each ``EngineLoop`` says how the engine's loop is built from a contact and the tuned parameters
(``build``: MuJoCo's drops the MJCF ``tune`` writes, in memory; PyBullet's and Drake's set the
pair's values on the model file), which of the parameters it starts from (``start``: the reduced
model's, in the loop's form: MuJoCo's solref, the others' stiffness and damping), how its answer
goes back into the parameters ``tune`` writes (``written``), what it names of the gap
(``shares``, ``bases``) and how the written file is dropped again (``measuring``, ``verify``).
"""

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from contactalpha.adapters.registry import model_files

from .engine_loop import LoopAnswer, base_of, explain, loop_notes, solve_damping
from .robot_files import FORMATS


@dataclass(frozen=True)
class EngineLoop:
    """An engine's loop as ``tune`` runs it.

    ``build(contact, params, timestep, base) -> PhaseSampler``; ``start(params) -> tuple``;
    ``written(params, answer params) -> params``; ``shares(loop, contact, timestep, base,
    answer) -> (engine_loop.Share, ...)``; ``bases(loop, contact, base) -> [line]``;
    ``measuring(result) -> PhaseSampler`` (on the written file); ``formats`` of the model files
    it drops (``robot_files.file_format``).
    """

    name: str
    build: Callable[..., Any]
    start: Callable[[dict], tuple]
    written: Callable[[dict, tuple], dict]
    shares: Callable[..., tuple]
    bases: Callable[..., list]
    measuring: Callable[[Any], Any]
    formats: tuple


def _mujoco_loop(contact, params, timestep, base=None):
    from .engine_loop import MujocoLoop
    from .writers import in_memory_mjcf

    c = contact
    return MujocoLoop(in_memory_mjcf(c, params), c.pair, c.qpos, c.qvel, timestep=timestep, forces=c.forces)


def _mujoco_measuring(result):
    from .engine_loop import MujocoLoop

    c = result.contact
    return MujocoLoop(str(result.output), c.pair, c.qpos, c.qvel, timestep=result.timestep, forces=c.forces)


def _mujoco_bases(loop, contact, base):
    from .mujoco_model import geom_id

    return [base_of(loop.model, geom_id(loop.model, g)) for g in contact.pair]


def _pybullet_loop(contact, params, timestep, base):
    from .mujoco_model import reader_joint_names
    from .pybullet_loop import PybulletLoop

    return PybulletLoop(contact.model, contact.pair, contact.qpos, contact.qvel, timestep=timestep,
                        joint_names=reader_joint_names(contact), forces=contact.forces,
                        speed=contact.approach_speed, base=base or "fixed")  # fmt: skip


def _drake_loop(contact, params, timestep, base):
    from .drake_loop import DrakeLoop

    return DrakeLoop(contact.model, contact.pair, contact.qpos, contact.qvel, timestep=timestep,
                     forces=contact.forces, base=base or "fixed")  # fmt: skip


def _drake_measuring(result):
    from .drake_loop import DrakeLoop

    c = result.contact
    return DrakeLoop(str(result.output), c.pair, c.qpos, c.qvel, timestep=result.timestep, forces=c.forces)


def _formats(engine):
    """The formats of the model files ``engine`` opens (its record's ``model_file``)."""
    return tuple(dict.fromkeys(FORMATS[s] for s in model_files()[engine].opens))


def _base_lines(loop, contact, base):
    return [_base_line(contact, base)]


LOOPS = {
    "mujoco": EngineLoop(
        "mujoco", _mujoco_loop, lambda p: tuple(p["solref"]), lambda p, x: {**p, "solref": x},
        lambda loop, c, h, base, answer: explain(loop, answer.reduced_solref, answer.reduced),
        _mujoco_bases, _mujoco_measuring, _formats("mujoco"),
    ),
    "pybullet": EngineLoop(
        "pybullet", _pybullet_loop,
        lambda p: (float(p["contactStiffness"]), float(p["contactDamping"])),
        lambda p, x: {**p, "contactDamping": float(x[1]), "pair_damping": 2.0 * float(x[1])},
        lambda loop, c, h, base, answer: _pybullet_shares(c, h, base, answer),
        _base_lines, lambda r: _pybullet_loop(r.contact, r.parameters, r.timestep, None),
        _formats("pybullet"),
    ),
    "drake": EngineLoop(
        "drake", _drake_loop,
        lambda p: (float(p["point_contact_stiffness"]), float(p["hunt_crossley_dissipation"])),
        lambda p, x: {**p, "hunt_crossley_dissipation": float(x[1]), "pair_dissipation": float(x[1])},
        lambda loop, c, h, base, answer: (), _base_lines, _drake_measuring, _formats("drake"),
    ),
}  # fmt: skip


def run_loop(engine: str, contact, params: dict, target: float, timestep: float,
             base: str | None = None) -> tuple[LoopAnswer, dict, list]:  # fmt: skip
    """``(LoopAnswer, the parameters to write, note lines)`` of ``engine``'s loop on ``contact``.

    ValueError where the pair is not at first touch (the drops start there) or the model file
    is not one the engine's loop drops.
    """
    rec = LOOPS[engine]
    if not contact.at_touch:
        raise ValueError(
            f"the engine loop starts its drops at first touch; the pair is {contact.gap:.3g} m apart at "
            "this configuration: give the configuration of touch (qpos)"
        )
    if contact.file_format not in rec.formats:
        raise ValueError(
            f"{engine}'s engine loop drops {'/'.join(f.upper() for f in rec.formats)} models, "
            f"not {contact.model!r}"
        )
    loop = rec.build(contact, params, timestep, base)
    try:
        answer = solve_damping(loop, target, rec.start(params))
    finally:
        close = getattr(loop, "close", None)
        if close is not None:
            close()
    out = rec.written(params, answer.solref) if answer.status == "ok" else params
    shares = rec.shares(loop, contact, timestep, base, answer) if math.isfinite(answer.reduced.mean) else ()
    lines = loop_notes(answer, shares, target, loop.timestep, rec.bases(loop, contact, base), loop.engine,
                       loop.damping_name)  # fmt: skip
    return answer, out, lines


# The parts PyBullet's loop can switch off (the loop's method, which says what there was).
PYBULLET_PARTS = (("friction", "switch_off_friction"), ("joint and link damping", "switch_off_damping"))


def _pybullet_shares(contact, timestep, base, answer):
    """``engine_loop.Share`` of each part PyBullet's loop can switch off, at the reduced answer."""
    from .engine_loop import Share

    out = []
    for name, method in PYBULLET_PARTS:
        loop = _pybullet_loop(contact, None, timestep, base)
        try:
            present = getattr(loop, method)()
            if present:
                pm = loop.phase_mean(answer.reduced_solref, answer.reduced.phases)
                out.append(Share(name, present, float(answer.reduced.mean - pm.mean)))
        finally:
            loop.close()
    return tuple(out)


def _base_line(contact, base):
    text = contact.engine_row.get("base")
    if text:
        return str(text)
    return f"{base or 'fixed'}: the URDF's root link fixed to the world (the same default in every engine)"


@dataclass(frozen=True)
class Verified:
    """The tuned model dropped in its engine at ``phases`` phases: mean, standard error, range.

    The phases are ``REPLICATES`` even grids, each shifted by a uniform draw (a randomized
    rectangle rule, unbiased for a uniform touchdown phase, none of them the loop's midpoints);
    ``stderr`` is the replicates' spread over sqrt(``REPLICATES``).
    """

    mean: float
    stderr: float
    minimum: float
    maximum: float
    phases: int


REPLICATES = 4


def engine_params(result) -> tuple:
    """The tuned parameters of ``result`` in its loop's form."""
    return LOOPS[result.engine].start(result.parameters)


def verify(result, phases: int, seed: int = 0) -> Verified:
    """``Verified``: ``result``'s tuned model dropped in its engine at ``phases`` touchdown phases."""
    import numpy as np

    if int(phases) < 2 * REPLICATES:
        raise ValueError(f"verify = {phases!r} phases must be at least {2 * REPLICATES}")
    if result.output is None:
        raise ValueError("verify drops the written file: nothing was written")
    loop = LOOPS[result.engine].measuring(result)
    params = engine_params(result)
    n = int(phases) // REPLICATES
    means, lo, hi = [], math.inf, -math.inf
    try:
        for shift in np.random.default_rng(seed).random(REPLICATES):
            grid = (np.arange(n) + shift) / n
            e = loop.values_at(params, grid)
            means.append(float(np.mean(e)))
            lo, hi = min(lo, float(np.min(e))), max(hi, float(np.max(e)))
    finally:
        if hasattr(loop, "close"):
            loop.close()
    m = np.array(means)
    return Verified(float(m.mean()), float(m.std(ddof=1) / math.sqrt(REPLICATES)), lo, hi, n * REPLICATES)


def verify_line(v: Verified, predicted: float, engine: str) -> str:
    """One line: the measured mean and range beside the predicted, with the sampling error."""
    return (f"verify ({engine}, the written file, {v.phases} touchdown phases on shifted grids): mean e_N "
            f"{v.mean:.6g} ± {v.stderr:.1g} (standard error), one drop {v.minimum:.6g} to {v.maximum:.6g}; "
            f"predicted {predicted:.6g} (measured − predicted {v.mean - predicted:+.2g})")  # fmt: skip
