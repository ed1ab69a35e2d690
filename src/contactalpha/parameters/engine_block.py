"""One engine's parameters for one scene: ``contactalpha params --engine NAME``.

Every engine gets its block of ``contact_parameters(..., engine=NAME)``: its law's exact damping
at the scene's load in the engine's own names and units (one path, so the command line and Python
print the same numbers).  ``refine=True`` runs the engine's own drops at its default step and
refines the damping (``calibrate``), which needs the engine installed.
"""

import warnings

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import adapter
from contactalpha.adapters.registry import engine as engine_record
from contactalpha.scene.load import scene_accel
from contactalpha.validation import check_flag

from . import impulse
from .at_step import DEFAULT_STEP, EnergyGainWarning, at_step
from .front_door import contact_parameters
from .on_drops import answer_on_drops
from .reach import UnreachableTarget, unreachable_on_drops
from .result import as_plain_data, block_lines, stepped_lines

# Refinement outcomes that reached the target (``adapters.base.Refinement.status``).
REACHED = ("ok", "unchanged")


def engine_block(engine, target, mass, stiffness, approach_speed, accel=None, **options):
    """``(parameters, notes)`` of ``engine`` for the scene: ``engine_answer`` without the step's numbers."""
    return engine_answer(engine, target, mass, stiffness, approach_speed, accel, **options)[:2]


def engine_answer(engine, target, mass, stiffness, approach_speed, accel=None, *, force=None,
                  restitution="kinematic", radius=None, refine=False, timestep=None, verify=None,
                  progress=None):  # fmt: skip
    """``(parameters, notes, stepped)`` of ``engine`` for the scene; ``notes`` say how they were found.

    ``stepped`` is, with ``timestep``, the answer at the step as plain numbers (``SteppedAnswer``'s
    fields: the predicted ``mean``, ``minimum``, ``maximum``, ``steps_min``, ``steps_max``, ...),
    else None.

    Parameters
    ----------
    engine : str
        A registered engine (``adapters.registry.ENGINE_NAMES``).
    target : float
        Target restitution (``restitution``: "kinematic" e_N or "energetic" eps).
    mass, stiffness, approach_speed, accel : float
        kg, the engine law's physical stiffness (N/m^1.5 for n = 3/2, N/m for n = 1), m/s, m/s^2 (load).
    force : float, optional
        The load as a force, N, instead of ``accel`` (give exactly one).
    radius : float, optional
        Sphere radius, m.
    refine : bool
        Refine on the engine's own drops (stepping engines; needs the engine).
    timestep : float or "default", optional
        The engine's step: parameters for the mean over the touchdown phase at it (the notes give the
        predicted mean and range); ``verify`` N then runs the engine at N phases.
    progress : callable, optional
        Told of each drop of the refinement and of the scans for what would reach an unreachable
        target (``contactalpha.progress.Progress``).

    Raises
    ------
    parameters.reach.UnreachableTarget
        When the refinement finds no damping that delivers the target on the engine's drops: the
        message names the nearest e_N reached and the stiffness and step that would reach it.
    """
    a = adapter(engine)
    refine = check_flag("refine", refine)
    key = "e_N" if restitution == "kinematic" else "eps"
    if impulse.is_impulse(engine):  # answered at its step only, with its own lines
        if refine:
            raise ValueError(
                f"{engine} has no --refine: its answer is solved on its step map (--verify N checks it)"
            )
        cp = contact_parameters(mass=mass, stiffness=stiffness, approach_speed=approach_speed, accel=accel,
                                force=force, radius=radius, engine=engine, timestep=timestep, verify=verify,
                                **{key: target})  # fmt: skip
        return cp.block, impulse.impulse_lines(cp), as_plain_data(cp)["stepped"]
    if engine_record(engine).step_map is None and (timestep is not None or verify is not None):
        return answer_on_drops(a, target if key == "e_N" else _kinematic_only(engine), mass, stiffness,
                               approach_speed, accel, force, radius, refine, timestep, verify,
                               progress)  # fmt: skip
    if timestep is not None or verify is not None:
        if refine:
            raise ValueError("give --refine or --timestep, not both: the step's answer needs no engine run")
        with warnings.catch_warnings():  # the notes carry it (``result.stepped_lines``)
            warnings.simplefilter("ignore", EnergyGainWarning)
            cp = contact_parameters(mass=mass, stiffness=stiffness, approach_speed=approach_speed,
                                    accel=accel, force=force, radius=radius, engine=engine, timestep=timestep,
                                    verify=verify, **{key: target})  # fmt: skip
        ans = cp.stepped
        if ans.status != "ok":
            name = "e_N" if ans.restitution == "kinematic" else "eps"
            raise UnreachableTarget(
                f"no {engine} damping gives a mean {name} of {target!r} at its step {ans.timestep:.6g} s "
                f"({ans.status}): the nearest mean met is {ans.nearest:.6g}; the largest step found that "
                f"reaches the target is {ans.timestep_reachable:.6g} s"
                + (f" ({ans.search})" if ans.search else ""),
                ans.nearest,
                {"timestep": ans.timestep_reachable},
            )
        return cp.block, stepped_lines(ans), as_plain_data(cp)["stepped"]
    if not refine:
        cp = contact_parameters(mass=mass, stiffness=stiffness, approach_speed=approach_speed, accel=accel,
                                force=force, radius=radius, engine=engine, **{key: target})  # fmt: skip
        notes = [f"law {cp.law}: {cp.damping_name} = {cp.damping:.15g} at xi = {cp.xi:.15g} ({cp.source})"]
        step = a.timestep(a.settings)
        if step is not None:
            notes += _at_default_step(
                cp, engine, target, restitution, mass, stiffness, approach_speed, radius
            )
            notes.append(f"{engine} steps at {step:g} s: the block is the continuous law's; --timestep gives "
                         "the step's own, --refine refines it on the engine's drops")  # fmt: skip
        elif engine_record(engine).step_map is None and hasattr(a, "timestep_for"):
            notes.append(f"{engine}'s step follows each scene's contact time: the block is the continuous "
                         "law's; --timestep H refines it on the engine's drops at your step H, --verify N "
                         "checks it there at N touchdown phases")  # fmt: skip
        return cp.block, notes, None
    accel = scene_accel(mass, accel, force)
    scene = DropScene(mass, stiffness, approach_speed, accel, 0.0, 0.05 if radius is None else radius)
    params, ref, got = a.calibrate(scene, target, progress=progress)
    if ref.status not in REACHED:
        raise unreachable_on_drops(a, scene, target, ref, progress=progress)
    return (
        params,
        [
            f"law {a.law.name}: {a.law.damping} = {ref.start:.15g} (law), delivers {ref.e_n_start:.6g}",
            f"refined on {engine}'s drops: {a.law.damping} = {ref.damping:.15g}, delivers {got.e_n:.6g} "
            f"({ref.status}; spread over touchdown phases {got.spread:.3g}; {got.contact_steps} steps)",
        ],
        None,
    )


def _at_default_step(cp, engine, target, restitution, mass, stiffness, approach_speed, radius):
    """Lines of what ``cp``'s continuous block does at ``engine``'s default step (``stepped_lines``)."""
    scene = (float(mass), float(stiffness), float(approach_speed), float(cp.accel), radius)
    try:
        with warnings.catch_warnings():  # the lines carry it (``result.stepped_lines``)
            warnings.simplefilter("ignore", EnergyGainWarning)
            at = at_step(cp, engine, DEFAULT_STEP, *scene, target, restitution)
    except ValueError as exc:
        return [f"not checked at {engine}'s default step: {' '.join(str(exc).split())}"]
    return stepped_lines(at.stepped)


def format_block(engine, params, notes):
    """Aligned text lines of one engine's parameters (each with its unit) and notes."""
    return "\n".join(block_lines(engine, params) + [f"# {n}" for n in notes])


def _kinematic_only(engine):
    raise ValueError(
        f"{engine}'s drops are checked in Newton's e_N: give --e-n (not --eps) with --timestep or --verify"
    )
