"""A restitution per step for an impulse engine: the loaded contact's table (``impulse.schedule``).

``touchdown_schedule`` tabulates, from the critical speed up to the approach speed, the e_N and
the contact duration that ``scene.bounces.predict_bounces`` takes for a contact at each speed;
``impulse.schedule.Rebounder`` then sets the engine's restitution before every step so that each
touchdown rebounds and lets go as that contact does.
"""

import math

import numpy as np

from contactalpha.engine.codes import OUT_STATE, OUT_T_END, OUT_V_END, SEPARATION
from contactalpha.engine.driver import ATOL, RTOL
from contactalpha.engine.table import XI_MAX
from contactalpha.impulse.schedule import TouchdownSchedule
from contactalpha.scene.ball import Scene, contact_alpha, run_contact
from contactalpha.scene.threshold import critical_speed
from contactalpha.validation import check_count, check_scalar

from .front_door import contact_parameters
from .impulse import DEFAULT_RADIUS, impulse_engines, is_impulse, resolve_timestep

# The table: speeds, and how far above the approach speed it reaches.
SCHEDULE_POINTS = 64
SCHEDULE_HEADROOM = 1.05


def touchdown_schedule(
    mass, stiffness, approach_speed, *, eps=None, e_N=None, accel=None, force=None,  # noqa: N803
    radius=None, engine="pybullet_impulse", timestep=None, points=SCHEDULE_POINTS,
):  # fmt: skip
    """The loaded contact per approach speed, for a restitution set each step (``impulse.schedule``).

    The contact is the default law's (Hunt-Crossley, n = 3/2; ``stiffness`` in N/m^1.5) with the
    material's ``eps``, or the one whose e_N at ``approach_speed`` is ``e_N``, under the load
    ``accel`` (or ``force``); the table runs from its critical speed to ``approach_speed``
    (``points`` speeds, log spaced), each with the e_N and the contact duration that
    ``scene.bounces.predict_bounces`` takes for a contact at that speed.

    Returns
    -------
    impulse.schedule.TouchdownSchedule
        At ``engine``'s step ``timestep`` (None or "default": its default); drive it with
        ``impulse.schedule.Rebounder`` before every step.
    """
    if not is_impulse(engine):
        raise ValueError(f"engine = {engine!r} is not an impulse engine; valid: {impulse_engines()}")
    h = resolve_timestep(engine, timestep)
    points = check_count("points", points, 2, 10_000)
    cp = contact_parameters(eps, mass, stiffness, approach_speed, e_N=e_N, accel=accel, force=force)
    m, k, v = float(mass), float(stiffness), float(approach_speed)
    r = DEFAULT_RADIUS if radius is None else check_scalar("radius", radius, 0.0, math.inf, lo_open=True)
    e, accel = float(cp.eps), float(cp.accel)
    critical = float(critical_speed(e, m, k, accel))
    sc = Scene(mass=m, radius=r, stiffness=k, approach_speed=v, force=0.0, eps=e, gravity=accel)
    speeds = np.geomspace(critical * (1.0 + 1e-9), v * SCHEDULE_HEADROOM, points)
    e_n, durations = np.empty(points), np.empty(points)
    for i, speed in enumerate(speeds):
        name = "exact" if sc.influence(speed) <= XI_MAX else "exact_solve"
        _, out, _, _, ts = run_contact(
            sc, speed, contact_alpha(sc, speed, name, "A"), "A", RTOL, ATOL, np.inf
        )
        e_n[i] = -out[OUT_V_END] if int(out[OUT_STATE]) == SEPARATION else 0.0
        durations[i] = out[OUT_T_END] * ts
    return TouchdownSchedule(speeds, e_n, durations, critical, accel, h, r, engine)
