"""The one answer of the front door: ``ContactParameters``, for every law, one scene or many.

``contact_parameters`` returns this class whatever the law, the engine and the input's shape.

**One scene or a batch.**  A call with plain numbers gives plain Python values in every field
(``float``, ``str``, ``bool``); a call with any array input gives numpy arrays of the scenes'
broadcast shape in every per-scene field (``xi``, ``damping``, ..., ``ok``, ``reason``, and every
number in ``engines``; MuJoCo's ``solref`` and ``solimp``, one scene's tuples, are arrays of shape
``(*batch, 2)`` and ``(*batch, 5)``, a row per world, as MJX and MuJoCo Warp take them).  ``law``,
``damping_name``, ``physical_unit`` and ``engine`` are one string for the whole call.

**Units.**  The stiffness given is physical on every path: N/m for the n = 1 laws, N/m^1.5 for
the Hertz laws (``ContactLaw.stiffness_unit``).  Engine-specific units (MuJoCo's per-unit-mass
``solref``) appear only inside that engine's block of ``engines``.

**No answer.**  One scene whose target no damping reaches raises (the message says why); in a
batch such a row gets NaN in every number, ``ok = False`` and the reason, and the other rows are
what a batch without it gives.
"""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from contactalpha.adapters.registry import adapter
from contactalpha.laws import get_law
from contactalpha.stepping.registry import stepper


class NoSeparationWarning(UserWarning):
    """The target is met with the bodies staying in contact: no rebound at this load."""


def no_separation_note(cp):
    """Why one scene's answer has no rebound ("" when the bodies separate)."""
    if cp.end_state == "separation":
        return ""
    return (
        f"the bodies will not separate: at this load (xi = {cp.xi:.6g}) the target is met with the bodies "
        f"staying in contact (end state {cp.end_state}, e_N = {cp.e_n:.6g}); a rebound needs a smaller "
        "load, a faster approach or a larger target"
    )


class Deferred:
    """A field's value computed on first read (then kept): a batch's integrated restitutions.

    A batch's damping comes from a table at millions of scenes a second; integrating every row's
    impact (its restitutions, end state and the e_N at half and twice the speed) costs about a
    thousand times more, so a batch computes those fields only when they are read.
    """

    __slots__ = ("compute",)

    def __init__(self, compute):
        self.compute = compute


@dataclass(frozen=True)
class ContactParameters:
    """Everything ``contact_parameters`` derives for one contact or a batch of them (SI units).

    Fields mean the same for every law; for a batch each per-scene field is an array.

    Attributes
    ----------
    law : name of the contact law (``contactalpha.laws.LAWS``).
    xi : load factor of the scene (``ContactLaw.load_factor``; the paper's influence factor
        for Hunt-Crossley), in [0, 1).
    damping_name : name of the law's dimensionless damping: "alpha", "zeta" or "beta".
    damping : the law's dimensionless damping that delivers the target restitution.
    physical_damping : the law's physical damping coefficient (``ContactLaw.physical_damping``
        with the physical mass and stiffness; ``ContactLaw.damping_physical`` says which), in
        ``physical_unit``: d = alpha / v_minus (s/m) for both Hunt-Crossley laws, c = 2 zeta
        sqrt(k m) (N s/m) for the spring-dashpots, eta = beta sqrt(m k) (N s/m^1.25) for Tsuji.
    physical_unit : the unit of ``physical_damping``.
    eps, e_n : Stronge's energetic and Newton's kinematic restitution that ``damping`` delivers
        (one impact integrated; the requested one to the evaluator's accuracy).
    end_state : how that impact ends: separation, nonseparation, creep, no_restitution.
    ok : True where the scene has an answer (a single scene without one raises instead).
    reason : why a scene has no answer ("" where ``ok``).
    accel : relative acceleration of the load, m/s^2.
    delta_star : the law's length scale (undamped, unloaded maximum compression), m.
    source : where ``damping`` comes from: "table" (a shipped table), "closed form" or "solver".
    engines : ``{engine: {parameter: value}}`` for every registered engine of the law, keyed by
        the engine ("opensim", "exudyn", "mujoco", "drake", "pybullet"), each block in that
        engine's own names and units (per geometry for a pair, as ``adapters`` document).
    e_n_half_speed, e_n_twice_speed : Newton's e_N that the same ``physical_damping`` delivers at
        half and at twice the approach speed (NaN where the load's xi rounds to 1 there): the
        engine's constant holds at this approach speed only.
    engine : the engine asked for (``contact_parameters(..., engine=NAME)``), else None.
    stepped : with ``timestep=``, what the engine delivers at its step over a uniformly random
        touchdown phase (``parameters.at_step.SteppedAnswer``; ``engines[engine]`` then holds the
        parameters for the phase mean), else None.
    """

    law: str
    xi: float | np.ndarray
    damping_name: str
    damping: float | np.ndarray
    physical_damping: float | np.ndarray
    physical_unit: str
    eps: float | np.ndarray
    e_n: float | np.ndarray
    end_state: object
    ok: object
    reason: object
    accel: float | np.ndarray
    delta_star: float | np.ndarray
    source: object
    engines: dict
    e_n_half_speed: float | np.ndarray
    e_n_twice_speed: float | np.ndarray
    engine: str | None = None
    stepped: Any = None  # parameters.at_step.SteppedAnswer or None (at_step imports this module)

    def __getattribute__(self, name):
        value = object.__getattribute__(self, name)
        if type(value) is Deferred:
            value = value.compute()
            object.__setattr__(self, name, value)
        return value

    def replaced(self, **changes):
        """A copy with ``changes`` (``dataclasses.replace`` would compute every deferred field)."""
        from dataclasses import fields

        values = {f.name: object.__getattribute__(self, f.name) for f in fields(self)}
        return ContactParameters(**{**values, **changes})

    @property
    def block(self):
        """The asked engine's block (``engines[engine]``); ValueError when no engine was asked for."""
        if self.engine is None:
            raise ValueError("no engine was asked for: give contact_parameters(..., engine=NAME)")
        return self.engines[self.engine]


def format_parameters(cp: ContactParameters) -> str:
    """One scene's ``ContactParameters`` as aligned text lines, every number with its unit."""
    law = get_law(cp.law)
    lines = [
        f"law             {law.name}: {law.formula}",
        f"xi              {cp.xi:.15g}   (load factor)",
        f"{cp.damping_name:15s} {cp.damping:.15g}   ({cp.source}; dimensionless)",
        f"damping         {cp.physical_damping:.15g} {cp.physical_unit}   ({law.damping_physical})",
        f"end state       {cp.end_state}"
        + ("   (no rebound: the bodies will not separate)" if no_separation_note(cp) else ""),
        f"eps             {cp.eps:.15g}",
        f"e_N             {cp.e_n:.15g}",
        f"accel           {cp.accel:.15g} m/s^2",
        f"delta_star      {cp.delta_star:.15g} m",
        f"the same damping delivers e_N = {cp.e_n_half_speed:.6g} at half and {cp.e_n_twice_speed:.6g} at "
        "twice this approach speed: it holds at this speed only",
    ]
    for engine, values in cp.engines.items():
        lines.extend(block_lines(engine, values))
        lines.extend(f"  {line}" for line in adapter(engine).unit_notes)
    if cp.stepped is not None:
        lines.extend(stepped_lines(cp.stepped))
    return "\n".join(lines)


def gain_note(ans):
    """The warning where one drop of the answer ``ans`` can leave faster than it came, else None.

    The mean over the phase is the target, but at some touchdown phases the step adds energy (a
    heavy load at a coarse step: MuJoCo's soft contact, for one, carries only (1 - d) of it); a
    batch's answer names how many rows do.
    """
    over = (np.asarray(ans.status) == "ok") & (np.asarray(ans.maximum, dtype=float) > 1.0)
    if not over.any():
        return None
    name = "e_N" if ans.restitution == "kinematic" else "eps"
    worst = float(np.max(np.asarray(ans.maximum, dtype=float)[over]))
    rows = f" in {int(over.sum())} of {over.size} rows" if np.ndim(ans.maximum) else ""
    return (f"a single drop can leave faster than it came{rows}: {name} up to {worst:.4g} > 1 "
            f"at some touchdown phases (the step adds energy there); the mean over random phases is the "
            f"target, and a smaller step narrows the range")  # fmt: skip


def stepped_lines(ans):
    """Text lines of a ``parameters.at_step.SteppedAnswer`` for ``format_parameters``."""
    name = "e_N" if ans.restitution == "kinematic" else "eps"
    lines = [
        f"at {ans.engine}'s step {ans.timestep:.6g} s, over a uniformly random touchdown phase "
        f"(drops read at {stepper(ans.engine).read_at}):"
    ]
    if ans.status == "ok":
        lines += [
            f"  {ans.engine} damping   {ans.damping:.15g}   (its own parameter; zeta {ans.law_damping:.15g})",
            f"  mean {name}      {ans.mean:.15g}   (target {ans.target:.15g})",
            f"  one drop        {ans.minimum:.6g} to {ans.maximum:.6g}   (std {ans.std:.3g}; "
            f"{ans.steps_min}-{ans.steps_max} steps in contact)",
        ]
        note = gain_note(ans)
        if note is not None:
            lines.append(f"  warning: {note}")
    else:
        lines += [
            f"  {ans.status}: no damping delivers it; the nearest mean {name} met is {ans.nearest:.6g}",
            f"  the largest step found that reaches the target: {ans.timestep_reachable:.6g} s"
            + (f" ({ans.search})" if ans.search else ""),
            "  (the block above is the continuous law's)",
        ]
    lines.append(
        f"  the continuous law's parameters would deliver {ans.continuous_mean:.6g} "
        f"({ans.continuous_minimum:.6g} to {ans.continuous_maximum:.6g}) at this step"
    )
    if ans.verify:
        v = ans.verify
        lines.append(
            f"  verified in {ans.engine} {v['version']} at {v['phases']} phases: mean {v['mean']:.6g} "
            f"(sampling error {v['sampling_error']:.1e}: half the gap of the two interleaved halves' "
            f"means), {v['minimum']:.6g} to {v['maximum']:.6g} ({v['seconds']:.3g} s)"
        )
    return lines


def block_lines(engine, params):
    """``engine.name  value  unit`` lines of an engine's block (units from the adapter's ``units``)."""
    units = getattr(adapter(engine), "units", {})
    lines = []
    for name, value in params.items():
        values = value if isinstance(value, tuple) else (value,)
        shown = ", ".join("nan" if isinstance(v, float) and math.isnan(v) else f"{v:.15g}" for v in values)
        lines.append(f"{engine + '.' + name:32s} {shown}   {units.get(name, '')}".rstrip())
    return lines


def as_plain_data(cp: ContactParameters) -> dict:
    """The fields as plain data (``--json``): arrays as lists, tuples as lists."""
    from dataclasses import fields, is_dataclass

    def plain(value):
        if isinstance(value, dict):
            return {k: plain(v) for k, v in value.items()}
        if isinstance(value, (tuple, list)):
            return [plain(v) for v in value]
        if isinstance(value, np.ndarray):
            return value.tolist()
        if is_dataclass(value):
            return {f.name: plain(getattr(value, f.name)) for f in fields(value)}
        return value

    return {f.name: plain(getattr(cp, f.name)) for f in fields(cp)}
