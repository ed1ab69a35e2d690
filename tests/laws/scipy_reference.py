"""An independent reference for the law family: SciPy's DOP853 with terminal events, segment by segment.

Nothing here shares code with ``contactalpha.laws`` beyond the scaled force functions' formulas,
written out again below.  Each segment integrates one regime (contact: the law's force; flight: the
load alone) until an event: the maximum compression, the floor ``f = 0``, separation ``x = 0``,
capture (``v`` back to 0 from below) or, in flight, a re-contact.  Creep and no restitution are
recognised when the motion settles at the equilibrium within ``T_MAX``.  A law without the floor
(``FLOORLESS``) keeps its force, pulling, until ``x = 0``: one contact segment after the maximum.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp

T_MAX = 1e4
# A turn of v this close to the equilibrium (relative) is rounding: the motion creeps into it.
SETTLED = 1e-9
# Longest step of a flight segment.
FLIGHT_STEP = 1e-2
SQRT5_2 = math.sqrt(5.0) / 2.0
# Hertz with sqrt(delta) damping: eta delta_s^{3/2} / (m v) per unit of kappa.
VISCOELASTIC = 1.25**0.6
# The laws whose force is not floored at 0.
FLOORLESS = {"hertz_tsuji_unfloored", "hertz_viscoelastic_unfloored"}


def force(name, x, v, p, A, d):
    """The scaled force argument of each law, written independently of ``laws/forces.py``."""
    if x <= 0.0:
        return 0.0
    if name == "hunt_crossley":
        return 1.25 * x**1.5 * (1.0 + p * v)
    if name == "hunt_crossley_linear":
        return x * (1.0 + p * v)
    if name == "kelvin_voigt":
        return x + 2.0 * p * v
    if name == "mujoco_soft":
        return d * A + x + 2.0 * p * v
    if name in ("hertz_tsuji", "hertz_tsuji_unfloored"):
        return 1.25 * x**1.5 + SQRT5_2 * p * x**0.25 * v
    if name in ("hertz_viscoelastic", "hertz_viscoelastic_unfloored"):
        return 1.25 * x**1.5 + VISCOELASTIC * p * math.sqrt(x) * v
    raise KeyError(name)


def equilibrium(name, A, d):
    """Static compression of each law under load A."""
    if name.startswith("hertz") or name == "hunt_crossley":
        return (A / 1.25) ** (2.0 / 3.0)
    if name == "mujoco_soft":
        return (1.0 - d) * A
    return A


def reference_impact(name, p, A, d=0.0, rtol=1e-13, atol=1e-15):
    """(eps, e_N, end state) of one impact, by SciPy."""
    y = np.array([0.0, 1.0])
    t = 0.0
    x_m = None
    contact = True
    retake = False
    x_eq = equilibrium(name, A, d)
    floored = name not in FLOORLESS
    for _ in range(1000):
        compressing = x_m is None

        def rhs(_t, s, contact=contact):
            f = force(name, s[0], s[1], p, A, d)
            return [s[1], A - ((max(0.0, f) if floored else f) if contact else 0.0)]

        def ev_v(_t, s):
            return s[1]

        def ev_x(_t, s):
            return s[0]

        def ev_f(_t, s):
            # contact: the force reaching 0 from above; flight: rising above 0 (the law's expression
            # without the x <= 0 guard, so that the sign is that of the law near x = 0 too).
            x = max(s[0], 1e-300)
            return force(name, x, s[1], p, A, d)

        ev_v.terminal = True
        ev_v.direction = -1.0 if compressing else 1.0
        ev_x.terminal = True
        ev_x.direction = -1.0
        ev_f.terminal = True
        ev_f.direction = -1.0 if contact else 1.0
        floor_events = floored and ((contact and not compressing) or not contact)
        events = [ev_v, ev_x] + ([ev_f] if floor_events else [])
        # A flight is a parabola, which DOP853 would cross in one step, missing x = 0 inside it.
        step = FLIGHT_STEP if not contact or retake else np.inf
        sol = solve_ivp(
            rhs, (t, t + T_MAX), y, method="DOP853", rtol=rtol, atol=atol, events=events, max_step=step
        )
        hit = [(te[0], i) for i, te in enumerate(sol.t_events) if te.size]
        if not hit:
            # Settled: creep (after the maximum) or no restitution (before it).
            assert abs(sol.y[0, -1] - x_eq) < 1e-7 * max(x_eq, 1.0) and abs(sol.y[1, -1]) < 1e-9
            if compressing:
                return 0.0, 0.0, "no_restitution"
            eps2 = A * (x_m - x_eq) / (0.5 + A * x_m)
            return math.sqrt(max(eps2, 0.0)), 0.0, "creep"
        te, i = min(hit)
        if i == 0 and not compressing and sol.y_events[0][0][0] < 0.0 and not retake:
            # v turned below x = 0: x crossed 0 and back inside one step; retake it with short steps.
            retake = True
            continue
        retake = False
        y = sol.y_events[i][0].copy()
        t = te
        if i == 0 and compressing:
            x_m = y[0]
            y[1] = 0.0
            continue
        if i == 0:
            eps2 = A * (x_m - y[0]) / (0.5 + A * x_m)
            # A turn of v within rounding of the equilibrium is the creep's limit, not a capture.
            state = "creep" if abs(y[0] - x_eq) <= SETTLED * max(x_eq, 1.0) else "nonseparation"
            return math.sqrt(max(eps2, 0.0)), 0.0, state
        if i == 1:
            eps2 = (0.5 * y[1] ** 2 + A * x_m) / (0.5 + A * x_m)
            return math.sqrt(eps2), -y[1], "separation"
        contact = not contact
    raise RuntimeError("too many segments")
