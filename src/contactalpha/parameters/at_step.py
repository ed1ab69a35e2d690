"""The front door at an engine's own step: parameters for the mean over the touchdown phase.

``contact_parameters(..., engine=NAME, timestep=h)`` first solves the continuous law as without a
step, then, through the engine's discrete map (``contactalpha.stepping``): what those parameters
deliver at ``h`` (the phase mean, its range), the engine's own damping whose phase mean is the
target (``stepping.inverse``), and what that delivers.  The engine's block of ``engines`` then
holds the stepped parameters; the law's ``damping`` and ``physical_damping`` stay the continuous
law's.  ``SteppedAnswer`` carries the rest; ``parameters.verify`` runs the installed engine at N phases.
"""

import math
import warnings
from dataclasses import dataclass, replace

import numpy as np

from contactalpha.adapters.registry import adapter
from contactalpha.stepping.delivered import over_phase
from contactalpha.stepping.inverse import damping_for
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_scalar

from .block_scene import BlockScene
from .result import gain_note

# The word that asks for the engine's default step.
DEFAULT_STEP = "default"


@dataclass(frozen=True)
class SteppedAnswer:
    """What the engine delivers at its step, over a uniformly random touchdown phase.

    Attributes
    ----------
    engine, timestep : the engine and its step, s.
    restitution : "kinematic" (e_N) or "energetic" (eps): what ``target`` and the statistics are.
    target : the restitution asked for.
    damping : the engine's own damping for the phase mean (``engines[engine]`` holds its block).
    law_damping : the same as the law's dimensionless damping (zeta for MuJoCo and PyBullet,
        alpha for Drake).
    mean, minimum, maximum, std : the restitution over the phase with it (NaN when unreachable).
    steps_min, steps_max : steps in contact.
    status : "ok", "unreachable" or "not_converged" (``stepping.inverse``).
    nearest : when unreachable, the mean nearest the target the step can deliver.
    timestep_reachable : when unreachable, the largest step that reaches the target, s (NaN when
        none was found: ``search`` says where that search stopped).
    search : why the search for ``timestep_reachable`` stopped short ("" when it did not).
    continuous_mean, continuous_minimum, continuous_maximum : what the continuous law's
        parameters deliver at this step (the error the step makes without this correction).
    verify : ``{"phases", "mean", "minimum", "maximum", "seconds", "version"}`` measured in the
        installed engine, or None.
    few_steps : a batch's flat indices of the rows with an answer whose contact spans fewer than
        ``FEW_STEPS`` steps (one landing then spreads widely about the mean; a
        ``ContactStepsWarning`` gives their count); None for one scene (``steps_min`` says it).
    source : "exact" ("none" for a batch's row without a continuous answer): every answer is
        solved on the map (one scene at a time by ``stepping.inverse``, or a batch's rows together
        by ``stepping.batch_inverse``).
    mean_error : how far the mean is from the target by the map (at most
        ``stepping.inverse.MEAN_TOL``); NaN where there is no answer.

    In a batch (array inputs) every per-scene field is an array of the scenes' shape (``source``
    and ``status`` arrays of words); ``timestep_reachable`` is NaN there (one scene's call
    searches it).
    """

    engine: str
    timestep: float
    restitution: str
    target: float | np.ndarray
    damping: float | np.ndarray
    law_damping: float | np.ndarray
    mean: float | np.ndarray
    minimum: float | np.ndarray
    maximum: float | np.ndarray
    std: float | np.ndarray
    steps_min: int | np.ndarray
    steps_max: int | np.ndarray
    status: str | np.ndarray
    nearest: float | np.ndarray
    timestep_reachable: float | np.ndarray
    continuous_mean: float | np.ndarray
    continuous_minimum: float | np.ndarray
    continuous_maximum: float | np.ndarray
    verify: dict | None = None
    source: object = "exact"
    mean_error: object = math.nan
    few_steps: object = None
    search: str = ""


class EnergyGainWarning(UserWarning):
    """A single drop at the engine's step can leave faster than it came (e_N or eps above 1)."""


def warn_gain(ans, stacklevel=4):
    """``warnings.warn`` ``gain_note`` (``EnergyGainWarning``) where there is one; ``ans`` back.

    ``stacklevel`` 4 names the caller of ``contact_parameters`` (through ``at_step`` or
    ``at_step_batch``).
    """
    note = gain_note(ans)
    if note is not None:
        warnings.warn(note, EnergyGainWarning, stacklevel=stacklevel)
    return ans


def needs_radius(engine):
    """True when ``engine``'s step map reads the sphere's radius (``Stepper.needs_radius``)."""
    return stepper(engine).needs_radius


def resolve_timestep(engine, timestep):
    """The step in s: ``timestep``, or the engine's default for ``"default"``; ValueError otherwise."""
    s = stepper(engine)
    if isinstance(timestep, str):
        if timestep != DEFAULT_STEP:
            raise ValueError(f"timestep = {timestep!r} is neither a step in s nor {DEFAULT_STEP!r}")
        return s.timestep
    return check_scalar("timestep", timestep, 0.0, math.inf, lo_open=True, hi_open=True)


def at_step(cp, engine, timestep, mass, stiffness, approach_speed, accel, radius, target, restitution):
    """``cp`` with the engine's block for the phase mean at ``timestep`` and ``stepped`` filled."""
    if engine is None:
        raise ValueError("timestep needs engine=: the step is an engine's (mujoco, pybullet, drake)")
    s = stepper(engine)
    if s.from_block is None or s.law_damping is None:
        raise ValueError(f"engine = {engine!r} has a step map but no front door at its step yet")
    h = resolve_timestep(engine, timestep)
    if accel <= 0.0:
        raise ValueError("timestep needs a load pressing the bodies together: accel or force > 0")
    sol = solve_on_map(s, cp.engines[engine], mass, radius, h, approach_speed, accel, target, restitution)
    inv = sol.inverse
    engines = dict(cp.engines)
    if inv.status == "ok":
        a = adapter(engine)
        settings = replace(a.settings, **{s.step_setting: h})
        scene = BlockScene(mass, stiffness, approach_speed, radius)
        engines[engine] = a.parameters(sol.zeta, scene, settings)
    answer = SteppedAnswer(
        engine=engine, timestep=h, restitution=restitution, target=float(target),
        damping=float(inv.damping), law_damping=sol.zeta,
        mean=sol.mean, minimum=sol.minimum, maximum=sol.maximum, std=sol.std,
        steps_min=inv.stats.steps_min, steps_max=inv.stats.steps_max, status=inv.status,
        nearest=float(inv.nearest), timestep_reachable=float(inv.timestep_reachable),
        continuous_mean=sol.continuous[0], continuous_minimum=sol.continuous[1],
        continuous_maximum=sol.continuous[2], mean_error=float(abs(sol.mean - target)), search=inv.search,
    )  # fmt: skip
    return cp.replaced(engines=engines, stepped=warn_gain(answer))


@dataclass(frozen=True)
class MapSolution:
    """One scene solved on the engine's step map (``solve_on_map``).

    ``inverse`` is ``stepping.inverse.StepInverse``; ``mean``, ``minimum``, ``maximum``, ``std``
    what its damping delivers and ``zeta`` the law's damping of it (NaN unless it reached the
    target); ``continuous`` the (mean, minimum, maximum) the continuous law's block delivers.
    """

    inverse: object
    mean: float
    minimum: float
    maximum: float
    std: float
    zeta: float
    continuous: tuple


def solve_on_map(s, block, mass, radius, h, approach_speed, accel, target, restitution, remedies=True):
    """``MapSolution`` of one scene from the continuous law's ``block`` of stepper ``s``'s engine."""
    p0 = s.from_block(block, mass, radius)
    before = over_phase(s.name, p0, h, approach_speed, accel)
    inv = damping_for(s.name, p0, h, approach_speed, accel, target, restitution, remedies=remedies)
    ok = inv.status == "ok"
    mean, lo, hi = inv.stats.of(restitution) if ok else (math.nan,) * 3
    std = (inv.stats.std if restitution == "kinematic" else inv.stats.eps_std) if ok else math.nan
    zeta = float(s.law_damping(inv.p, approach_speed)) if ok else math.nan
    continuous = tuple(float(x) for x in before.of(restitution))
    return MapSolution(inv, float(mean), float(lo), float(hi), float(std), zeta, continuous)
