"""The rebound of a contact read from its gap sampled in time: engine-independent."""

import math

import numpy as np
from numpy.typing import ArrayLike


def rebound_speed(t: ArrayLike, gap: ArrayLike) -> tuple[float, float]:
    """``(speed, time)`` at the gap's first upward crossing of 0 after it went negative.

    The speed is the derivative at the crossing of the parabola through the three samples around
    it (free flight is a parabola; a semi-implicit Euler trajectory's samples lie on one).
    ``(nan, nan)`` when the gap never penetrates or never comes back.

    Parameters
    ----------
    t, gap : (n,) sample times (s) and signed gaps (m).
    """
    t = np.asarray(t, dtype=float)
    g = np.asarray(gap, dtype=float)
    inside = np.flatnonzero(g < 0.0)
    if inside.size == 0:
        return math.nan, math.nan
    after = np.flatnonzero(g[inside[0] :] >= 0.0)
    if after.size == 0:
        return math.nan, math.nan
    k = inside[0] + after[0]  # first sample back at or above 0
    lo = max(k - 2, 0) if k + 1 >= len(g) else k - 1
    idx = np.arange(lo, lo + 3)
    if idx[-1] >= len(g) or idx[0] < 0:
        return math.nan, math.nan
    c = np.polyfit(t[idx] - t[k], g[idx], 2)
    roots = np.roots(c)
    roots = roots[np.isreal(roots)].real
    window = (t[k - 1] - t[k] - 1e-15, 1e-15)
    roots = roots[(roots >= window[0]) & (roots <= window[1])]
    if roots.size == 0:
        return math.nan, math.nan
    r = roots[0]
    return float(2.0 * c[0] * r + c[1]), float(t[k] + r)
