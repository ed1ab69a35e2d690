"""``verify``: the installed engine's drops at N touchdown phases, against the answer at its step.

``contact_parameters(..., engine=NAME, timestep=h, verify=N)`` runs the engine's own drop with the
stepped parameters at ``N`` phases (``"default"``: doubling them until the mean's sampling error
is small) and reports what it measured in ``stepped.verify``.
"""

import math
from dataclasses import replace
from typing import Any

import numpy as np

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import adapter
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_count

from .at_step import DEFAULT_STEP
from .result import ContactParameters

# Radius of the sphere an engine's verification drop uses when the scene gives none, m.
VERIFY_RADIUS = 0.05
# ``verify="default"`` (``--verify`` alone): phases to start with, the sampling error at which
# doubling them stops, and the most phases.  Where a drop's step count jumps with the phase the
# error falls as 1/N: at 2-3 steps per contact 2.6e-3 over 64 phases, 1.6e-4 over 1024.
VERIFY_PHASES = 64
VERIFY_TOL = 1e-4
VERIFY_MAX_PHASES = 4096


def phase_mean_error(values: Any) -> float:
    """Error estimate of the mean over equally spaced phases: half its two interleaved halves' gap.

    ``values[0::2]`` and ``values[1::2]`` are each a rectangle rule of the phase integral on half
    the points, shifted by one spacing; their means differ by about twice the full grid's error
    (which falls as 1/N where a drop's step count jumps with the phase, faster where it is smooth).
    """
    x = np.asarray(values, dtype=float)
    return 0.5 * abs(float(x[0::2].mean() - x[1::2].mean())) if x.size >= 2 else math.nan


def verify_on_engine(
    cp: ContactParameters,
    phases: int | str,
    mass: float,
    stiffness: float,
    approach_speed: float,
    accel: float,
    radius: float | None,
) -> ContactParameters:
    """``cp`` with ``stepped.verify``: the installed engine's drop at ``phases`` touchdown phases.

    The engine runs the block of ``cp.engines`` (the stepped parameters) at the stepped answer's
    step, the whole load as gravity; e_N per phase is read by the adapter.
    ``stepped.verify["sampling_error"]`` is the mean's ``phase_mean_error``.  ``phases``
    "default" starts at ``VERIFY_PHASES`` and doubles them (to ``VERIFY_MAX_PHASES``) until that
    error is at most ``VERIFY_TOL``.
    """
    ans = cp.stepped
    if ans is None or ans.status != "ok":
        raise ValueError("verify needs a stepped answer that reached the target (give timestep=)")
    auto = isinstance(phases, str) and phases == DEFAULT_STEP
    n = VERIFY_PHASES if auto else check_count("phases", phases, 1, 100_000)
    a = adapter(ans.engine)
    scene = DropScene(mass, stiffness, approach_speed, gravity=accel, force=0.0,
                      radius=VERIFY_RADIUS if radius is None else radius)  # fmt: skip
    seconds = 0.0
    while True:
        settings = replace(a.settings, **{stepper(ans.engine).step_setting: ans.timestep}, phases=n)
        samples = a.run(a.build_drop(scene, cp.engines[ans.engine], settings), scene, settings)
        a.measure(samples, scene)
        e = np.asarray(samples.extra["e_n_phases"], dtype=float)
        seconds += float(samples.seconds)
        error = phase_mean_error(e)
        if not auto or error <= VERIFY_TOL or 2 * n > VERIFY_MAX_PHASES:
            break
        n *= 2
    measured = {
        "phases": n, "mean": float(e.mean()), "minimum": float(e.min()), "maximum": float(e.max()),
        "sampling_error": error, "seconds": seconds, "version": a.version(),
    }  # fmt: skip
    return cp.replaced(stepped=replace(ans, verify=measured))
