"""e_N read off a raw engine's sampled gap, as a user measures it: free flight on either side.

A semi-implicit Euler step's positions in free flight lie on one parabola: the entry rate is the
slope at zero of the parabola through the three samples before the first one inside, the exit
rate that through the first three samples back outside (no sample in contact in either).  A
free fall started ``tau`` before touchdown arrives at ``speed`` when its stored velocity is
``-(speed - g tau) + g h / 2`` (``start_rate``): the samples' parabola runs half a step behind.
"""

import numpy as np

G = 9.81


def start_rate(speed, tau, h):
    """The vertical velocity to store so that a fall from ``tau`` before touchdown arrives at ``speed``."""
    return -(speed - G * tau) + 0.5 * G * h


def _rate(t, g, idx, lo, hi):
    """The slope at zero of the parabola through samples ``idx``, its root taken between lo and hi
    (a supported body's gap is no exact parabola: then the real root nearest that interval)."""
    c = np.polyfit(t[idx], g[idx], 2)
    roots = [x.real for x in np.roots(c) if abs(x.imag) < 1e-12]
    r = min(roots, key=lambda x: max(lo - x, x - hi, 0.0))
    return 2 * c[0] * r + c[1]


def flight_e(gaps, h):
    """``-exit rate / entry rate`` of a gap sampled at step ``h`` with three samples back outside."""
    g = np.asarray(gaps, dtype=float)
    t = np.arange(g.size) * h
    k_in = int(np.flatnonzero(g < 0)[0])
    k_out = k_in + int(np.flatnonzero(g[k_in:] >= 0)[0])
    entry = _rate(t, g, np.arange(k_in - 3, k_in), t[k_in - 1], t[k_in])
    exit_ = _rate(t, g, np.arange(k_out, k_out + 3), t[k_out - 1], t[k_out])
    return -exit_ / entry


def done(gaps):
    """Whether a gap has come back outside for three samples after going in."""
    g = np.asarray(gaps)
    inside = np.flatnonzero(g < 0)
    return inside.size > 0 and g.size - 1 - inside[-1] >= 3 and np.all(g[inside[-1] + 1 :] >= 0)
