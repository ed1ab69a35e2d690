"""The batch rules (issue 32, item 4): a row with no answer is NaN and flagged; the rest unchanged."""

import math

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.parameters.result import ContactParameters

NUMBER_FIELDS = (
    "xi",
    "damping",
    "physical_damping",
    "eps",
    "e_n",
    "delta_star",
    "e_n_half_speed",
    "e_n_twice_speed",
)


def _entries(value, cp):
    """A block value's entries, each of the batch's shape (MuJoCo's (n, 2) solref: its two columns)."""
    if isinstance(value, tuple):
        return value
    if np.ndim(value) > np.ndim(cp.ok):
        return tuple(np.moveaxis(np.asarray(value), -1, 0))
    return (value,)


def _rows(cp, keep):
    """Every per-scene number of ``cp`` at rows ``keep``, engine entries included, as a flat dict."""
    out = {f: np.asarray(getattr(cp, f))[keep] for f in (*NUMBER_FIELDS, "accel")}
    for f in ("end_state", "ok", "reason", "source"):
        out[f] = np.asarray(getattr(cp, f), dtype=object)[keep]
    for engine, block in cp.engines.items():
        for name, value in block.items():
            for j, x in enumerate(_entries(value, cp)):
                out[f"{engine}.{name}[{j}]"] = np.broadcast_to(x, np.shape(cp.ok))[keep]
    return out


def _numbers(cp, i):
    """Every number of row ``i`` (the scene's own load ``accel`` aside)."""
    values = [np.asarray(getattr(cp, f))[i] for f in NUMBER_FIELDS]
    for block in cp.engines.values():
        for value in block.values():
            entries = _entries(value, cp)
            values += [np.broadcast_to(x, np.shape(cp.ok))[i] for x in entries]
    return values


SCENES = {
    "mujoco": dict(mass=[0.5, 0.5, 0.2], stiffness=[1e4, 1e4, 3e4], approach_speed=[0.5, 0.5, 1.0]),
    "opensim": dict(mass=[0.5, 0.5, 0.2], stiffness=[1.4e8, 1.4e8, 1e7], approach_speed=[0.5, 0.5, 1.0]),
}


@pytest.mark.parametrize("engine", sorted(SCENES))
def test_a_row_without_an_answer_is_nan_in_every_number_and_the_others_are_bit_identical(engine):
    s = SCENES[engine]
    # Row 1's target is below every batch evaluator's smallest restitution (0.01): no answer.
    targets = [0.5, 0.001, 0.7]
    cp = ca.contact_parameters(e_N=targets, accel=9.81, engine=engine, **s)
    assert type(cp) is ContactParameters and list(cp.ok) == [True, False, True]
    assert "0.001" in cp.reason[1] and cp.reason[0] == cp.reason[2] == ""
    numbers = _numbers(cp, 1)
    assert numbers and all(math.isnan(x) for x in numbers)  # solref and solimp included
    # The other rows are bit for bit what a batch without row 1 gives.
    without = ca.contact_parameters(e_N=[0.5, 0.7], accel=9.81, engine=engine,
                                    **{k: [v[0], v[2]] for k, v in s.items()})  # fmt: skip
    got, want = _rows(cp, [0, 2]), _rows(without, [0, 1])
    assert got.keys() == want.keys()
    for key in got:
        np.testing.assert_array_equal(got[key], want[key], err_msg=key)


def test_mujocos_solref_of_a_flagged_row_is_nan_not_minus_zero():
    cp = ca.contact_parameters(e_N=[0.5, 0.001], mass=0.5, stiffness=1e4, approach_speed=0.5, accel=9.81,
                               law="mujoco_soft")  # fmt: skip
    assert cp.engines["mujoco"]["solref"].shape == (2, 2)
    stiffness, damping = cp.engines["mujoco"]["solref"].T
    assert np.isnan(stiffness[1]) and np.isnan(damping[1]) and damping[0] < 0.0


@pytest.mark.parametrize(
    "argument, values, index",
    [
        ("mass", [0.5, 0.5, math.nan, -1.0], 2),
        ("mass", [0.5, -0.5, 0.5, 0.5], 1),
        ("approach_speed", [0.5, 0.5, 0.5, math.inf], 3),
        ("e_N", [0.5, 1.5, 0.5, 0.5], 1),
        ("accel", [9.81, 9.81, -1.0, 9.81], 2),
    ],
)
def test_a_refused_batch_names_the_argument_and_its_first_bad_index(argument, values, index):
    scene = dict(mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=9.81, e_N=0.5)
    scene[argument] = values
    with pytest.raises(ValueError, match=rf"^{argument}\[{index}\] = {values[index]!r} is outside"):
        ca.contact_parameters(**scene)


def test_a_refused_force_batch_names_force():
    with pytest.raises(ValueError, match=r"^force\[1\] = -1.0 is outside"):
        ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1.4e8, approach_speed=0.5, force=[1.0, -1.0])
