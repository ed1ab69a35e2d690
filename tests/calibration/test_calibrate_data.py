"""Drop-test CSVs: columns recognised, and every bad input named by row and column."""

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.calibration.data import from_arrays, read_drop

GOOD = [0.0, 0.5, 0.9, 1.22, 1.48, 1.69]


def _csv(tmp_path, header, rows):
    path = tmp_path / "drop.csv"
    path.write_text(header + "\n" + "\n".join(str(r) for r in rows) + "\n")
    return path


def test_times_column_with_unit_is_read(tmp_path):
    d = read_drop(_csv(tmp_path, "t (s)", GOOD))
    assert d.kind == "times"
    np.testing.assert_array_equal(d.values, GOOD)


def test_intervals_become_times_from_zero(tmp_path):
    d = read_drop(_csv(tmp_path, "dt", np.diff(GOOD).round(6)))
    assert d.kind == "times"
    np.testing.assert_allclose(d.values, GOOD, atol=1e-12)


def test_heights_and_trajectory_kinds(tmp_path):
    assert read_drop(_csv(tmp_path, "h [m]", [1.0, 0.6, 0.4, 0.3, 0.2])).kind == "heights"
    t = np.linspace(0, 1, 30)
    path = tmp_path / "traj.csv"
    path.write_text("t,z\n" + "\n".join(f"{a},{abs(np.sin(6 * a))}" for a in t))
    d = read_drop(path)
    assert d.kind == "trajectory" and d.count == 30


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ([0.0, 0.5, 0.4, 1.2, 1.4, 1.6], r"row 3, column 't \(s\)': time 0.4 is not after row 2's 0.5"),
        ([0.0, 0.5, 0.9, 1.4, 1.6, 1.7], r"row 4, column 't \(s\)': the interval 0.5 s before this impact"),
        ([0.0, 0.5, 0.9, 1.2], r"column 't \(s\)' has 4 impacts; at least 5"),
        ([0.0, 0.5, "nan", 1.2, 1.4, 1.6], r"row 3, column 't \(s\)': nan is not a finite number"),
        ([0.0, 0.5, "x", 1.2, 1.4, 1.6], r"row 3, column 't \(s\)': 'x' is not a number"),
    ],
)
def test_bad_times_are_named_by_row_and_column(tmp_path, rows, message):
    with pytest.raises(ValueError, match=message):
        read_drop(_csv(tmp_path, "t (s)", rows))


def test_rising_apex_and_unknown_columns_are_refused(tmp_path):
    with pytest.raises(ValueError, match=r"row 3, column 'h': apex 0.7 m is not below"):
        read_drop(_csv(tmp_path, "h", [1.0, 0.6, 0.7, 0.3, 0.2]))
    with pytest.raises(ValueError, match=r"no known columns"):
        read_drop(_csv(tmp_path, "speed", [1.0, 0.6]))
    with pytest.raises(ValueError, match=r"kind = 'bogus' is not one of"):
        from_arrays("bogus", values=GOOD)


def test_interval_tolerance_allows_jitter_but_not_a_missed_impact(tmp_path):
    jittered = [0.0, 0.1, 0.19, 0.27, 0.34, 0.4105]  # last interval 0.5 ms longer than the one before
    assert read_drop(_csv(tmp_path, "t", jittered)).count == 6
    with pytest.raises(ValueError, match=r"row 6, column 't'.* by more than 0.0001 s"):
        read_drop(_csv(tmp_path, "t", jittered), interval_tolerance=1e-4)


def test_header_units_are_honoured(tmp_path):
    t = [0.0, 0.5, 0.9, 1.22, 1.48, 1.69]
    seconds = read_drop(_csv(tmp_path, "t (s)", t)).values
    ms = read_drop(_csv(tmp_path, "t (ms)", [1e3 * x for x in t])).values
    assert ms == pytest.approx(seconds, rel=1e-15)
    h = [1.0, 0.64, 0.41, 0.26, 0.17]
    assert read_drop(_csv(tmp_path, "h [cm]", [100 * x for x in h])).values == pytest.approx(h, rel=1e-15)
    assert read_drop(_csv(tmp_path, "h (mm)", [1e3 * x for x in h])).values == pytest.approx(h, rel=1e-15)
    with pytest.raises(ValueError, match=r"column 't \(min\)': unit 'min' is not one of 's', 'ms'"):
        read_drop(_csv(tmp_path, "t (min)", t))


def test_semicolons_with_decimal_commas_are_read(tmp_path):
    path = tmp_path / "drop.csv"
    path.write_text("t (s);note\n0;a\n0,5;b\n0,9;c\n1,22;d\n1,48;e\n1,69;f\n")
    assert read_drop(path).values == pytest.approx([0.0, 0.5, 0.9, 1.22, 1.48, 1.69], rel=1e-15)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        # Sniffed as comma-separated: every number split in two, its integer part read as the time.
        (
            "t\n-0,012\n0,003\n0,5\n0,9\n1,22\n1,48\n",
            r"row 1 '-0,012' has 2 comma-separated cells and the header 1: decimal commas\?",
        ),
        (
            "t (s),note\n0,0,a\n0,5,b\n0,9,c\n1,22,d\n1,48,e\n",
            r"row 1 '0,0,a' has 3 .* header 2: decimal commas\?",
        ),
        (
            't\n"0,0"\n"0,5"\n"0,9"\n"1,22"\n"1,48"\n',
            r"row 1, column 't': '0,0' is not a number: a decimal comma\?",
        ),
    ],
)
def test_decimal_commas_in_a_comma_separated_file_are_named(tmp_path, text, message):
    path = tmp_path / "drop.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message) as info:
        read_drop(path)
    assert "separate the columns with ';' or a tab" in str(info.value)


def test_one_millisecond_jitter_is_accepted_but_a_missed_impact_is_not():
    from contactalpha.calibration import hypotheses, sequence
    from contactalpha.calibration.data import check_times

    t = sequence.simulate(
        hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": 1e8}, 0.05, 9.81, 2.0, 0.0, 20
    ).touchdowns
    rng = np.random.default_rng(0)
    for _ in range(30):
        noisy = t + rng.normal(0.0, 1e-3, t.size)
        check_times(noisy)  # each valid recording passes with the derived tolerance
        with pytest.raises(ValueError, match="a missed or extra impact"):
            check_times(np.delete(noisy, 8))


def test_long_recordings_are_capped_with_a_note(monkeypatch):
    from contactalpha.calibration import data, hypotheses, sequence

    t = sequence.simulate(
        hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": 1e8}, 0.05, 9.81, 2.0, 0.0, 12
    ).touchdowns
    monkeypatch.setitem(data.MAX_OBSERVATIONS, "times", 8)
    capped, note = data.capped(data.from_arrays("times", values=t))
    assert capped.count == 8 and capped.values == pytest.approx(t[:8]) and "first 8 of 12" in note
    lines = []
    cal = ca.calibrate(
        t, kind="times", mass=0.05, hypotheses=["constant_e"], intervals=False, progress=lines.append
    )
    assert cal.data.count == 8 and cal.notes == [note] and note in lines
