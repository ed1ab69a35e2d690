"""The refinement's first step goes toward the target (issue 34: a flipped sign went unnoticed)."""

import math

import pytest

from contactalpha.adapters.base import refine


@pytest.mark.parametrize(("target", "start"), [(0.5, 0.4), (0.5, 1.0), (0.8, 0.1), (0.2, 2.5)])
def test_the_first_secant_step_moves_the_delivered_e_n_toward_the_target(target, start):
    calls = []

    def e_n_of(p):  # falls as the damping grows, as every engine's delivered e_N
        calls.append(p)
        return math.exp(-p)

    ref = refine(e_n_of, target, start, 1e-3)
    assert ref.status == "ok" and ref.e_n == pytest.approx(target, abs=1e-5)
    first, second = calls[0], calls[1]
    assert first == start
    assert abs(math.exp(-second) - target) < abs(math.exp(-first) - target)
    # Too much e_N (too little damping) steps the damping up by 5 %, too little steps it down.
    assert second == pytest.approx(start * (1.05 if math.exp(-start) > target else 0.95), rel=1e-15)
