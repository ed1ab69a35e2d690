"""The parts of the adapter contract every engine shares.

They are the law's damping, a drop's delivered restitution, and the refinement of the damping on
the engine's own drops.

An adapter that derives from ``Adapter`` writes only what is its engine's own (``parameters``,
``build_drop``, ``run``, ``static_penetration``, ``version``, ``timestep``) and gets:

- ``law_damping(scene, target, restitution)``: the law's exact inverse at the scene's load;
- ``measure(samples, scene)``: the impact cut out of sampled states (``adapters.measure``); a
  stepping engine's version reads the flight parabola instead (``adapters.stepped``);
- ``delivered(scene, damping)``: build, run, measure, summarise (``Delivered``);
- ``calibrate(scene, target)``: secant steps on the delivered e_N (``refine``), with one rule when
  they find no damping: the law's own damping is what gets measured and reported.
"""

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from contactalpha.adapters.contract import law_damping
from contactalpha.adapters.measure import measure_with_rest_check

if TYPE_CHECKING:
    from contactalpha.laws.law import ContactLaw

# Secant iterations of ``refine`` at most, and its tolerance on the mean delivered e_N.
REFINE_ITER = 12
REFINE_TOL = 1e-5
# Tolerance on the delivered e_N of ``calibrate`` for settings that do not carry a ``tol``.
DELIVERED_TOL = 1e-3


@dataclass(frozen=True)
class Delivered:
    """Newton's restitution an engine delivers, over touchdown phases.

    Attributes
    ----------
    e_n : mean e_N over the phases (0 for a drop that does not separate).
    spread : max - min of e_N over the phases (0 for an error-controlled integrator: one phase).
    contact_steps : fewest steps in contact over the phases; None for an error-controlled integrator.
    separated : every phase separated.
    """

    e_n: float
    spread: float
    contact_steps: int | None
    separated: bool


@dataclass(frozen=True)
class Refinement:
    """The outcome of ``refine``.

    Attributes
    ----------
    damping : the law's damping parameter that delivers the target (NaN when none does).
    e_n : the mean e_N delivered with it.
    start : the damping it started from (the continuous law's), and ``e_n_start`` its delivered e_N.
    iterations : engine evaluations after the start's.
    status : "ok", "unchanged" (the start already within the tolerance), "unreachable" (even zero
        damping delivers less than the target at this step), or "not_converged".
    """

    damping: float
    e_n: float
    start: float
    e_n_start: float
    iterations: int
    status: str


def refine(e_n_of, target, start, tol, *, max_iter=REFINE_ITER, refine_tol=REFINE_TOL):
    """Secant steps on ``e_n_of(damping) - target`` from ``start`` (the delivered e_N falls as damping grows).

    Parameters
    ----------
    e_n_of : callable
        The mean e_N the engine delivers with a damping parameter (>= 0).
    target : float
        Target e_N in (0, 1).
    start : float
        The continuous law's damping parameter (> 0).
    tol : float
        Below this |delivered - target| the start is kept ("unchanged").
    refine_tol : float
        The secant stops once |delivered - target| <= this.
    """
    e0 = e_n_of(start)
    if abs(e0 - target) <= tol:
        return Refinement(start, e0, start, e0, 0, "unchanged")
    x0, f0 = start, e0 - target
    x1 = start * (1.0 + 0.05 * math.copysign(1.0, f0))
    f1 = e_n_of(x1) - target
    n = 1
    best = (abs(f0), x0, f0) if abs(f0) < abs(f1) else (abs(f1), x1, f1)
    while n < max_iter and best[0] > refine_tol:
        slope = (f1 - f0) / (x1 - x0) if x1 != x0 else -1.0
        if not (slope < 0.0 and math.isfinite(slope)):
            slope = -abs(f1) / max(abs(x1), 1e-12) - 1.0
        x2 = max(x1 - f1 / slope, 0.0)
        if x2 == 0.0 and x1 == 0.0:
            break
        f2 = e_n_of(x2) - target
        n += 1
        if x2 == 0.0 and f2 < 0.0:
            return Refinement(math.nan, f2 + target, start, e0, n, "unreachable")
        x0, f0, x1, f1 = x1, f1, x2, f2
        if abs(f2) < best[0]:
            best = (abs(f2), x2, f2)
    status = "ok" if best[0] <= refine_tol else "not_converged"
    return Refinement(best[1], best[2] + target, start, e0, n, status)


class Adapter:
    """The shared implementation of the contract's derived parts (see the module docstring).

    A subclass sets ``name``, ``law``, ``module``, ``settings`` and writes ``version``,
    ``parameters``, ``build_drop``, ``run``, ``static_penetration`` and ``timestep``.
    """

    # The parameter block's names and units in words, a line each (printed under its parameters
    # by the front door); none by default.
    unit_notes: tuple[str, ...] = ()
    # What a subclass sets (declared only: no class attribute here).
    name: str
    law: "ContactLaw"
    module: str
    settings: Any  # the engine's own settings dataclass
    parameters: Callable[..., dict]
    build_drop: Callable[..., Any]
    run: Callable[..., Any]

    def law_damping(self, scene, target, restitution="kinematic", settings=None):
        """``(DampingSolution, xi)``: the law's exact damping for ``target`` (``contract.law_damping``)."""
        return law_damping(self.law, scene, target, restitution)

    def measure(self, samples, scene):
        """``MeasuredImpact`` of the samples (``measure_with_rest_check``: Hermite-located events)."""
        return measure_with_rest_check(samples, scene)

    def summary(self, result, samples, settings):
        """``Delivered`` of one measured drop: one phase, no spread, no step count."""
        return Delivered(float(result.e_n), 0.0, None, bool(result.separated))

    def check_delivered(self, got, settings):
        """Hook for what a delivered restitution needs said (a stepping engine warns on coarse steps)."""

    def delivered(self, scene, damping, settings=None):
        """``Delivered``: the e_N the engine delivers with the law's ``damping`` in ``scene``."""
        settings = self.settings if settings is None else settings
        model = self.build_drop(scene, self.parameters(damping, scene, settings), settings)
        samples = self.run(model, scene, settings)
        return self.summary(self.measure(samples, scene), samples, settings)

    def calibrate(self, scene, target, start=None, settings=None, progress=None):
        """Parameters that deliver the target e_N in the engine, refined from the law's damping ``start``.

        Parameters
        ----------
        scene : contract.DropScene
        target : float
            Target Newton's restitution e_N.
        start : float, optional
            The damping to start from; by default the law's exact inverse (``law_damping``).
        settings : optional
            The engine's settings; ``settings.tol`` (default ``DELIVERED_TOL``) is the tolerance on
            the delivered e_N.
        progress : callable, optional
            Called with a line naming each drop in the engine as it starts (``contactalpha.progress``).

        Returns
        -------
        (dict, Refinement, Delivered)
            The engine's parameters of the refined damping (``{}`` when the refinement found none),
            the refinement, and what the parameters deliver.  The one fallback rule: when the
            refinement finds no damping, ``Delivered`` is what the start (the law's damping) delivers.
        """
        settings = self.settings if settings is None else settings
        if start is None:
            sol, xi = self.law_damping(scene, target, "kinematic", settings)
            if not sol.ok:
                raise ValueError(
                    f"no {self.law.damping} gives e_N {target!r} at xi = {xi!r} in {self.law.name}: "
                    f"{sol.status}"
                )
            start = float(sol.damping)
        tol = getattr(settings, "tol", DELIVERED_TOL)
        drops = [0]

        def e_n_of(damping):
            drops[0] += 1
            if progress is not None:
                progress(f"{self.name} drop {drops[0]}, {self.law.damping} = {damping:.6g}")
            return self.delivered(scene, damping, settings).e_n

        ref = refine(e_n_of, target, start, tol)
        found = math.isfinite(ref.damping)
        got = self.delivered(scene, ref.damping if found else start, settings)
        self.check_delivered(got, settings)
        return (self.parameters(ref.damping, scene, settings) if found else {}), ref, got
