"""Stronge's and Newton's restitution measured from an engine's sampled trajectory.

An engine gives states ``(t, delta, delta_dot)`` at report times; between two reports the motion
is taken as the cubic Hermite interpolant of the two states (its error is ``O(dt^4)``).  One
impact is cut out of the samples at these events, each located on the interpolant:

- touchdown: ``delta`` rises through 0 (or the first sample, when the run starts there);
- maximum compression: ``delta_dot`` falls through 0;
- separation: ``delta`` falls through 0 after the maximum;
- non-separation: ``delta_dot`` rises back through 0 while ``delta > 0``.

Stronge's coefficient follows from the energy identity of the paper's Eq. 24 in physical units,
with the load ``m a`` and the approach speed ``v_minus`` (docs/engines/index.md):

    eps^2 = (v_e^2 / 2 + a (delta_m - delta_e)) / (v_minus^2 / 2 + a delta_m),

and Newton's ``e_N = |v_e| / v_minus`` at separation, 0 otherwise.  When the samples end before
either end event (creep), the last sample stands in for the end and the state says so.
"""

from dataclasses import dataclass

import numpy as np

from contactalpha.engine.codes import CREEP, END_STATES, FAILED, NONSEPARATION, SEPARATION
from contactalpha.validation import check_positive, check_range


@dataclass(frozen=True)
class MeasuredImpact:
    """One impact as measured in an engine; SI units.

    Attributes
    ----------
    eps : Stronge's restitution from the energy identity (NaN if no maximum was found).
    e_n : Newton's kinematic restitution ``|v_e| / v_minus`` (0 without separation).
    state : "separation", "nonseparation", "creep" (samples ended first) or "failed".
    approach_speed : ``delta_dot`` at touchdown, m/s (the given one when the run starts in contact).
    t_touch, t_max, t_end : times of touchdown, maximum compression and end, s.
    delta_max, delta_end, v_end : deformation (m) at the maximum and the end, and ``delta_dot`` at the end.
    """

    eps: float
    e_n: float
    state: str
    approach_speed: float
    t_touch: float
    t_max: float
    t_end: float
    delta_max: float
    delta_end: float
    v_end: float

    @property
    def separated(self):
        """True if the bodies left each other."""
        return self.state == END_STATES[SEPARATION]


def hermite(t0, t1, y0, y1, v0, v1):
    """Cubic Hermite interpolant on ``[t0, t1]``: callables ``(position(s), velocity(s))``, s in [0, 1]."""
    h = t1 - t0
    c2 = 3.0 * (y1 - y0) - h * (2.0 * v0 + v1)
    c3 = -2.0 * (y1 - y0) + h * (v0 + v1)

    def pos(s):
        return y0 + s * (h * v0 + s * (c2 + s * c3))

    def vel(s):
        return v0 + s * (2.0 * c2 + 3.0 * s * c3) / h

    return pos, vel


def _root(f, lo=0.0, hi=1.0, iters=80):
    """Root of ``f`` on ``[lo, hi]`` by bisection (``f(lo)`` and ``f(hi)`` differ in sign)."""
    flo = f(lo)
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _crossing(t, d, dd, i, which):
    """Zero of the interpolated "position" or "velocity" inside ``[t[i], t[i+1]]``; returns (t, d, dd)."""
    pos, vel = hermite(t[i], t[i + 1], d[i], d[i + 1], dd[i], dd[i + 1])
    s = _root(pos if which == "position" else vel)
    return t[i] + s * (t[i + 1] - t[i]), float(pos(s)), float(vel(s))


def _first(mask, start=0):
    idx = np.nonzero(mask[start:])[0]
    return int(idx[0]) + start if idx.size else None


def measure_impact(t, delta, delta_dot, accel, approach_speed=None):
    """Measure the first impact in sampled states.

    Parameters
    ----------
    t : array_like, shape (n,)
        Report times, s, increasing.
    delta, delta_dot : array_like, shape (n,)
        Deformation (m, > 0 in contact) and its rate (m/s, > 0 while compressing).
    accel : float
        Constant acceleration ``a`` of the external load pressing the bodies together, m/s^2 (>= 0).
    approach_speed : float, optional
        ``delta_dot`` at touchdown, m/s.  Default: read at the touchdown found in the samples.

    Returns
    -------
    MeasuredImpact
    """
    t = np.asarray(t, dtype=float)
    d = np.asarray(delta, dtype=float)
    dd = np.asarray(delta_dot, dtype=float)
    if not (t.ndim == 1 and t.shape == d.shape == dd.shape and t.size >= 2):
        raise ValueError(
            f"t, delta, delta_dot must be 1-d of one length >= 2; got {t.shape}, {d.shape}, {dd.shape}"
        )
    a = float(check_range("accel", accel, 0.0, np.inf, hi_open=True))
    nan = np.nan
    # Touchdown.
    if d[0] >= 0.0:
        i0, t_touch, v_touch = 0, t[0], dd[0]
    else:
        i0 = _first((d[:-1] < 0.0) & (d[1:] >= 0.0))
        if i0 is None:
            return MeasuredImpact(nan, nan, END_STATES[FAILED], nan, nan, nan, nan, nan, nan, nan)
        t_touch, _, v_touch = _crossing(t, d, dd, i0, "position")
    v_minus = float(check_positive("approach_speed", v_touch if approach_speed is None else approach_speed))
    # Maximum compression.
    im = _first((dd[:-1] > 0.0) & (dd[1:] <= 0.0), i0)
    if im is None:
        return MeasuredImpact(nan, nan, END_STATES[FAILED], v_minus, t_touch, nan, nan, nan, nan, nan)
    t_max, d_max, _ = _crossing(t, d, dd, im, "velocity")
    # End: separation or the velocity's return to zero, whichever comes first.
    i_sep = _first((d[:-1] > 0.0) & (d[1:] <= 0.0), im + 1)
    i_stop = _first((dd[:-1] < 0.0) & (dd[1:] >= 0.0) & (d[1:] > 0.0), im + 1)
    # The maximum's own interval may hold the separation (a very short restitution).
    if i_sep is None and d[im + 1] <= 0.0:
        i_sep = im
    if i_sep is not None and (i_stop is None or i_sep <= i_stop):
        t_end, d_end, v_end = _crossing(t, d, dd, i_sep, "position")
        d_end, state = 0.0, SEPARATION
    elif i_stop is not None:
        t_end, d_end, v_end = _crossing(t, d, dd, i_stop, "velocity")
        v_end, state = 0.0, NONSEPARATION
    else:
        t_end, d_end, v_end, state = t[-1], d[-1], dd[-1], CREEP
    w_c = 0.5 * v_minus**2 + a * d_max
    eps2 = (0.5 * v_end**2 + a * (d_max - d_end)) / w_c
    e_n = abs(v_end) / v_minus if state == SEPARATION else 0.0
    return MeasuredImpact(
        eps=float(np.sqrt(max(eps2, 0.0))),
        e_n=float(e_n),
        state=END_STATES[state],
        approach_speed=v_minus,
        t_touch=float(t_touch),
        t_max=float(t_max),
        t_end=float(t_end),
        delta_max=float(d_max),
        delta_end=float(d_end),
        v_end=float(v_end),
    )


def measure_with_rest_check(samples, scene):
    """``measure_impact`` of ``samples``, and whether the ball left the ground after a non-separating end.

    ``samples.extra`` gains ``separated_later`` (it must stay False) and ``min_delta_after_end``.
    """
    t, d = samples.t, samples.delta
    result = measure_impact(t, d, samples.delta_dot, scene.accel, scene.approach_speed)
    after = t > result.t_end
    samples.extra["separated_later"] = bool(not result.separated and np.any(d[after] <= 0.0))
    samples.extra["min_delta_after_end"] = float(d[after].min()) if after.any() else np.nan
    return result
