"""When no damping reaches a target: the nearest reachable target, and what would reach this one.

``UnreachableTarget`` (a ``ValueError``) carries both; ``contactalpha params`` prints its message on
one line and exits with ``EXIT_UNREACHABLE`` (its ``--help`` says so).  Two cases reach it:

- an engine's own drops (``params --engine NAME --refine``): at the engine's step even zero damping
  delivers less than the target (the step's own dissipation), or the step is so coarse that the
  contact is unstable.  ``remedies`` finds the largest stiffness, and the largest step, at which
  zero damping delivers at least the target with a stable contact (damping then brings it down to
  the target), by a geometric scan down from the scene's value and a few bisections
  (``stepping.inverse.largest_passing``);
- Stronge's eps = 0 without a load: alpha grows without bound as eps -> 0; any load reaches it.
"""

import math
from dataclasses import fields, replace

from contactalpha.adapters.base import DELIVERED_TOL
from contactalpha.defaults import EXIT_UNREACHABLE  # noqa: F401  (the CLI's exit status, re-exported)
from contactalpha.stepping.inverse import largest_passing

# Scan of a remedy (engine drops, slow): factor per trial, trials at most (2^-12 of the start),
# bisections after it.
SHRINK = 2.0**-0.5
TRIALS = 24
BISECTIONS = 4


class UnreachableTarget(ValueError):
    """No damping delivers the target restitution.

    Attributes
    ----------
    nearest : the reachable restitution nearest the target (NaN where none is known).
    remedies : ``{what: value}`` that would reach the target: "stiffness" (the law's physical
        unit), "timestep" (s), "accel" (m/s^2); NaN where the scan found none.
    """

    def __init__(self, message, nearest=math.nan, remedies=None):
        super().__init__(message)
        self.nearest = nearest
        self.remedies = dict(remedies or {})


def _largest(reaches, x0):
    """``stepping.inverse.largest_passing`` with this module's scan."""
    return largest_passing(reaches, x0, SHRINK, TRIALS, BISECTIONS)


def remedies(adapter, scene, target, settings=None, progress=None):
    """``{"stiffness": k, "timestep": h}``: the largest of each (the other kept) that can reach ``target``.

    "Can reach": zero damping delivers at least the target e_N on the engine's drops and at most
    1 + its tolerance (a stable contact), with the rest penetration (the spring's share of the
    load) below the sphere's radius: a softer contact is no remedy.  The step is scanned only for
    settings with a ``timestep``.  ``progress(text)`` hears each scan start (engine drops, slow).
    """
    settings = adapter.settings if settings is None else settings
    tol = getattr(settings, "tol", DELIVERED_TOL)

    def reaches(s, at):
        if s.mass * s.accel / s.stiffness ** (1.0 / adapter.law.exponent) >= s.radius:
            return False  # it would sink deeper than the ball is large
        e_n = adapter.delivered(s, 0.0, at).e_n
        return target <= e_n <= 1.0 + tol

    if progress is not None:
        progress(f"no damping reaches e_N = {target!r} on {adapter.name}'s drops: scanning the stiffness")

    k = _largest(lambda x: reaches(replace(scene, stiffness=x), settings), scene.stiffness)
    out = {"stiffness": k}
    step = adapter.timestep(settings)
    if step is not None and "timestep" in {f.name for f in fields(settings)}:
        if progress is not None:
            progress(f"scanning {adapter.name}'s step")
        out["timestep"] = _largest(lambda h: reaches(scene, replace(settings, timestep=h)), step)
    return out


def unreachable_on_drops(adapter, scene, target, ref, settings=None, progress=None):
    """``UnreachableTarget`` for a refinement on ``adapter``'s drops that found no damping."""
    settings = adapter.settings if settings is None else settings
    found = remedies(adapter, scene, target, settings, progress)
    step = adapter.timestep(settings)
    unit = adapter.law.stiffness_unit
    ways = [f"a stiffness <= {found['stiffness']:.4g} {unit} at this step"]
    if "timestep" in found:
        ways.append(f"a step <= {found['timestep']:.3g} s at this stiffness")
    ways = [w for w, v in zip(ways, found.values(), strict=True) if math.isfinite(v)] or ["none found"]
    message = (
        f"no {adapter.law.damping} delivers e_N = {target!r} on {adapter.name}'s drops at its step "
        f"{step:g} s ({ref.status}): the e_N nearest the target that it delivered is {ref.e_n:.6g}; what "
        f"would reach "
        f"e_N = {target!r}: {' or '.join(ways)}"
    )
    return UnreachableTarget(message, ref.e_n, found)


def eps_zero_without_load():
    """``UnreachableTarget`` for Stronge's eps = 0 with no load (alpha -> infinity)."""
    return UnreachableTarget(
        "eps = 0.0 needs a load: without one alpha -> infinity and every eps > 0 is reachable, the nearest "
        "as close to 0 as asked; any load reaches eps = 0: give accel or force > 0",
        nearest=0.0,
    )
