"""What every time-stepping engine (MuJoCo, Bullet, Drake's discrete plant) shares.

**Semi-implicit Euler in flight.**  These engines update the velocity first and the position with
the new velocity: ``v' = v - a h``, ``z' = z + h v'`` (z the height above touchdown, v upward).
In flight under a constant acceleration ``a`` the positions then lie exactly on a parabola whose
velocity at a step's end is ``v - a h / 2`` (the stored velocity is the mean over the step).  So:

- a drop *arrives* with approach speed ``v_minus`` when its parabola crosses z = 0 at that speed:
  ``touchdown_state`` (``contactalpha.stepping.flight``, re-exported here) gives the stored state
  one step-fraction ``phase`` before the crossing;
- the *rebound* speed is the speed at z = 0 of the flight parabola through the first sample above
  the surface after the contact (read one free step later where that step is free, the same
  parabola): ``e_N = sqrt((v_j - a h/2)^2 + 2 a z_j) / v_minus``, whether the body rises on or
  lands again within the next step (a hop shorter than a step, under a heavy load at a coarse
  step).  A drop test reads the same number from the rebound height.

**Touchdown phase.**  A spring-dashpot contact switches its force on at touchdown, so where
touchdown falls within a step moves the rebound by O(h / contact time).  ``summarise`` averages
e_N over ``phases`` touchdowns spread evenly over one step and reports the spread; the
adapters warn when that spread, or the contact's length in steps, makes one drop's e_N untrustworthy.

**Refinement.**  Where the step moves the mean e_N away from the target by more than the
tolerance, ``calibrate`` adjusts the law's damping parameter by secant steps on the engine's own
drops until the mean delivered e_N is the target (``adapters.base.refine``).

**One implementation.**  ``SteppingAdapter`` measures every phase of a run and summarises them;
``delivered`` and ``calibrate`` come from ``adapters.base.Adapter``.  A stepping engine's ``run``
returns ``Samples`` whose ``extra`` holds ``z`` and ``v`` (one row per touchdown phase, height
above touchdown and upward velocity at every step) and ``timestep`` (s; 0 for a run that is not
stepped, which is then measured as a continuous one).
"""

import math
import warnings

import numpy as np

from contactalpha.adapters.base import DELIVERED_TOL, Adapter, Delivered
from contactalpha.adapters.measure import MeasuredImpact
from contactalpha.engine.codes import END_STATES, NONSEPARATION, SEPARATION
from contactalpha.stepping.flight import touchdown_state  # noqa: F401  (the adapters import it here)

# A contact spanning fewer steps than this is flagged: its rebound depends on the touchdown phase.
MIN_CONTACT_STEPS = 20
# Relative tolerance telling a free-flight step (the velocity changed by exactly -a h).
FREE_STEP_RTOL = 1e-9


class ContactStepsWarning(UserWarning):
    """A discrete engine's contact spans too few steps for its restitution to be trusted."""


def measure_steps(z, v, accel, h, approach_speed, free_rtol=FREE_STEP_RTOL):
    """The impact in per-step states ``z`` (height above touchdown, m) and ``v`` (upward, m/s).

    ``free_rtol`` tells a free-flight step (the velocity changed by ``-a h`` to that fraction of
    the larger of ``a h`` and the approach speed); an engine stepping in float32 (MuJoCo Warp,
    Newton) needs about 1e-6.

    Returns
    -------
    MeasuredImpact
        ``e_n`` from the flight parabola through the first sample above the surface after the
        first below it, a hop shorter than a step included (see the module docstring);
        ``eps`` from the energy identity with the deepest sampled deformation; ``t_*`` in steps
        times ``h`` from the first state.  No sample above the surface after it: "nonseparation"
        with e_N = 0.  Only the first impact counts: a later bounce inside the samples (a deeper
        one, say) is never mistaken for it.
    """
    z = np.asarray(z, dtype=float)
    v = np.asarray(v, dtype=float)
    dv = np.diff(v)
    free = (np.abs(dv + accel * h) <= free_rtol * max(accel * h, abs(approach_speed))) & (z[:-1] > 0.0)
    inside = np.nonzero(z < 0.0)[0]
    k0 = int(inside[0]) if inside.size else 0
    above = np.nonzero(z[k0:] > 0.0)[0] if inside.size else np.empty(0, dtype=int)
    j = k0 + int(above[0]) if above.size else z.size - 1  # the first sample above the surface after it
    if above.size and j + 1 < z.size and free[j]:
        j += 1  # the same parabola, one free step on (where ``stepping.drop`` reads it)
    i_max = int(np.argmin(z[: j + 1]))
    d_max = -float(z[i_max])
    w_c = 0.5 * approach_speed**2 + accel * d_max
    if above.size == 0:
        d_end = -float(z[-1])
        eps2 = accel * (d_max - d_end) / w_c
        return MeasuredImpact(
            float(np.sqrt(max(eps2, 0.0))), 0.0, END_STATES[NONSEPARATION], approach_speed,
            0.0, i_max * h, (z.size - 1) * h, d_max, d_end, 0.0,
        )  # fmt: skip
    s = v[j] - 0.5 * accel * h
    rebound = math.sqrt(s * s + 2.0 * accel * z[j])
    e_n = rebound / approach_speed
    eps2 = (0.5 * rebound**2 + accel * d_max) / w_c
    return MeasuredImpact(
        float(np.sqrt(eps2)), float(e_n), END_STATES[SEPARATION], approach_speed,
        0.0, i_max * h, j * h, d_max, 0.0, -rebound,
    )  # fmt: skip


def float_or_array(arr):
    """A float for a 0-d result, else the float array (the adapters' parameters keep their input's shape)."""
    arr = np.asarray(arr, dtype=float)
    return float(arr) if arr.ndim == 0 else arr


def summarise(e_n_per_phase, contact_steps, separated):
    """``Delivered`` from per-phase results (arrays over the phases)."""
    e = np.asarray(e_n_per_phase, dtype=float)
    return Delivered(float(e.mean()), float(np.ptp(e)), int(np.min(contact_steps)), bool(np.all(separated)))


def warn_if_coarse(engine, result, tol, min_steps=MIN_CONTACT_STEPS, stacklevel=3):
    """Warn (``ContactStepsWarning``): a contact under ``min_steps`` steps or a phase spread over ``tol``.

    The message says which of the two triggered it.
    """
    coarse, spread = result.contact_steps < min_steps, result.spread > tol
    if not (coarse or spread):
        return
    steps = f"the contact spans {result.contact_steps} steps"
    phases = f"one drop's e_N depends on where touchdown falls within a step by up to {result.spread:.3g}"
    if coarse and spread:
        why = f"{steps} (coarse below {min_steps}) and {phases} (over the tolerance {tol:g})"
    elif coarse:
        why = f"{steps} (coarse below {min_steps}); {phases} (within the tolerance {tol:g})"
    else:
        why = f"{phases} (over the tolerance {tol:g}), though {steps} ({min_steps} or more: not coarse)"
    warnings.warn(
        f"{engine}: {why}; the mean over touchdown phases is what the parameters deliver; "
        "a smaller time step narrows it",
        ContactStepsWarning,
        stacklevel=stacklevel,
    )


class SteppingAdapter(Adapter):
    """The shared measuring of a fixed-step engine (MuJoCo, Bullet, Drake's discrete plant).

    ``run`` returns ``Samples`` with ``extra`` ``z``, ``v`` (phases x steps) and ``timestep``; the
    rest of ``delivered`` and ``calibrate`` is ``adapters.base.Adapter``'s.
    """

    def measure(self, samples, scene):
        """The first phase's impact (``measure_steps``); every phase's e_N in ``samples.extra``.

        A run with ``extra["timestep"]`` 0 (not stepped) is measured as a continuous one.
        """
        x = samples.extra
        h = x["timestep"]
        if not h:
            return super().measure(samples, scene)
        rows = zip(x["z"], x["v"], strict=True)
        results = [measure_steps(z, v, scene.accel, h, scene.approach_speed) for z, v in rows]
        x["e_n_phases"] = np.array([r.e_n for r in results])
        x["contact_steps"] = np.array([round(r.t_end / h) for r in results])
        x["separated"] = np.array([r.separated for r in results])
        return results[0]

    def summary(self, result, samples, settings):
        """``Delivered`` over the touchdown phases (``summarise``); one drop for a run not stepped."""
        x = samples.extra
        if "e_n_phases" not in x:
            return super().summary(result, samples, settings)
        return summarise(x["e_n_phases"], x["contact_steps"], x["separated"])

    def check_delivered(self, got, settings):
        """Warn (``ContactStepsWarning``) when the contact is coarse at the engine's step."""
        if got.contact_steps is not None:
            warn_if_coarse(self.name, got, getattr(settings, "tol", DELIVERED_TOL), stacklevel=4)
