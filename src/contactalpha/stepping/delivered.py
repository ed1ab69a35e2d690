"""What an engine delivers over the touchdown phase, for a scene, a step and its parameters.

``over_phase`` gives the mean of Newton's e_N (and Stronge's eps) over a uniformly random
touchdown phase, exact across the jumps (``phase.phase_mean``), with the range and standard
deviation one drop sees and the steps per contact.  ``at_phases`` evaluates single drops.
"""

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from contactalpha.validation import (  # check_restitution: for .inverse and .stepsize
    check_count,
    check_positive,
    check_range,
    check_restitution,  # noqa: F401
    check_scalar,
)

from . import codes
from .drop import run_drops
from .phase import GL_W, GL_X, GRID, MAX_INTERVALS, QUAD_TOL, phase_mean
from .registry import Stepper, stepper

# A drop runs at most this many contact times (a slowly ringing capture comes to rest within it).
REST_CONTACT_TIMES = 400
# A scene whose contact time spans more steps than this is refused (``check_contact_steps``): a
# drop's work grows with the steps (the steps this package proposes for soft, slow PyBullet scenes
# reach about 7,000).
MAX_CONTACT_STEPS = 20_000


@dataclass(frozen=True)
class PhaseStats:
    """Restitution over a uniform touchdown phase.

    Attributes
    ----------
    mean, minimum, maximum, std : Newton's e_N over the phase (mean; the range one drop sees,
        over the phases evaluated, both sides of every jump included; standard deviation).
    eps_mean, eps_min, eps_max, eps_std : the same for Stronge's eps.
    steps_min, steps_max : steps in contact, fewest and most.
    quad_error : estimated error of the means (adaptive quadrature).
    jumps : phases where the steps in contact change.
    evaluations : drops evaluated.
    status : "ok" or the worst drop's status (``codes.DROP_STATUS``); NaN statistics unless "ok"
        or "quadrature interval limit".
    """

    mean: float
    minimum: float
    maximum: float
    std: float
    eps_mean: float
    eps_min: float
    eps_max: float
    eps_std: float
    steps_min: int
    steps_max: int
    quad_error: float
    jumps: int
    evaluations: int
    status: str

    def of(self, restitution: str) -> tuple[float, float, float]:
        """``(mean, minimum, maximum)`` of e_N ("kinematic") or eps ("energetic")."""
        if restitution == "kinematic":
            return self.mean, self.minimum, self.maximum
        return self.eps_mean, self.eps_min, self.eps_max


def check_scene(
    p: ArrayLike, timestep: float, approach_speed: float, accel: float
) -> tuple[np.ndarray, float, float, float]:
    """Checked ``(p, h, v_in, accel)``: p finite float64, the others finite and > 0, ``v_in >= accel h / 2``.

    A drop starts on its flight parabola up to a step before touchdown; slower than ``accel h / 2``
    that parabola would start below the surface (the flight lasts less than a step).
    """
    p = np.ascontiguousarray(check_range("p", p, -math.inf, math.inf), dtype=float)
    if p.ndim != 1:
        raise ValueError(f"p has shape {p.shape}; valid: a 1-D array of the engine's parameters")
    h = check_scalar("timestep", timestep, 0.0, math.inf, lo_open=True, hi_open=True)
    v = check_scalar("approach_speed", approach_speed, 0.0, math.inf, lo_open=True, hi_open=True)
    a = check_scalar("accel", accel, 0.0, math.inf, lo_open=True, hi_open=True)
    if v < 0.5 * a * h:
        raise ValueError(
            f"approach_speed = {v!r} is below accel * timestep / 2 = {0.5 * a * h!r}: a drop this slow "
            "under this load flies less than a step before touchdown, so its touchdown phase is not "
            "defined; give a smaller timestep or a faster approach"
        )
    return p, h, v, a


def contact_steps(s: Stepper, p: np.ndarray, h: float) -> float | np.ndarray:
    """Steps per contact time of stepper ``s`` (its ``contact_time`` over the step ``h``)."""
    return s.contact_time(p) / h


def too_many_steps(s: Stepper, p: np.ndarray, h: float) -> str:
    """Why a scene with more than ``MAX_CONTACT_STEPS`` steps per contact is refused ("" if it is not)."""
    n = contact_steps(s, p, h)
    if n <= MAX_CONTACT_STEPS:
        return ""
    return (
        f"timestep = {h!r} s gives {n:,.0f} steps per contact ({s.name}'s contact time "
        f"{s.contact_time(p):.4g} s over the step), above the {MAX_CONTACT_STEPS:,} this package solves for: "
        f"give a step of at least {s.contact_time(p) / MAX_CONTACT_STEPS:.3g} s, or use the continuous "
        "law's parameters (no timestep), which the step's answer approaches as the step shrinks"
    )


def check_contact_steps(s: Stepper, p: np.ndarray, h: float) -> None:
    """ValueError (``too_many_steps``) for a scene of more than ``MAX_CONTACT_STEPS`` steps per contact."""
    why = too_many_steps(s, p, h)
    if why:
        raise ValueError(why)


def step_limit(s: Stepper, p: np.ndarray, h: float) -> int | np.ndarray:
    """Steps a drop of stepper ``s`` may take: ``REST_CONTACT_TIMES`` contact times, at least 1000.

    ``p`` may hold one column per scene (slots first): an int array then.
    """
    n = np.maximum(1000, np.ceil(REST_CONTACT_TIMES * s.contact_time(p) / h))
    return int(n) if np.ndim(n) == 0 else n.astype(np.int64)


def over_phase(
    engine: str,
    p: ArrayLike,
    timestep: float,
    approach_speed: float,
    accel: float,
    *,
    tol: float = QUAD_TOL,
    grid: int = GRID,
    max_steps: int | None = None,
) -> PhaseStats:
    """``PhaseStats`` of a drop through ``engine``'s step map over a uniform touchdown phase.

    Parameters
    ----------
    engine : str
        A name of ``registry.STEPPERS``.
    p : array
        The engine's parameters (``registry.Stepper.pack``).
    timestep : float
        The engine's step, s.
    approach_speed : float
        Touchdown speed, m/s.
    accel : float
        Load acceleration pressing into the contact (gravity plus push over mass), m/s^2.
    tol : float
        Quadrature tolerance per unit phase.
    grid : int
        Phases sampled to find the jumps.
    max_steps : int, optional
        Steps per drop (default ``step_limit``).
    """
    s = stepper(engine)
    p, h, v, a = check_scene(p, timestep, approach_speed, accel)
    check_contact_steps(s, p, h)
    check_positive("tol", tol)
    grid = check_count("grid", grid, 4, 1_000_000)
    max_steps = (
        int(step_limit(s, p, h)) if max_steps is None else check_count("max_steps", max_steps, 1, 10**9)
    )
    return over_phase_unchecked(s, p, h, v, a, float(tol), grid, max_steps)


def over_phase_unchecked(
    s: Stepper,
    p: np.ndarray,
    h: float,
    v: float,
    a: float,
    tol: float = QUAD_TOL,
    grid: int = GRID,
    max_steps: int | None = None,
) -> PhaseStats:
    """``over_phase`` for stepper ``s`` on values ``check_scene`` has passed (the root finders' core)."""
    max_steps = int(step_limit(s, p, h)) if max_steps is None else max_steps
    return _stats(phase_mean(s.code, p, h, v, a, max_steps, tol, grid, MAX_INTERVALS, GL_X, GL_W))


def _stats(row):
    st = int(row[codes.P_STATUS])
    return PhaseStats(
        float(row[codes.P_MEAN]),
        float(row[codes.P_MIN]),
        float(row[codes.P_MAX]),
        float(row[codes.P_STD]),
        float(row[codes.P_EPS_MEAN]),
        float(row[codes.P_EPS_MIN]),
        float(row[codes.P_EPS_MAX]),
        float(row[codes.P_EPS_STD]),
        int(row[codes.P_STEPS_MIN]),
        int(row[codes.P_STEPS_MAX]),
        float(row[codes.P_ERR]),
        int(row[codes.P_JUMPS]),
        int(row[codes.P_EVALS]),
        "ok" if st == 0 else codes.DROP_STATUS[st],
    )


def at_phases(
    engine: str,
    p: ArrayLike,
    timestep: float,
    phases: ArrayLike,
    approach_speed: float,
    accel: float,
    *,
    max_steps: int | None = None,
) -> dict[str, np.ndarray]:
    """Single drops at ``phases`` (each in [0, 1)): dict of arrays ``e_n``, ``eps``, ``steps``, ``status``."""
    s = stepper(engine)
    p, h, v, a = check_scene(p, timestep, approach_speed, accel)
    phases = np.atleast_1d(check_range("phases", phases, 0.0, 1.0, hi_open=True)).astype(float).ravel()
    max_steps = (
        int(step_limit(s, p, h)) if max_steps is None else check_count("max_steps", max_steps, 1, 10**9)
    )
    rows = run_drops(s.code, p, h, phases, v, a, max_steps)
    return {
        "e_n": rows[:, codes.D_EN],
        "eps": rows[:, codes.D_EPS],
        "steps": rows[:, codes.D_STEPS].astype(int),
        "status": np.array([codes.DROP_STATUS[int(c)] for c in rows[:, codes.D_STATUS]]),
    }
