"""A single drop that can leave faster than it came is warned of at the front door (issue 44, S2).

The issue's MuJoCo scene (0.0444 kg, 73.7 N/m, 0.0901 m/s, 2.06 N on top of gravity, e_N 0.174 at
2 ms) has single drops up to e_N 1.25 (MuJoCo, read in the engine at 512 phases: up to 1.235).
"""

import warnings

import numpy as np
import pytest

from contactalpha import contact_parameters
from contactalpha.parameters.at_step import EnergyGainWarning
from contactalpha.parameters.result import stepped_lines

HEAVY = {"mass": 0.0444, "stiffness": 73.7, "approach_speed": 0.0901, "accel": 9.81 + 2.06 / 0.0444,
         "e_N": 0.174}  # fmt: skip


def test_a_drop_that_gains_energy_is_warned_of_with_its_largest_e_n():
    with pytest.warns(EnergyGainWarning, match=r"faster than it came: e_N up to 1\.24\d > 1") as record:
        cp = contact_parameters(**HEAVY, engine="mujoco", timestep=0.002)
    assert record[0].filename == __file__  # the caller's line, not the package's
    ans = cp.stepped
    assert ans.status == "ok" and 1.2 < ans.maximum < 1.3
    assert f"{ans.maximum:.4g}" in str(record[0].message)
    assert any("faster than it came" in line for line in stepped_lines(ans))


def test_no_warning_where_every_drop_leaves_slower():
    with warnings.catch_warnings():
        warnings.simplefilter("error", EnergyGainWarning)
        cp = contact_parameters(mass=0.5, stiffness=2e4, approach_speed=0.5, accel=9.81, e_N=0.5,
                                engine="mujoco", timestep=0.002)  # fmt: skip
    assert cp.stepped.maximum < 1.0
    assert not any("faster than it came" in line for line in stepped_lines(cp.stepped))


def test_a_batch_names_how_many_rows_gain():
    """The issue's (1.02 kg, 749 N/m, 0.285 m/s, 98.4 N, 0.706) beside a scene without a gain."""
    rows = {"mass": np.array([1.02, 0.5]), "stiffness": np.array([749.0, 2e4]),
            "approach_speed": np.array([0.285, 0.5]), "accel": np.array([9.81 + 98.4 / 1.02, 9.81]),
            "e_N": np.array([0.706, 0.5])}  # fmt: skip
    with pytest.warns(EnergyGainWarning, match=r"in 1 of 2 rows: e_N up to 1\.36\d > 1") as record:
        cp = contact_parameters(**rows, engine="mujoco", timestep=0.002)
    assert f"{cp.stepped.maximum[0]:.4g}" in str(record[0].message) and cp.stepped.maximum[1] < 1.0


def test_params_prints_the_warning_once_in_its_block(capsys):
    """``contactalpha params --timestep``: the line in the printed block, no Python warning beside it."""
    from contactalpha.cli import main

    args = ["params", "--engine", "mujoco", "--timestep", "0.002", "--mass", "0.0444", "--stiffness", "73.7",
            "--speed", "0.0901", "--accel", str(HEAVY["accel"]), "--e-n", "0.174"]  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error", EnergyGainWarning)
        main(args)
    out = capsys.readouterr()
    assert "#   warning: a single drop can leave faster than it came: e_N up to 1.24" in out.out
    assert "EnergyGainWarning" not in out.err
