"""From a robot model to tuned contact parameters: ``tune`` and ``contactalpha tune``.

``tune`` reads the pair's contact from the model (``read_contact``: MuJoCo for MJCF, Drake for SDF
or URDF, whichever is installed), solves the engine's contact law for Newton's e_N at the
contact's effective mass, load and approach speed (``adapters``' ``law_damping``, the law's exact
inverse), corrects MuJoCo's parameters for its own contact row (``mujoco_row``), writes them
beside the model (``write``) and, with ``check=True``, drops the tuned model in the engine from
the touchdown state: the delivered e_N, and how much the effective mass moves over the contact
(a warning above ``MASS_CHANGE_WARN``).
"""

import importlib.util
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from contactalpha.adapters.base import refine as secant
from contactalpha.adapters.mujoco_soft import IMPEDANCE
from contactalpha.adapters.record import Tuner
from contactalpha.adapters.registry import adapter, model_readers, tuners
from contactalpha.parameters.block_scene import BlockScene
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_range

from . import write
from .discrete import ENGINE_STEPS, step_answer
from .drake_loop import DRAKE_STEP
from .drake_model import BASES, drake_drop
from .engine_loop import in_engine
from .inputs import check_coordinates, check_model_size, check_step_resolves, check_timestep
from .loops import LOOPS, run_loop, verify_line
from .loops import verify as verify_tuning
from .mujoco_model import load_model, mujoco_drop, reader_joint_names
from .mujoco_row import DISCRETE_TOL, current_stiffness, discrete_answer, law_scene, mujoco_tuning, solref_for
from .pybullet_model import collision_links, pybullet_drop
from .robot_files import engine_for, needs_preparing, prepared_urdf
from .touch import first_touch, joint_limit_problems, landing_check

# Relative change of the effective mass over the contact above which ``tune`` warns: the law is
# solved at touchdown's m_eff, and the load factor and MuJoCo's effective impedance move with it.
MASS_CHANGE_WARN = 0.01
# Gap samples per undamped contact time in a Drake check.
DRAKE_SAMPLES = 1000
# |delivered - target| at which refining on the engine's drop stops.
REFINE_TOL = 2e-4


class OtherContactsWarning(UserWarning):
    """Contacts other than the pair's are active at the configuration: the reduced model leaves them out."""


class MassChangeWarning(UserWarning):
    """The effective mass moves by more than ``MASS_CHANGE_WARN`` over the engine's contact."""


class JointLimitWarning(UserWarning):
    """The configuration has a joint outside its limits."""


class UnmodelledSettingWarning(UserWarning):
    """A setting of the MuJoCo model changes the contact's e_N and the answer leaves it out.

    Not given where the engine loop reached the target: its drops run the whole model.
    """


@dataclass(frozen=True)
class Reader:
    """A model reader: ``name``, the Python ``module`` it needs, file ``suffixes``, ``read`` call."""

    name: str
    module: str
    suffixes: tuple
    read: Callable[..., Any]


# The engines' model-file readers, from their records (``adapters.registry``).
READERS = tuple(Reader(name, *reader) for name, reader in model_readers().items())


def read_contact(model, pair, *, reader=None, qpos=None, qvel=None, speed=None, forces=None, base=None):
    """``MechanismContact`` of ``pair`` in ``model`` read by ``reader`` (default: the first that reads it).

    Parameters
    ----------
    model : path of an MJCF, URDF or SDF file.
    pair : (geometry 1, geometry 2) names; the normal points from 1 to 2.
    reader : "mujoco" or "drake" (``READERS``), or None.
    qpos : joint positions (the engine's coordinates; default the model's own).
    qvel, speed : the approach: joint velocities, or the closing speed of the contact point, m/s.
    forces : {body: (fx, fy, fz)} constant forces at bodies' centres of mass, N, world axes.
    base : Drake: "fixed" (default: a URDF's root link welded to the world, as MuJoCo and PyBullet
        load it) or "floating" (``drake_model.BASES``).
    """
    path = Path(model)
    if not path.is_file():
        raise ValueError(f"model = {str(model)!r} is not a file")
    check_model_size(path)
    qpos, qvel = check_coordinates("qpos", qpos), check_coordinates("qvel", qvel)
    pair = tuple(str(g) for g in pair)
    if len(pair) != 2:
        raise ValueError(f"pair = {pair!r} must name two geometries")
    names = tuple(r.name for r in READERS)
    if reader is not None and reader not in names:
        raise ValueError(f"reader = {reader!r} is outside the valid choices {names}")
    fits = [r for r in READERS if (reader is None or r.name == reader) and path.suffix.lower() in r.suffixes]
    if not fits:
        raise ValueError(
            f"model = {str(model)!r}: no reader for {path.suffix!r} files "
            "(mujoco: MJCF/URDF, drake: SDF/URDF)"
        )
    ready = [r for r in fits if importlib.util.find_spec(r.module) is not None]
    if not ready:
        raise ImportError(f"reading {path.suffix} models needs {' or '.join(r.module for r in fits)}")
    extra = {}
    if base is not None:
        if ready[0].name != "drake":
            raise ValueError(f"base = {base!r}: MuJoCo fixes a URDF's root link (an MJCF says its own base "
                             "with a <freejoint>); base chooses Drake's")  # fmt: skip
        extra["base"] = base
    return ready[0].read(path, pair, qpos=qpos, qvel=qvel, speed=speed, forces=forces, **extra)


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


def _mujoco_tune(contact, target, stiffness, impedance, timestep, discrete):
    k = current_stiffness(contact) if stiffness is None else stiffness
    t = mujoco_tuning(contact, target, k, impedance)
    h = contact.engine_row["timestep"] if timestep is None else float(timestep)
    named = "the model's timestep" if timestep is None else "timestep"
    check_step_resolves(h, contact.effective_mass, k, named)
    step = discrete_answer(contact, t, target, h) if discrete is not False else None
    row = contact.engine_row
    params = {"solref": t.solref, "solimp": t.solimp, "condim": (row["condim"],),
              "friction": row["friction"], "margin": (row["geom_margin"],),
              "gap": (row["geom_gap"],)}  # fmt: skip
    notes = [
        f"stiffness {k:.9g} N/m along the normal" + (" (the model's own)" if stiffness is None else ""),
        f"MuJoCo's row: diagA = {row['diagA']:.9g} where J M^-1 J^T = {1 / contact.effective_mass:.9g}; "
        f"solimp d = {t.impedance:.6g} acts as d_e = {t.effective_impedance:.9g}",
        f"law mujoco_soft at d_e: zeta = {t.zeta:.12g}, xi = {t.xi:.9g}",
        f"free-body mapping (exact only where diagA = J M^-1 J^T): solref = "
        f"({t.free_body['solref'][0]:.9g}, {t.free_body['solref'][1]:.9g})",
    ]
    if step is not None:
        use, lines = _step_notes("MuJoCo", step, target, discrete, f"solref[1] = {-step.inverse.damping:.9g}")
        notes += lines
        if use:
            params["solref"] = (t.solref[0], -step.inverse.damping)
    elif discrete is not False:
        notes.append(
            "MuJoCo's step map does not apply (no pressing load, or its integrator): continuous answer"
        )
    if row["condim"] > 1:
        pyramid = (f"; the {row['cone']} cone's {row['rows']} edge rows act on the normal as one row "
                   f"with their R over {row['rows']}" if row.get("rows", 1) > 1 else "")  # fmt: skip
        notes.append(
            f"condim {row['condim']}{pyramid}: exact for a contact whose tangential motion is decoupled "
            "from the normal and that does not slide; friction coupled to the normal (a contact point "
            "off the line of the normal's action) changes e_N: check with a drop"
        )
    return params, notes, (t if step is None else replace(t, discrete=step)), step


def _step_notes(engine, step, target, discrete, written):
    """``(use, notes)``: whether the step's phase-mean inverse replaces the continuous answer.

    It does where the continuous answer's phase mean at the step misses ``target`` by more than
    ``DISCRETE_TOL`` (``discrete`` None), always (True), and only where the inverse reached it.
    """
    st, inv = step.continuous, step.inverse
    notes = [
        f"at {engine}'s step {step.timestep:g} s the law's answer delivers a phase mean {st.mean:.6g} "
        f"(one drop: {st.minimum:.6g} to {st.maximum:.6g}; {st.steps_min}-{st.steps_max} steps)"
    ]
    use = _wants_step(step, target, discrete)
    if use and inv.status == "ok":
        notes.append(
            f"discrete answer (phase-mean inverse of {engine}'s step at m_eff): {written}; "
            f"one drop sees {inv.stats.minimum:.6g} to {inv.stats.maximum:.6g}"
        )
        return True, notes
    if use:
        notes.append(
            f"no damping reaches e_N {target} at this step ({inv.status}; nearest phase mean "
            f"{inv.nearest:.6g}); largest step that reaches it: {inv.timestep_reachable:.3g} s"
        )
    return False, notes


def _wants_step(step, target, discrete):
    """Whether the step's answer is wanted: always (``discrete`` True), or where the law's misses."""
    return discrete is True or abs(step.continuous.mean - target) > DISCRETE_TOL


def _unreachable(step, target, discrete):
    """Why no damping reaches the target at the step where its answer is wanted (one line), else ""."""
    if step is None or not _wants_step(step, target, discrete) or step.inverse.status == "ok":
        return ""
    inv = step.inverse
    return (f"no damping reaches e_N {target} at {step.engine}'s step {step.timestep:g} s ({inv.status}; "
            f"nearest phase mean {inv.nearest:.6g}); largest step that reaches it: "
            f"{inv.timestep_reachable:.3g} s")  # fmt: skip


def _write_mujoco(contact, output, params):
    attrs = {name: value for name, value in params.items()}
    attrs["condim"] = str(int(params["condim"][0]))
    compiled = None
    if Path(contact.model).suffix.lower() == ".urdf":
        compiled = _compiled_mjcf(contact.model, output)
    return write.write_mjcf(contact.model, output, contact.pair, attrs, compiled_xml=compiled,
                            stamp=_stamp(contact))  # fmt: skip


def _compiled_mjcf(model, output):
    import mujoco

    m = load_model(model)
    tmp = Path(output).with_suffix(".compiled.tmp.xml")
    try:
        mujoco.mj_saveLastXML(str(tmp), m)
        return tmp.read_text()
    finally:
        tmp.unlink(missing_ok=True)


def _front_door(contact, target, stiffness, engine):
    """The engine's block of ``contact_parameters`` at the contact's m_eff, load and speed."""
    scene = law_scene(contact, _need(stiffness, engine))
    cp = contact_parameters(
        e_N=target, mass=scene.mass, stiffness=scene.stiffness, approach_speed=scene.approach_speed,
        accel=scene.accel, engine=engine,
    )  # fmt: skip
    return cp, cp.engines[engine]


def _drake_tune(contact, target, stiffness, impedance, timestep, discrete):
    cp, params = _front_door(contact, target, stiffness, "drake")
    notes = [f"law {cp.law}: alpha = {cp.damping:.12g} at xi = {cp.xi:.9g}; each geometry gets 2k "
             "and d (Drake combines k1 k2/(k1 + k2), (k2 d1 + k1 d2)/(k1 + k2))"]  # fmt: skip
    return _engine_step(contact, "drake", cp, params, notes, target, timestep, discrete)


def _engine_step(contact, engine, cp, params, notes, target, timestep, discrete):
    """The step's answer for Drake's discrete plant or PyBullet: its map at the contact's m_eff and load.

    ``timestep`` None is the engine's ``discrete.ENGINE_STEPS`` default (None for Drake: its
    continuous plant, no step).  Returns ``(params, notes, cp, step)`` with the block rebuilt from the
    inverse's damping where ``_step_notes`` uses it.
    """
    es = ENGINE_STEPS[engine]
    h = es.default_step if timestep is None else float(timestep)
    if h is None or discrete is False:
        return params, notes, cp, None
    check_step_resolves(h, contact.effective_mass, float(params["pair_stiffness"]))
    if contact.accel <= 0.0:
        notes.append(f"{engine}'s step map needs a pressing load: the continuous answer is kept")
        return params, notes, cp, None
    s = stepper(engine)
    step = step_answer(engine, es.parameters(params, contact), contact, target, h)
    use, lines = _step_notes(
        engine, step, target, discrete, f"{es.damping} = {step.inverse.damping:.9g} each"
    )
    lines.append(es.note)
    if use:
        assert s.law_damping is not None  # every stepper tune reaches has its law's damping
        zeta = float(s.law_damping(step.inverse.p, contact.approach_speed))
        a = adapter(engine)
        settings = replace(a.settings, **{s.step_setting: h})
        k = float(params["pair_stiffness"])
        scene = BlockScene(contact.effective_mass, k, contact.approach_speed, None)
        params = a.parameters(zeta, scene, settings)
    return params, notes + lines, cp, step


def _write_drake(contact, output, params):
    keep = {k: params[k] for k in ("point_contact_stiffness", "hunt_crossley_dissipation")}
    return write.write_drake(contact.model, output, contact.pair, keep, stamp=_stamp(contact))


def _stamp(contact):
    return f"tune of {Path(contact.model).name}, pair {contact.pair[0]} / {contact.pair[1]}"


def _pybullet_tune(contact, target, stiffness, impedance, timestep, discrete):
    cp, params = _front_door(contact, target, stiffness, "pybullet")
    notes = [f"law {cp.law}: zeta = {cp.damping:.12g} at xi = {cp.xi:.9g} (continuous law at m_eff)"]
    return _engine_step(contact, "pybullet", cp, params, notes, target, timestep, discrete)


def _write_pybullet(contact, output, params, notes):
    urdf = Path(contact.model).suffix.lower() == ".urdf"
    links = collision_links(contact.model, contact.pair) if urdf else (None, None)
    return write.write_pybullet(contact.model, output, contact.pair, params, notes, links)


def _need(stiffness, engine):
    if stiffness is None:
        raise ValueError(f"engine {engine!r} needs the contact stiffness: give stiffness (N/m)")
    return float(check_range("stiffness", stiffness, 0.0, math.inf, lo_open=True, hi_open=True))


# The engines' tuners: their records (``adapters.registry``) name these.
MUJOCO_TUNER = Tuner(
    "mujoco", "mujoco", ".xml", _mujoco_tune, lambda c, o, p, n: _write_mujoco(c, o, p), True
)
DRAKE_TUNER = Tuner("drake", "drake", ".sdf", _drake_tune, lambda c, o, p, n: _write_drake(c, o, p), True)
PYBULLET_TUNER = Tuner("pybullet", None, ".py", _pybullet_tune, _write_pybullet, True)
TUNERS = tuple(tuners().values())
TUNER_NAMES = tuple(t.name for t in TUNERS)


def _tuner(engine, model):
    if engine is None:
        if Path(model).is_file():
            check_model_size(model)  # named before the engine that would read it is looked for
        engine = engine_for(model)[0] if Path(model).is_file() else _by_suffix(model)
    for t in TUNERS:
        if t.name == engine:
            return t
    raise ValueError(f"engine = {engine!r} is outside the valid choices {TUNER_NAMES}")


def _by_suffix(model):
    return "drake" if Path(model).suffix.lower() in (".sdf", ".urdf") else "mujoco"


def default_output(model, engine=None):
    """``MODEL_tuned.xml`` (or .sdf, .urdf, .py) beside the model."""
    t = _tuner(engine, model)
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
    t = _tuner(engine, model)
    if verify is not None and (int(verify) != verify or verify < 8):
        raise ValueError(f"verify = {verify!r} must be a whole number of phases >= 8")
    if verify is not None and output is None:
        raise ValueError("verify drops the written file: give output")
    chosen = []
    if engine is None and Path(model).is_file():
        why = engine_for(model)[1]
        chosen.append(f"engine: {t.name} (not given: {why})")
    if base is not None and base not in BASES:
        raise ValueError(f"base = {base!r} is outside the valid choices {BASES}")
    if base == "floating" and t.name != "drake":
        raise ValueError(f"base = 'floating': {t.name} loads a URDF with its root link fixed; a floating "
                         "robot is an MJCF with a <freejoint>, or Drake's (engine='drake')")  # fmt: skip
    if output is not None:
        write.check_output(model, output)
    if ground and Path(model).suffix.lower() != ".urdf":
        raise ValueError(
            f"ground: adds a floor to a URDF; {str(model)!r} is not one (an MJCF or SDF adds its own)"
        )
    if ground and base == "floating":
        raise ValueError("ground with base = 'floating': the floor is fixed to the root link; fix the base")
    if needs_preparing(model, pair, ground):
        model = prepared_urdf(model, ground)
        chosen.append(f"the model read: {model} (the URDF with its unnamed collisions named LINK/collisionN"
                      + (", a floor 'ground' added" if ground else "") + ")")  # fmt: skip
    if engine_loop and t.name == "drake" and timestep is None:
        timestep = DRAKE_STEP  # the loop runs Drake's discrete plant: its own default step
    reader = t.reader if t.reader is not None else None

    def read(q):
        return read_contact(model, pair, reader=reader, qpos=q, qvel=qvel, speed=speed, forces=forces,
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
    miss = _unreachable(step, target, discrete)
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
    h = step.timestep if step is not None else _step_of(t.name, contact, timestep)
    result = Tuning(contact, t.name, params, notes, None, details=details, discrete=step, timestep=h,
                    reached=not miss, unreachable=miss)  # fmt: skip
    if engine_loop:
        result = _looped(result, target, base)
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
        result = _refined(result, target, timestep)
    if check and t.drop and (result.reached or result.output is not None or t.name == "mujoco"):
        result = _checked(result, timestep, refined=refine)  # unreached and unwritten: nothing to drop
    if verify is not None and result.output is not None:
        v = verify_tuning(result, int(verify))
        predicted = result.loop.delivered.mean if result.loop is not None else target
        result = replace(result, verified=v, notes=[*result.notes, verify_line(v, predicted, t.name)])
    return result


def _looped(result, target, base=None):
    """``result`` with the engine loop's answer, run in memory: ``tune`` writes the file after."""
    if result.engine in LOOPS:
        answer, params, lines = run_loop(result.engine, result.contact, result.parameters, target,
                                         result.timestep, base)  # fmt: skip
        ok = answer.status == "ok"
        why = "" if ok else f"the engine loop did not reach e_N {target:g} ({answer.status})"
        return replace(result, parameters=params, notes=[*result.notes, *lines], loop=answer, reached=ok,
                       unreachable=why)  # fmt: skip
    if result.engine != "mujoco":  # an engine with no loop of its own (a toy's): the reduced answer
        return replace(
            result, notes=[*result.notes, f"{result.engine} has no engine loop: the reduced model's answer"]
        )
    source = _in_memory_mjcf(result)
    answer, _, lines = in_engine(source, result.contact, result.parameters["solref"], target, result.timestep)
    params = result.parameters
    ok = answer.status == "ok"
    if ok:
        params = {**params, "solref": answer.solref}
    why = "" if ok else f"the engine loop did not reach e_N {target:g} ({answer.status})"
    return replace(result, parameters=params, notes=[*result.notes, *lines], loop=answer, reached=ok,
                   unreachable=why)  # fmt: skip


def _refined(result, target, timestep):
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
    _write_mujoco(c, result.output, params)
    notes = [*result.notes, f"refined on MuJoCo's drop from touchdown: zeta {tuning.zeta:.9g} -> "
             f"{ref.damping:.9g} ({ref.status}; the law's value delivered {ref.e_n_start:.6g})"]  # fmt: skip
    return replace(result, parameters=params, notes=notes)


def _checked(result, timestep, refined=False):
    c = result.contact
    if result.engine == "mujoco":
        source = result.output if result.output is not None else _in_memory_mjcf(result)
        drop = mujoco_drop(source, c.pair, c.qpos, c.qvel, timestep=timestep, forces=c.forces)
    elif result.output is None:
        raise ValueError(f"check with engine {result.engine!r} needs output (the tuned model or script)")
    elif result.engine == "pybullet":
        if Path(c.model).suffix.lower() != ".urdf":
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


def _step_of(engine, contact, timestep):
    """The step ``tune`` works at when no step map ran: MuJoCo's model step, the engines' defaults."""
    if timestep is not None:
        return float(timestep)
    if engine in ENGINE_STEPS:
        return ENGINE_STEPS[engine].default_step
    return float(contact.engine_row["timestep"])  # MuJoCo: the model's


def _in_memory_mjcf(result):
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / ("tuned" + Path(result.contact.model).suffix.replace(".urdf", ".xml"))
        _write_mujoco(result.contact, out, result.parameters)
        return out.read_text()
