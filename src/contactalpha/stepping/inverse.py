"""The engine's own damping whose mean restitution over the touchdown phase is the target.

The mean e_N (or eps) over a uniform phase is continuous in the damping (the jumps in phase move
continuously with it) and, at a step fine enough for a stable map, falls as the damping grows.
``damping_for`` brackets the root on a fixed ladder from zero damping upwards (the first rung
whose mean falls below the target) and solves it by Brent's method on the phase mean (of e_N on a
piecewise-affine map's pieces, ``affine_phase``; else drop by drop, ``delivered``); the result's
mean, drop by drop, is within ``MEAN_TOL`` of the target by the map.  Zero damping gives the most the
engine can deliver at that step: a larger target is out of reach.  So is any target when the
step is so coarse that the map is unstable (damping then raises the mean).  ``damping_for`` then
reports the mean nearest the target and the largest step (and the largest stiffness at the given
step) at which some damping reaches it: those searches together stop after ``SEARCH_CPU_S`` of CPU
time (saying so in ``StepInverse.search``), never try a step finer than
``delivered.MAX_CONTACT_STEPS`` steps per contact, and tell ``contactalpha.progress`` each trial
(on stderr once they have run a few seconds).
"""

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from contactalpha.progress import Progress
from contactalpha.validation import check_range

from .affine_phase import QUAD_TOL as AFFINE_TOL
from .affine_phase import phase_mean_affine
from .codes import P_MAX, P_MEAN, P_MIN, P_STD
from .delivered import (
    MAX_CONTACT_STEPS,
    PhaseStats,
    check_contact_steps,
    check_restitution,
    check_scene,
    contact_steps,
    over_phase_unchecked,
    step_limit,
)
from .registry import stepper

# The phase mean at the solution is within this of the target (by the map).
MEAN_TOL = 1e-6
# Brent's tolerance on the damping, relative.
DAMPING_RTOL = 1e-12
# The bracket's ladder: from BRACKET_START over the contact time (the same ladder for every call,
# so that an answer does not hang on a first guess where a coarse step makes the mean non-monotone),
# doubled at most BRACKET_DOUBLINGS times.
BRACKET_START = 1e-2
BRACKET_DOUBLINGS = 48
# Step (or stiffness) search for an unreachable target: factor per trial, trials at most, and
# bisections of the last bracket (the answer within 2^(0.25 / 2^3), 2.2 %, below the largest: advice,
# and the finest trials cost the most).
SHRINK = 2.0**-0.25
SHRINK_TRIALS = 80
BISECTIONS = 3
# CPU seconds the searches for an unreachable target's remedies take at most, all together.
SEARCH_CPU_S = 8.0


@dataclass(frozen=True)
class StepInverse:
    """The engine's damping for a target mean restitution at a step.

    Attributes
    ----------
    damping : the engine's own damping parameter (NaN when out of reach).
    p : the engine's parameters with it (``damping`` slots set; zero damping when out of reach).
    stats : ``PhaseStats`` at ``p``: mean (the target within ``MEAN_TOL``), range, steps.
    status : "ok", "unreachable" (no damping delivers the target at this step) or "not_converged".
    nearest : the mean nearest the target that the damping scan met, when unreachable.
    timestep_reachable : the largest step (s) at which some damping reaches the target (NaN when
        reachable at the given step, or not found).
    stiffness_reachable : the largest value of the stiffness slot at which some damping reaches
        the target at the given step (NaN likewise, or not searched; None for a map without a
        stiffness slot).
    search : why a search for those stopped short ("" when it did not): its CPU budget, or the
        finest step it tries.
    """

    damping: float
    p: np.ndarray
    stats: PhaseStats
    status: str
    nearest: float
    timestep_reachable: float
    stiffness_reachable: float
    search: str = ""


def _mean(engine, p, h, v, a, restitution):
    """The phase mean alone: on the affine pieces where the map has them (e_N), else drop by drop.

    The scene was checked where it entered (``damping_for``; a smaller step in the searches below
    keeps v >= a h / 2).  Where the affine sweep gives no number (its quadrature's budget) the
    drop-by-drop quadrature answers, as it does for eps.
    """
    s = stepper(engine)
    if restitution == "kinematic" and s.affine:
        m = float(phase_mean_affine(s.code, p, h, v, a, int(step_limit(s, p, h)), AFFINE_TOL)[P_MEAN])
        if math.isfinite(m):
            return m
    return over_phase_unchecked(s, p, h, v, a).of(restitution)[0]


def _stats(engine, p, h, v, a, restitution):
    """``PhaseStats`` drop by drop (eps, steps), once per answer; e_N's from the affine pieces if any.

    The drop-by-drop quadrature can run out of intervals (it then keeps an estimate, off by up to
    5e-4 in e_N where the affine mean is exact); the answer's e_N statistics are the affine ones.
    """
    s = stepper(engine)
    st = over_phase_unchecked(s, p, h, v, a)
    if restitution == "kinematic" and s.affine:
        row = phase_mean_affine(s.code, p, h, v, a, int(step_limit(s, p, h)), AFFINE_TOL)
        if math.isfinite(row[P_MEAN]):
            st = replace(st, mean=float(row[P_MEAN]), minimum=float(row[P_MIN]), maximum=float(row[P_MAX]),
                         std=float(row[P_STD]))  # fmt: skip
    return st


def damping_for(
    engine: str,
    p: ArrayLike,
    timestep: float,
    approach_speed: float,
    accel: float,
    target: float,
    restitution: str = "kinematic",
    *,
    remedies: bool = True,
) -> StepInverse:
    """``StepInverse``: the damping slot of ``p`` whose phase-mean restitution is ``target``.

    Parameters
    ----------
    engine : str
        A name of ``registry.STEPPERS``.
    p : array
        The engine's parameters (the damping slots' values are ignored).
    timestep, approach_speed, accel : float
        Step (s), touchdown speed (m/s), load acceleration pressing in (m/s^2).
    target : float
        Target mean restitution in (0, 1).
    restitution : str
        "kinematic" (Newton's e_N) or "energetic" (Stronge's eps).
    remedies : bool or str
        When the target is out of reach: True searches the largest step that reaches it, "both"
        also the largest stiffness at the given step, False neither.
    """
    s = stepper(engine)
    p, h, v, a = check_scene(p, timestep, approach_speed, accel)
    check_contact_steps(s, p, h)
    target = float(check_range("target", target, 0.0, 1.0, lo_open=True, hi_open=True))
    check_restitution(restitution)
    lo, hi, bracketed, nearest = _bracket(s, p, h, v, a, target, restitution)
    if not bracketed:
        # Out of reach at this step: no damping brings the mean down to, or up to, the target.
        step = stiff = math.nan
        note = ""
        if remedies:
            label = f"{engine}: the target is out of reach at {h:.4g} s; searching what reaches it"
            with Search(label) as search:
                step = reachable_timestep(engine, p, h, v, a, target, restitution, search)
                if remedies == "both":
                    stiff = reachable_stiffness(engine, p, h, v, a, target, restitution, search)
            note = search.note
        q = _with_damping(s, p, 0.0)
        st0 = _stats(engine, q, h, v, a, restitution)
        return StepInverse(math.nan, q, st0, "unreachable", nearest, step, stiff, note)
    root = brentq(lambda c: _mean(engine, _with_damping(s, p, c), h, v, a, restitution) - target, lo, hi,
                  xtol=1e-300, rtol=DAMPING_RTOL)  # fmt: skip
    q = _with_damping(s, p, root)
    st = _stats(engine, q, h, v, a, restitution)
    m = st.of(restitution)[0]
    status = "ok" if abs(m - target) <= MEAN_TOL else "not_converged"
    return StepInverse(root, q, st, status, math.nan, math.nan, math.nan)


def _with_damping(s, p, c):
    q = p.copy()
    q[list(s.damping_slots)] = c
    return q


def _bracket(s, p, h, v, a, target, restitution):
    """``(lo, hi, bracketed, nearest)``: the ladder's first rung whose mean falls below the target.

    Zero damping first (the most the step delivers: no bracket when below the target), then
    ``BRACKET_START`` over the contact time, doubled; ``nearest`` is the mean nearest the target met.
    """
    top = _mean(s.name, _with_damping(s, p, 0.0), h, v, a, restitution)
    lo, hi, nearest = 0.0, None, top
    if top < target:
        return lo, hi, False, nearest
    hi = BRACKET_START / s.contact_time(p)
    for _ in range(BRACKET_DOUBLINGS):
        m = _mean(s.name, _with_damping(s, p, hi), h, v, a, restitution)
        if abs(m - target) < abs(nearest - target):
            nearest = m
        if m < target:
            return lo, hi, True, nearest
        lo, hi = hi, 2.0 * hi
    return lo, hi, False, nearest


class Search:
    """The remedies' search budget: ``SEARCH_CPU_S`` of CPU time, each trial told to a ``Progress``.

    ``give_up(what, x, steps)`` is called before each trial (of ``steps`` steps per contact): True
    once the budget is spent, or when the trial would overrun it at the CPU time per step per contact
    the trials so far took (``note`` then says where the search stopped).  Use it as a context
    manager (the progress timer stops).
    """

    def __init__(self, label, cpu_s=None):
        cpu_s = SEARCH_CPU_S if cpu_s is None else cpu_s
        self.deadline = time.process_time() + cpu_s
        self.cpu_s = cpu_s
        self.note = ""
        self.progress = Progress(label)
        self.rate = 0.0  # CPU s per step per contact of the costliest trial so far
        self._last = None

    def give_up(self, what: str, x: float, steps: float) -> bool:
        """True to stop before trying ``what`` = ``x`` (``steps`` per contact); else tells the progress."""
        if self.note:
            return True
        now = time.process_time()
        if self._last is not None:
            self.rate = max(self.rate, (now - self._last[0]) / self._last[1])
        self._last = (now, steps)
        if now + self.rate * steps > self.deadline:
            self.note = f"the search stopped at its {self.cpu_s:g} s CPU budget, before {what} {x:.4g}"
            return True
        self.progress(f"trying {what} {x:.4g}")
        return False

    def stop(self, note: str) -> bool:
        """Stop the search here, saying why."""
        self.note = self.note or note
        return True

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.progress.close()
        return False


def largest_passing(
    reaches: Callable[[float], bool],
    x0: float,
    shrink: float = SHRINK,
    trials: int = SHRINK_TRIALS,
    bisections: int = BISECTIONS,
    give_up: Callable[[float], bool] | None = None,
) -> float:
    """The largest x < x0 with ``reaches(x)``: a geometric scan by ``shrink``, then bisection; NaN if none.

    ``reaches`` need not be monotone: the answer passes, and the scan's rung above it fails.
    ``give_up(x)``, asked before each trial, stops the search: NaN in the scan, the passing end of
    the bracket in the bisection.
    """

    def stop(x):
        return give_up is not None and give_up(x)

    prev, x = x0, x0 * shrink
    for _ in range(trials):
        if stop(x):
            return math.nan
        if reaches(x):
            break
        prev, x = x, x * shrink
    else:
        return math.nan
    lo, hi = x, prev
    for _ in range(bisections):
        mid = math.sqrt(lo * hi)
        if stop(mid):
            break
        lo, hi = (mid, hi) if reaches(mid) else (lo, mid)
    return lo


def _reaches(engine, p, h, v, a, target, restitution):
    """True when some damping reaches the target at step ``h``: the ladder brackets it (the root follows)."""
    return _bracket(stepper(engine), p, h, v, a, target, restitution)[2]


def _give_up(search, what, steps):
    """``largest_passing``'s ``give_up`` for ``search``: its budget, and no trial past ``MAX_CONTACT_STEPS``.

    ``steps(x)`` is the trial's steps per contact.
    """
    if search is None:
        return None

    def give_up(x):
        n = steps(x)
        if n > MAX_CONTACT_STEPS:
            return search.stop(f"no {what} tried reaches it; the next, {x:.4g}, would be over "
                               f"{MAX_CONTACT_STEPS:,} steps per contact")  # fmt: skip
        return search.give_up(what, x, n)

    return give_up


def reachable_timestep(
    engine: str,
    p: np.ndarray,
    h: float,
    v: float,
    a: float,
    target: float,
    restitution: str = "kinematic",
    search: Search | None = None,
) -> float:
    """The largest step below ``h`` at which some damping delivers the target phase mean (NaN if none).

    ``search`` (a ``Search``) bounds it: its CPU budget, and no step past ``MAX_CONTACT_STEPS``.
    """
    s = stepper(engine)
    give_up = _give_up(search, "step", lambda x: contact_steps(s, p, x))
    return largest_passing(lambda x: _reaches(engine, p, x, v, a, target, restitution), h, give_up=give_up)


def reachable_stiffness(
    engine: str,
    p: np.ndarray,
    h: float,
    v: float,
    a: float,
    target: float,
    restitution: str = "kinematic",
    search: Search | None = None,
) -> float | None:
    """The largest stiffness below ``p``'s at which some damping delivers the target at step ``h``.

    The stiffness slots keep their ratios; the value returned is the first slot's.  ``search`` as
    for ``reachable_timestep``.
    """
    s = stepper(engine)
    if not s.stiffness_slots:
        return None
    k = list(s.stiffness_slots)

    def scaled(x):
        q = p.copy()
        q[k] = x * p[k] / p[k[0]]
        return q

    give_up = _give_up(search, "stiffness", lambda x: contact_steps(s, scaled(x), h))

    def reaches(x):
        return _reaches(engine, scaled(x), h, v, a, target, restitution)

    return largest_passing(reaches, float(p[k[0]]), give_up=give_up)
