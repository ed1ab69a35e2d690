"""``params --engine NAME --timestep h --verify N`` for an engine without a step map (LAMMPS).

An engine whose record has no ``step_map`` has no discrete answer to solve for: at a step the
user names (``timestep``) its answer is the damping refined on the engine's own drops at that
step (``adapter.calibrate``), and ``verify`` N drops it at N touchdown phases spread over one
step and reports the measured mean, minimum, maximum and the mean's sampling error
(``verify.phase_mean_error``), beside the target.  An engine that integrates with error control
(``adapter.timestep(settings) is None``) takes no ``timestep``; its ``verify`` is one drop.
"""

from dataclasses import fields, replace
from typing import Any

import numpy as np

from contactalpha.adapters.contract import DropScene
from contactalpha.scene.load import scene_accel
from contactalpha.validation import check_count, check_scalar

from .at_step import DEFAULT_STEP
from .reach import unreachable_on_drops
from .verify import VERIFY_PHASES, VERIFY_RADIUS, phase_mean_error

# A refinement's statuses that reached the target (``adapters.base.Adapter.calibrate``).
REACHED = ("ok", "unchanged")
# The refinement at a step: at least this many touchdown phases per drop, and this tolerance on the
# phase mean (an engine's default settings may hold fewer or a looser one, for a quick check).
REFINE_PHASES = 32
REFINE_TOL = 2e-4


def drop_settings(a: Any, timestep: float | None) -> Any:
    """``a``'s drop settings, at ``timestep`` (s) when given; ValueError where it takes none."""
    settings = a.settings
    if timestep is None:
        return settings
    h = check_scalar("timestep", timestep, 0.0, 1.0, lo_open=True)
    if (
        "timestep" not in {f.name for f in fields(settings)}
        or a.timestep(replace(settings, timestep=h)) is None
    ):
        raise ValueError(f"timestep = {timestep!r}: {a.name} integrates with error control and takes no step")
    return replace(settings, timestep=h)


def refine_settings(settings: Any) -> Any:
    """``settings`` with at least ``REFINE_PHASES`` phases and at most ``REFINE_TOL`` (where it has them)."""
    names = {f.name for f in fields(settings)}
    changes: dict[str, float] = {}
    if "phases" in names:
        changes["phases"] = max(int(settings.phases), REFINE_PHASES)
    if "tol" in names:
        changes["tol"] = min(float(settings.tol), REFINE_TOL)
    return replace(settings, **changes)


def answer_on_drops(a, target, mass, stiffness, approach_speed, accel, force, radius, refine, timestep,
                    verify, progress=None):  # fmt: skip
    """``(block, notes, numbers)`` of engine ``a`` without a step map: refined at ``timestep``, verified.

    ``refine`` (or a ``timestep``) refines the law's damping on the engine's drops at that step;
    otherwise the block is the continuous law's.  ``verify`` N (or None) drops the block at N phases.
    """
    settings = drop_settings(a, timestep)
    load = scene_accel(mass, accel, force)
    scene = DropScene(mass, stiffness, approach_speed, load, 0.0, VERIFY_RADIUS if radius is None else radius)
    step_for = getattr(a, "timestep_for", None)  # a step that follows the scene's contact time
    step = step_for(scene, settings) if step_for is not None else a.timestep(settings)
    if refine or timestep is not None:
        params, ref, got = a.calibrate(scene, target, settings=refine_settings(settings), progress=progress)
        if ref.status not in REACHED:
            raise unreachable_on_drops(a, scene, target, ref, progress=progress)
        damping = ref.damping
        notes = [
            f"law {a.law.name}: {a.law.damping} = {ref.start:.15g} (law), delivers {ref.e_n_start:.6g}",
            f"refined on {a.name}'s drops at {step:g} s: {a.law.damping} = {ref.damping:.15g}, delivers "
            f"{got.e_n:.6g} ({ref.status}; spread over touchdown phases {got.spread:.3g})",
        ]
    else:
        sol, xi = a.law_damping(scene, target, "kinematic", settings)
        if not sol.ok:
            raise ValueError(
                f"no {a.law.damping} gives e_N {target!r} at xi = {xi!r} in {a.law.name}: {sol.status}"
            )
        damping = float(sol.damping)
        params = a.parameters(damping, scene, settings)
        notes = [f"law {a.law.name}: {a.law.damping} = {damping:.15g} (the continuous law's block)"]
    numbers = None
    if verify is not None:
        numbers = verify_on_drops(
            a,
            scene,
            params,
            damping,
            VERIFY_PHASES if verify == DEFAULT_STEP else check_count("verify", verify, 1, 100_000),
            settings,
        )
        notes.append(
            f"verified on {a.name}'s drops at {numbers['phases']} touchdown phases"
            + (f" (step {step:g} s)" if step is not None else "")
            + f": mean e_N {numbers['mean']:.6g} (target {target:g}), range [{numbers['minimum']:.6g}, "
            f"{numbers['maximum']:.6g}], sampling error of the mean {numbers['sampling_error']:.2g}"
        )
    return params, notes, numbers


def verify_on_drops(a, scene, params, damping, phases, settings):
    """The engine's drops of ``params`` at ``phases`` touchdown phases: mean, range, sampling error."""
    if "phases" in {f.name for f in fields(settings)}:
        settings = replace(settings, phases=phases)
    samples = a.run(a.build_drop(scene, a.parameters(damping, scene, settings), settings), scene, settings)
    measured = a.measure(samples, scene)
    e = np.asarray(samples.extra.get("e_n_phases", [measured.e_n]), dtype=float)
    return {
        "phases": int(e.size), "mean": float(e.mean()), "minimum": float(e.min()),
        "maximum": float(e.max()), "sampling_error": phase_mean_error(e) if e.size > 1 else 0.0,
    }  # fmt: skip
