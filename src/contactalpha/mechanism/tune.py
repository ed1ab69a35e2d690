"""From a robot model to tuned contact parameters: ``tune`` and ``contactalpha tune``.

``tune`` decides once what the file is and which engine tunes it (``model_kind``), reads the
pair's contact (``reading``: MuJoCo for MJCF, Drake for SDF or URDF, whichever is installed),
solves the engine's contact law for Newton's e_N at the contact's effective mass, load and
approach speed (``reduced``; MuJoCo's corrected for its own contact row, ``mujoco_row``), with
``engine_loop`` solves on the engine's own drops of the whole model (``on_engine``, ``loops``),
writes the parameters beside the model (``writers``) and, with ``check=True``, drops the tuned
model in the engine from the touchdown state.
"""

import math
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from contactalpha.adapters.mujoco_soft import IMPEDANCE
from contactalpha.validation import check_range

from . import write
from .drake_loop import DRAKE_STEP
from .drake_model import BASES
from .inputs import check_coordinates, check_model_size, check_timestep
from .loops import verify as verify_tuning
from .loops import verify_line
from .model_kind import model_kind
from .mujoco_row import current_stiffness
from .on_engine import checked, looped, refined, step_of
from .reading import reading
from .reduced import unreachable
from .robot_files import needs_preparing, prepared_urdf
from .touch import first_touch, joint_limit_problems, landing_check
from .tune_warnings import JointLimitWarning, OtherContactsWarning, UnmodelledSettingWarning


@dataclass(frozen=True)
class Tuning:
    """What ``tune`` found and wrote.

    ``contact`` (MechanismContact), ``engine``, ``parameters`` (the engine's names and units),
    ``notes`` (text lines), ``output`` (the written path or None), ``delivered`` (the e_N of the
    engine's own drop with ``check``, else NaN), ``mass_change`` (relative change of m_eff over
    that drop, NaN without one), ``details`` (the engine's derivation, e.g. ``MuJoCoTuning``),
    ``discrete`` (``discrete.DiscreteAnswer`` of the engine's step map, or None where no step
    was evaluated), ``timestep`` (the step of that answer and of the check, s; None: continuous),
    ``loop`` (``engine_loop.LoopAnswer`` of the engine loop, or None where it did not run),
    ``reached`` (False where no damping reaches the target: at the step, or in the engine loop)
    and ``unreachable`` (why, one line; "" where reached).
    """

    contact: object
    engine: str
    parameters: dict
    notes: list
    output: object = None
    delivered: float = math.nan
    mass_change: float = math.nan
    details: object = None
    drop: object = field(default=None, repr=False)
    discrete: object = None
    timestep: float | None = None
    loop: Any = None
    reached: bool = True
    unreachable: str = ""
    verified: Any = None


def default_output(model, engine=None):
    """``MODEL_tuned.xml`` (or .sdf, .urdf, .py) beside the model."""
    t = model_kind(model, engine).tuner
    suffix = Path(model).suffix if t.name == "drake" else t.suffix
    return Path(model).with_name(Path(model).stem + "_tuned" + suffix)


def tune(
    model, pair, e_n, *, speed=None, qvel=None, qpos=None, engine=None, stiffness=None, forces=None,
    impedance=IMPEDANCE, output=None, check=False, timestep=None, refine=False, discrete=None,
    engine_loop=False, force_write=False, base=None, ground=False, verify=None,
):  # fmt: skip
    """Parameters that give ``pair`` of ``model`` Newton's restitution ``e_n`` in ``engine``.

    Parameters
    ----------
    model : path of the MJCF, URDF or SDF file (never overwritten).
    pair : (geometry 1, geometry 2).
    e_n : target Newton's restitution, in (0, 1).
    speed, qvel : the approach (one of them): closing speed of the contact point (m/s), or joint
        velocities (the engine's coordinates).
    qpos : configuration at touchdown (default the model's).
    engine : "mujoco", "drake" or "pybullet" (default: the first installed engine that reads the
        file, ``robot_files.engine_for``: drake for SDF and for URDF whose meshes it reads, else
        mujoco; the choice is in ``notes``).
    stiffness : contact stiffness along the normal, N/m (MuJoCo's default: the model's own, seen
        through its contact row; required for the others).
    forces : {body: (fx, fy, fz)} constant forces, N, at bodies' centres of mass, world axes.
    impedance : MuJoCo's constant solimp d.
    output : path written (None: nothing written).
    check : drop the tuned model in the engine from touchdown and report the delivered e_N
        (MuJoCo also the effective mass's change).  Drake and PyBullet need ``output``; PyBullet
        drops the URDF with the written script (``pybullet_model.pybullet_drop``).
    timestep : the engine's step, s: the discrete answer's and the check's.  Default: MuJoCo's
        model step; PyBullet's 1/240 s; Drake's continuous plant (no step; give one for the
        discrete plant, e.g. its default 1e-3).
    discrete : None uses the phase-mean inverse of the engine's step map (``stepping``, at the
        contact's m_eff and load; ``discrete``) where the continuous answer's phase mean at the
        step misses the target by more than ``DISCRETE_TOL``; True always, False never.
    force_write : where no damping reaches the target (the step's answer is wanted and the map
        reaches none, or the engine loop reaches none) ``tune`` writes nothing and returns the
        answer with ``reached`` False and ``unreachable`` saying why; True writes it anyway.
    refine : MuJoCo: refine the law's damping ratio on the engine's own drop from touchdown
        (secant, to ``REFINE_TOL``) and write that; it absorbs what the first-order answer
        leaves out (the effective mass moving over the contact, the step).  Needs ``output``.
    engine_loop : solve the damping on the engine's own drops of the whole model at its step, over
        the touchdown phase, from the reduced model's answer (``engine_loop``; MuJoCo), and name
        what the reduced model leaves out with each part's share.  MuJoCo (``engine_loop``),
        PyBullet (a URDF, ``pybullet_loop``) and Drake (its discrete plant at ``timestep``,
        default ``drake_loop.DRAKE_STEP``; ``drake_loop``).  ``contactalpha tune`` runs it by
        default; here it is off, for callers that tune many contacts.
    base : a URDF's root link: "fixed" (default in every engine: welded to the world) or
        "floating" (Drake only; ``drake_model.BASES``).
    ground : add a floor to a URDF that has none (``robot_files.prepared_urdf``: a box link
        ``ground``, its top at z = 0, fixed to the root link).
    verify : drop the written file in its engine at this many touchdown phases (shifted grids,
        ``loops.verify``) and report the measured mean, its standard error and range beside the
        predicted (``Tuning.verified``).

    Returns
    -------
    Tuning

    Notes
    -----
    A URDF's unnamed ``<collision>`` elements are named ``LINK/collisionN`` (``robot_files``).
    A pair apart (or overlapping) at ``qpos`` is moved to first touch along the approach (the
    joint velocity), where the coordinates add (no free joint); otherwise refused.  A
    configuration outside a joint's limits warns (``JointLimitWarning``).
    """
    target = float(check_range("e_n", e_n, 0.0, 1.0, lo_open=True, hi_open=True))
    timestep = check_timestep(timestep)
    # What needs no engine is checked before one is chosen: a bad input is named even where none is installed.
    if Path(model).is_file():
        check_model_size(model)
    check_coordinates("qpos", qpos), check_coordinates("qvel", qvel)
    if output is not None:
        write.check_output(model, output)
    kind = model_kind(model, engine)
    t = kind.tuner
    if verify is not None and (int(verify) != verify or verify < 8):
        raise ValueError(f"verify = {verify!r} must be a whole number of phases >= 8")
    if verify is not None and output is None:
        raise ValueError("verify drops the written file: give output")
    chosen = []
    if kind.chosen:
        chosen.append(f"engine: {t.name} (not given: {kind.chosen})")
    if base is not None and base not in BASES:
        raise ValueError(f"base = {base!r} is outside the valid choices {BASES}")
    if base == "floating" and t.name != "drake":
        raise ValueError(f"base = 'floating': {t.name} loads a URDF with its root link fixed; a floating "
                         "robot is an MJCF with a <freejoint>, or Drake's (engine='drake')")  # fmt: skip
    if output is not None:
        write.check_output(model, output)
    if ground and kind.format != "urdf":
        raise ValueError(
            f"ground: adds a floor to a URDF; {str(model)!r} is not one (an MJCF or SDF adds its own)"
        )
    if ground and base == "floating":
        raise ValueError("ground with base = 'floating': the floor is fixed to the root link; fix the base")
    if needs_preparing(kind.format, pair, ground):
        model = prepared_urdf(model, ground)
        chosen.append(f"the model read: {model} (the URDF with its unnamed collisions named LINK/collisionN"
                      + (", a floor 'ground' added" if ground else "") + ")")  # fmt: skip
    if engine_loop and t.name == "drake" and timestep is None:
        timestep = DRAKE_STEP  # the loop runs Drake's discrete plant: its own default step
    read = reading(model, pair, reader=t.reader, qvel=qvel, speed=speed, forces=forces,
                   base=base if t.name == "drake" else None)  # fmt: skip
    contact = read(qpos)
    if not contact.at_touch:
        contact, moved = first_touch(read, contact)
        chosen.append(moved)
    for line in joint_limit_problems(contact, base):
        warnings.warn(line, JointLimitWarning, stacklevel=2)
        chosen.append(line)
    k_landing = stiffness if stiffness is not None else (
        current_stiffness(contact) if contact.engine == "mujoco" else None)  # fmt: skip
    landing = landing_check(contact, k_landing) if k_landing is not None else ""
    params, notes, details, step = t.solve(contact, target, stiffness, impedance, timestep, discrete)
    notes = [*chosen, *([landing] if landing else []), *notes]
    miss = unreachable(step, target, discrete)
    points = contact.engine_row.get("pair_points", 1)
    if points > 1:
        notes.append(
            f"the pair touches at {points} points at this configuration: one contact mode; the reduced "
            "model is one point's (its m_eff and MuJoCo's row); "
            + (
                "the engine loop solves the whole landing"
                if engine_loop
                else "engine_loop=True solves the whole landing"
            )  # fmt: skip
        )
    others = contact.engine_row.get("other_contacts", ())
    if others:
        loop = "the engine loop includes them" if engine_loop else "engine_loop=True includes them"
        text = f"other contacts active at this configuration: {', '.join(others)}; the reduced model leaves "
        text += f"them out ({loop})"
        notes.append(text)
        if not engine_loop:
            warnings.warn(text, OtherContactsWarning, stacklevel=2)
    h = step.timestep if step is not None else step_of(t.name, contact, timestep)
    result = Tuning(contact, t.name, params, notes, None, details=details, discrete=step, timestep=h,
                    reached=not miss, unreachable=miss)  # fmt: skip
    if engine_loop:
        result = looped(result, target, base)
    if result.loop is None or result.loop.status != "ok":  # the loop's drops include every setting
        for setting in contact.engine_row.get("unmodelled", ()) if t.name == "mujoco" else ():
            warnings.warn(f"MuJoCo model setting not in the answer: {setting}", UnmodelledSettingWarning,
                          stacklevel=2)  # fmt: skip
    if output is not None and (result.reached or force_write):
        result = replace(result, output=t.write(contact, output, result.parameters, result.notes))
    if refine:
        if t.name != "mujoco" or result.output is None:
            raise ValueError(
                "refine works with engine 'mujoco' and an output file"
                + ("" if result.reached else f" (nothing written: {result.unreachable})")
            )
        result = refined(result, target, timestep)
    if check and t.drop and (result.reached or result.output is not None or t.name == "mujoco"):
        result = checked(result, timestep, refined=refine)  # unreached and unwritten: nothing to drop
    if verify is not None and result.output is not None:
        v = verify_tuning(result, int(verify))
        predicted = result.loop.delivered.mean if result.loop is not None else target
        result = replace(result, verified=v, notes=[*result.notes, verify_line(v, predicted, t.name)])
    return result
