"""Numbers of the stepping figures: e_N over the touchdown phase, and the step a tolerance needs.

Both in MuJoCo's map for a free body (``stepping.mujoco_map``, impedance ``d``), in its scaling:
stiffness 1 s^-2 and approach speed 1 m/s, so a step is ``omega h`` and the load is
``A = a / (omega v)``; every scene with the same ``(zeta, A, omega h)`` has the same numbers.
"""

import numpy as np

from contactalpha.laws import get_law
from contactalpha.stepping.delivered import at_phases, over_phase
from contactalpha.stepping.registry import stepper
from contactalpha.stepping.stepsize import step_for_tolerance

# The figures' scene: damping ratio, scaled load, MuJoCo's impedance.
ZETA = 0.2
LOAD = 0.1
IMPEDANCE = 0.9
# Steps of the phase figure, omega h (10, 20 and 80 steps per half period pi / omega).
STEPS = (np.pi / 10, np.pi / 20, np.pi / 80)
PHASES = 2048
# The step-needed map's grid and tolerance on a single drop's e_N.
MAP_ZETAS = (0.05, 0.1, 0.2, 0.35, 0.5)
MAP_LOADS = (0.001, 0.05, 0.1, 0.2, 0.4)
MAP_TOL = 0.01


def _p(zeta):
    return stepper("mujoco").pack(stiffness=1.0, damping=2.0 * zeta, impedance=IMPEDANCE)


def _accel(load):
    # A drop needs a load pressing in (stepping.delivered): the smallest load is a thousandth.
    return max(load, 1e-3)


def phase_curves(zeta=ZETA, load=LOAD, steps=STEPS, phases=PHASES):
    """``{omega h: (phases, e_N per phase, PhaseStats)}`` for one scene at each step."""
    phi = (np.arange(phases) + 0.5) / phases
    out = {}
    for h in steps:
        e = at_phases("mujoco", _p(zeta), h, phi, 1.0, _accel(load))["e_n"]
        out[float(h)] = (phi, e, over_phase("mujoco", _p(zeta), h, 1.0, _accel(load)))
    return out


def continuous_e_n(zeta, load):
    """The continuous law's e_N at ``(zeta, A)`` (``laws.mujoco_soft``)."""
    law = get_law("mujoco_soft", impedance=IMPEDANCE)
    return float(law.restitution(zeta, law.load_factor(load), "kinematic"))


def step_needed(zetas=MAP_ZETAS, loads=MAP_LOADS, tol=MAP_TOL):
    """``omega h`` at which one drop stays within ``tol`` of the target (the law's e_N), per (load, zeta).

    NaN where the law does not bounce (no target) or no step on the ladder passes.
    """
    out = np.full((len(loads), len(zetas)), np.nan)
    for i, load in enumerate(loads):
        for j, zeta in enumerate(zetas):
            target = continuous_e_n(zeta, _accel(load))
            if not 0.02 < target < 0.98:
                continue
            need = step_for_tolerance("mujoco", _p(zeta), 1.0, _accel(load), target, tol)
            out[i, j] = need.timestep
    return out
