"""A law's bounce sequence and what a drop test would observe of it (touchdown times, apexes, heights).

Flights are exact parabolas under the constant acceleration ``a = g + F/m``: a ball leaving
the ground at ``u`` lands again ``2 u / a`` later at ``u`` and peaks ``u^2 / (2 a)`` above the
ground.  Contacts are the law's (``hypotheses.Law.contact``); their durations are kept in the
touchdown times, since for a ball they are a fraction of a millisecond to milliseconds, at or
above a phone's timing jitter.  The height of the ball is measured from its touching position
(the ground at the ball's lowest point); inside a contact it is taken as 0 (the deformation is
micrometres).
"""

from dataclasses import dataclass

import numpy as np

# A rebound slower than this (m/s; an apex of 5e-20 m) ends the sequence: the ball rests for any
# instrument, and the next contact's scales would underflow.
REST_SPEED = 1e-9


@dataclass(frozen=True)
class Sequence:
    """Contacts of one sequence (SI units).

    Attributes
    ----------
    touchdowns : s, time of each touchdown, the first at ``t0``.
    v_in, v_out : m/s, approach and rebound speed (rebound 0 for the final contact).
    durations : s, contact durations (inf: the last contact creeps to rest).
    accel : m/s^2.
    ended : True when the last contact did not separate (the ball rests).
    status : "ok" or the kernel's failure.
    """

    touchdowns: np.ndarray
    v_in: np.ndarray
    v_out: np.ndarray
    durations: np.ndarray
    accel: float
    ended: bool
    status: str

    @property
    def e_n(self):
        """Newton's restitution of each contact."""
        return self.v_out / self.v_in

    @property
    def apexes(self):
        """Apex height of the flight after each contact, m (0 after the last)."""
        return self.v_out**2 / (2.0 * self.accel)


def simulate(law, values, mass, accel, v0, t0=0.0, contacts=30):
    """The first ``contacts`` contacts of ``law`` (fewer if the ball rests first).

    Parameters
    ----------
    law : hypotheses.Hypothesis
    values : dict
        The law's parameters, natural units.
    mass, accel : float
        kg and m/s^2.
    v0 : float
        First approach speed, m/s.
    t0 : float
        Time of the first touchdown, s.
    contacts : int
        Most contacts to compute.

    Returns
    -------
    Sequence
    """
    rows = []
    t, v, ended, status = float(t0), float(v0), False, "ok"
    for _ in range(contacts):
        c = law.contact(values, mass, accel, v)
        rows.append((t, v, c.v_out, c.duration))
        if c.status != "ok":
            status = c.status
            break
        if not c.separated or c.v_out < REST_SPEED:
            ended = True
            break
        t += c.duration + 2.0 * c.v_out / accel
        v = c.v_out
    arr = np.array(rows, dtype=float).reshape(-1, 4)
    return Sequence(arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3], float(accel), ended, status)


def touchdown_times(seq, count):
    """``count`` touchdown times; those the sequence lacks (the ball rested) are its rest time."""
    t = seq.touchdowns
    if t.size >= count:
        return t[:count]
    last = seq.durations[-1]
    rest = t[-1] + (last if np.isfinite(last) else 0.0)
    return np.concatenate([t, np.full(count - t.size, rest)])


def apex_heights(seq, count):
    """``count`` apex heights after the first ``count`` contacts (0 where the ball rested)."""
    h = seq.apexes
    return h[:count] if h.size >= count else np.concatenate([h, np.zeros(count - h.size)])


def height_at(seq, t):
    """Height of the ball's lowest point above the ground at times ``t`` (s), m.

    Before the first touchdown the ball falls onto it; after the last contact it rests at 0.
    """
    t = np.asarray(t, dtype=float)
    z = np.zeros_like(t)
    a = seq.accel
    before = t < seq.touchdowns[0]
    dt = seq.touchdowns[0] - t[before]
    z[before] = seq.v_in[0] * dt - 0.5 * a * dt**2
    for i in range(seq.touchdowns.size):
        lift = seq.touchdowns[i] + seq.durations[i]
        if not np.isfinite(lift) or seq.v_out[i] <= 0.0:
            break
        land = lift + 2.0 * seq.v_out[i] / a
        inside = (t > lift) & (t < land)
        s = t[inside] - lift
        z[inside] = seq.v_out[i] * s - 0.5 * a * s**2
    return z
