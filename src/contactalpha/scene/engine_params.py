"""One engine's parameters for one scene: ``contactalpha params --engine NAME``.

An engine whose law is the front door's (Hunt-Crossley, n = 3/2: OpenSim, Exudyn) gets its block
of ``contact_parameters``.  Any other registered engine gets its law's exact inverse at the scene's
load (``adapters.contract.law_damping``) in the engine's own names; ``refine=True`` then runs the
engine's own drops at its default step and refines the damping (``calibrate``), which needs the
engine installed.
"""

import math

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import adapter

from .parameters import LAW, contact_parameters


def engine_block(engine, target, mass, stiffness, approach_speed, accel, *, restitution="kinematic",
                 radius=None, refine=False, progress=None):  # fmt: skip
    """``(parameters, notes)`` of ``engine`` for the scene; ``notes`` are lines about how they were found.

    Parameters
    ----------
    engine : str
        A registered engine (``adapters.registry.ENGINE_NAMES``).
    target : float
        Target restitution (``restitution``: "kinematic" e_N or "energetic" eps).
    mass, stiffness, approach_speed, accel : float
        kg, the engine law's stiffness (N/m^1.5 for n = 3/2, N/m for n = 1), m/s, m/s^2 (the load).
    radius : float, optional
        Sphere radius, m.
    refine : bool
        Refine on the engine's own drops (stepping engines; needs the engine).
    progress : callable, optional
        Told of each drop of the refinement (``contactalpha.progress.Progress``).
    """
    a = adapter(engine)
    if a.law.name == LAW:
        key = "e_N" if restitution == "kinematic" else "eps"
        cp = contact_parameters(mass=mass, stiffness=stiffness, approach_speed=approach_speed, accel=accel,
                                radius=radius, **{key: target})  # fmt: skip
        return cp.engines[engine], [f"law {LAW}: alpha = {cp.alpha:.15g} at xi = {cp.xi:.15g}"]
    scene = DropScene(mass, stiffness, approach_speed, accel, 0.0, 0.05 if radius is None else radius)
    if refine:
        params, ref, got = a.calibrate(scene, target, progress=progress)
        return params, [
            f"law {a.law.name}: {a.law.damping} = {ref.start:.15g} (law), delivers {ref.e_n_start:.6g}",
            f"refined on {engine}'s drops: {a.law.damping} = {ref.damping:.15g}, delivers {got.e_n:.6g} "
            f"({ref.status}; spread over touchdown phases {got.spread:.3g}; {got.contact_steps} steps)",
        ]
    sol, xi = a.law_damping(scene, target, restitution)
    if not sol.ok:
        raise ValueError(f"no {a.law.damping} gives {restitution} {target!r} at xi = {xi!r}: {sol.status}")
    note = f"law {a.law.name}: {a.law.damping} = {float(sol.damping):.15g} at xi = {xi:.15g} (continuous)"
    step = a.timestep(a.settings)
    notes = (
        [note] if step is None else [note, f"{engine} steps at {step:g} s: run with refine for its own e_N"]
    )
    return a.parameters(float(sol.damping), scene), notes


def format_block(engine, params, notes):
    """Aligned text lines of one engine's parameters and notes."""
    lines = []
    for name, value in params.items():
        values = value if isinstance(value, tuple) else (value,)
        shown = ", ".join("nan" if isinstance(v, float) and math.isnan(v) else f"{v:.15g}" for v in values)
        lines.append(f"{engine + '.' + name:32s} {shown}")
    return "\n".join(lines + [f"# {n}" for n in notes])
