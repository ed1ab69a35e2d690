"""The configuration a contact is tuned at: moved to first touch, and checked against joint limits.

``first_touch`` moves a configuration whose pair is apart (or overlapping) along the approach's
joint velocity to where the gap is zero (secant steps on the reader's gap): the whole mechanism
moves rigidly along the direction it approaches in, so a free fall's touchdown is where it meets
the surface.  Where the coordinates do not add (a free joint's quaternion) it refuses: the user
gives the configuration of touch.

``joint_limit_problems`` lists the joints whose coordinate lies outside its limits.
"""

from collections.abc import Callable

import numpy as np

from .contact import TOUCH_TOLERANCE, MechanismContact

# Secant steps of ``first_touch`` on the gap.
TOUCH_ITER = 40
# A pair landing on several points is one contact mode while its points' height spread is at most
# this fraction of the maximum compression (issue 43's MuJoCo box: e_N moves < 2e-3 up to 0.2,
# by -0.014 at 1 and -0.30 at 4, rocking).
LANDING_SPREAD = 0.2
# Points higher than this many maximum compressions above the first are not reached in the
# landing's first contact: the pair's e_N is then the first point's.
LANDING_REACH = 10.0


def _refuse(contact, why):
    return ValueError(
        f"the pair is {contact.gap:.3g} m apart at this configuration and {why}: give the configuration "
        "of touch (qpos)"
    )


def first_touch(
    read: Callable[[np.ndarray], MechanismContact], contact: MechanismContact
) -> tuple[MechanismContact, str]:
    """``(contact at first touch, a note line)``: ``contact``'s configuration moved along its approach.

    ``read(qpos)`` reads the contact at a configuration (the approach as the user gave it).
    ValueError where the coordinates do not add along the joint velocity, the approach does not
    close the gap, or no touching configuration is found.
    """
    q = np.asarray(contact.qpos, dtype=float)
    d = np.asarray(contact.qvel, dtype=float)
    if q.size != d.size:
        raise _refuse(contact, "its coordinates do not add along the approach (a free joint)")
    rate = float(np.asarray(contact.jacobian) @ d)  # the gap's rate along the approach
    if not rate < 0.0:
        raise _refuse(contact, "the approach does not close the gap")
    s0, g0 = 0.0, float(contact.gap)
    s1 = -g0 / rate
    c1 = read(q + s1 * d)
    for _ in range(TOUCH_ITER):
        if abs(c1.gap) <= 0.1 * TOUCH_TOLERANCE or c1.gap == g0:
            break
        s0, s1, g0 = s1, s1 - c1.gap * (s1 - s0) / (c1.gap - g0), c1.gap
        c1 = read(q + s1 * d)
    if not c1.at_touch:
        raise _refuse(contact, f"moving it along the approach found no touch (gap {c1.gap:.3g} m)")
    shown = " ".join(f"{x:.9g}" for x in c1.qpos)
    note = (f"the pair was {contact.gap:.3g} m apart at the given configuration: moved to first touch "
            f"along the approach (qpos + {s1:.6g} s x qvel): qpos = {shown}")  # fmt: skip
    return c1, note


def joint_limit_problems(contact: MechanismContact, base: str | None = None) -> list[str]:
    """One line per joint whose coordinate at ``contact.qpos`` lies outside the joint's limits."""
    q = np.asarray(contact.qpos, dtype=float)
    limits = JOINT_LIMITS.get(contact.engine)  # a reader without joint limits (a toy's) has none to check
    rows = limits(contact, base) if limits is not None else []
    out = []
    for name, index, lo, hi in rows:
        if not (lo - 1e-9 <= q[index] <= hi + 1e-9):
            out.append(f"joint {name!r} is at {q[index]:.6g}, outside its limits [{lo:.6g}, {hi:.6g}]")
    return out


def _mujoco_limits(contact, base=None):
    from .mujoco_model import load_model

    m = load_model(contact.model)
    rows = []
    for j in range(m.njnt):
        if int(m.jnt_limited[j]) and int(m.jnt_type[j]) in (2, 3):  # slide, hinge
            lo, hi = (float(x) for x in m.jnt_range[j])
            rows.append((m.joint(j).name, int(m.jnt_qposadr[j]), lo, hi))
    return rows


def _drake_limits(contact, base):
    from .drake_model import ParsedPlant

    p = ParsedPlant(contact.model, base=base or "fixed")
    plant = p.plant
    rows = []
    for j in plant.GetJointIndices():
        joint = plant.get_joint(j)
        if joint.num_positions() != 1:
            continue
        lo, hi = float(joint.position_lower_limits()[0]), float(joint.position_upper_limits()[0])
        if np.isfinite(lo) or np.isfinite(hi):
            rows.append((joint.name(), int(joint.position_start()), lo, hi))
    return rows


def max_compression(contact: MechanismContact, stiffness: float) -> float:
    """The undamped, unloaded maximum compression v sqrt(m_eff / k), m."""
    return float(contact.approach_speed) * float(np.sqrt(contact.effective_mass / float(stiffness)))


def landing_check(contact: MechanismContact, stiffness: float) -> str:
    """A note on a pair that touches at several points; ValueError where they do not land as one.

    The heights are the reader's (``mujoco_model.pair_heights``: MuJoCo's contact points of the
    pair within a look above touch).  Within ``LANDING_SPREAD`` of the maximum compression the
    landing is one contact mode (a flat box); between that and ``LANDING_REACH`` compressions the
    other points land during the first one's contact (rocking) and e_N is not one contact's: the
    pair is refused with the reason.  "" for a single point.
    """
    heights = contact.engine_row.get("pair_heights", ())
    if len(heights) < 2:
        return ""
    return landing_note(heights, max_compression(contact, stiffness))


def landing_note(heights, delta: float) -> str:
    """``landing_check``'s note on points at ``heights`` (m) with the maximum compression ``delta`` (m).

    ValueError where they rock; "" for a single point.
    """
    heights = sorted(float(h) for h in heights)
    if len(heights) < 2:
        return ""
    spread = [h - heights[0] for h in heights[1:]]
    together = [s for s in spread if s <= LANDING_SPREAD * delta]
    rocking = [s for s in spread if LANDING_SPREAD * delta < s <= LANDING_REACH * delta]
    if rocking:
        raise ValueError(
            f"the pair lands on {len(heights)} points whose heights spread by {max(rocking):.3g} m = "
            f"{max(rocking) / delta:.3g} x the maximum compression {delta:.3g} m (one contact mode up to "
            f"{LANDING_SPREAD:g}; its first points rebound while the others land, rocking): its e_N is "
            "not one contact's; tune it landing flat (qpos), or tune the points as separate pairs"
        )
    far = len(spread) - len(together)
    first = (f"the pair touches at {len(together) + 1} points within {LANDING_SPREAD:g} of the maximum "
             f"compression {delta:.3g} m (one contact mode: a simultaneous landing)" if together
             else f"the pair's lowest point lands alone (maximum compression {delta:.3g} m)")  # fmt: skip
    return first + (f"; {far} more points lie above {LANDING_REACH:g} compressions, not reached in this "
                    "contact" if far else "")  # fmt: skip


# Each model-file reader's joint limits: ``(name, qpos index, lower, upper)`` rows.
JOINT_LIMITS = {"mujoco": _mujoco_limits, "drake": _drake_limits}
