"""Reading bounces from per-step states (``impulse.delivered.read_bounces``), on hand-made sequences."""

import numpy as np

from contactalpha.impulse.delivered import read_bounces

A, H = 9.81, 0.001


def _fall(z, w, zs, ws):
    """Free steps (symplectic Euler, as the engines step) until the next would end below the plane."""
    while z + H * (w - A * H) > 0.0:
        w -= A * H
        z += H * w
        zs.append(z)
        ws.append(w)


def test_a_landing_a_float_step_above_the_plane_is_not_a_bounce():
    # a single-precision engine's landing can read 7.45e-10 m above the plane, moving up at 1e-12
    # m/s; then the ball rests, leaves at 0.3 m/s once, and lands for good
    zs, ws = [0.01], [0.5 * A * H]
    _fall(zs[-1], ws[-1], zs, ws)
    zs += [7.45e-10] * 20
    ws += [1e-12] * 20
    zs.append(0.3 * H)
    ws.append(0.3)
    _fall(zs[-1], ws[-1], zs, ws)
    zs += [0.0] * 5
    ws += [0.0] * 5
    got = read_bounces(np.array(zs), np.array(ws), A, H, 1e-5)
    assert got.count == 1
    assert abs(got.rebound_speeds[0] - 0.3) < A * H
