"""The law tables' polish and cuts do what they say (issue 34: two planted bugs went unnoticed)."""

from dataclasses import dataclass, replace

import numpy as np
import pytest

from contactalpha.laws import get_law
from contactalpha.laws.fast import CLOSED_FORM
from contactalpha.laws.table_build import cut_curve


@dataclass(frozen=True)
class CountingForward:
    """The closed form, counting how many points its (slow) inverse is asked for."""

    counts: dict

    def restitution(self, law, p, A, xi, kinematic):
        return CLOSED_FORM.restitution(law, p, A, xi, kinematic)

    def damping(self, law, target, kinematic, A, xi):
        self.counts["inverted"] = self.counts.get("inverted", 0) + target.size
        return CLOSED_FORM.damping(law, target, kinematic, A, xi)


@pytest.mark.parametrize("law", ["kelvin_voigt", "mujoco_soft"])
def test_the_secant_polishes_the_tables_misses_without_root_finding(law):
    law = get_law(law)
    counts = {}
    counted = replace(law, fast=replace(law.fast, forward=CountingForward(counts)))
    rng = np.random.default_rng(5)
    e, xi = rng.uniform(0.05, 0.95, 200), rng.uniform(0.0, 0.9, 200)
    p = counted.fast_damping(e, xi, "kinematic")
    delivered = CLOSED_FORM.restitution(law, p, np.atleast_1d(law.scaled_load(xi)), xi, True)
    assert np.max(np.abs(delivered - e)) <= 1e-9
    # The table alone misses by up to ~1e-7; a few secant steps fix nearly every point.
    assert counts.get("inverted", 0) <= 10


def test_tsujis_cuts_are_the_first_and_the_last_of_the_floor_and_the_creep_curves():
    # For Tsuji's law the last floor and the onset of creep cross: the table is cut along the
    # first of them met as the damping grows (the higher eps) and along the last (the lower).
    law = get_law("hertz_tsuji")
    xi = np.array([0.05, 0.3, 0.6, 0.9])
    floor = cut_curve(law, xi, "last_floor")
    creep = cut_curve(law, xi, "creep_onset")
    assert np.any(np.abs(floor - creep) > 1e-3)  # they differ at these loads
    first = cut_curve(law, xi, "first_of_floor_creep")
    np.testing.assert_allclose(first, np.maximum(floor, creep), atol=1e-9)
    np.testing.assert_allclose(cut_curve(law, xi, "both_floor_creep"), np.minimum(floor, creep), atol=1e-9)
