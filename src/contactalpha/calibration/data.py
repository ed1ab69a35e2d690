"""Drop-test data: read and check a CSV of impact times, apex heights or a tracked trajectory.

Three kinds, told apart by the CSV's column names (case-insensitive; other columns are ignored).
A unit in brackets or parentheses after a name is honoured: ``t (ms)``, ``h [cm]`` (``UNITS``
lists them; an unknown one is refused).  Comma, semicolon and tab separated files are read; in a
semicolon or tab separated file a decimal comma (``0,125``) is read as a decimal point; in a
comma-separated one it would split every number in two, and is refused by name.

``times``
    Column ``t``: the time of each impact (touchdown), s, one row per impact, in order; or
    column ``dt``: the interval between successive impacts, s (what phyphox's "(In)elastic
    collision" shows as "Time 1..5"), turned into times from 0.
``heights``
    Column ``h``: the drop height (row 1: the lowest point of the ball above the ground when
    it is released at rest) and then the apex height of each rebound, m.
``trajectory``
    Columns ``t`` and ``z``: a tracked trajectory, s and m, ``z`` the height of the ball's
    lowest point above the ground (0 while it touches), starting in the first fall.

Errors name the row (1-based, the header not counted) and the column.
"""

import csv
import math
import re
from dataclasses import dataclass

import numpy as np

# Fewest impacts of a sequence: 4 times are 3 intervals, barely enough for 4 fitted numbers.
MIN_IMPACTS = 5
# Fewest apexes (the drop height included) and trajectory samples.
MIN_HEIGHTS = 5
MIN_SAMPLES = 20
KINDS = ("times", "heights", "trajectory")
# How much longer than the one before an interval may be before it is refused, s.  The true
# intervals shorten, but at the last bounces by less than a millisecond (the contacts lengthen
# as the flights shrink), so timing jitter can reverse two of them; a missed impact or an echo
# changes an interval by a whole flight.  1 ms is about 4 sigma of the reversal for 0.1 ms jitter.
INTERVAL_TOLERANCE = 1e-3
# The derived tolerance: this many standard deviations of the change between two successive
# intervals (sqrt(6) sigma for independent timing errors of sigma on each impact time).
JITTER_SIGMAS = 4.0
# Fewest intervals the scatter is estimated from (fewer: the fit would absorb a missed impact).
JITTER_MIN_INTERVALS = 10
# Units a column header may carry, to SI: times (t, dt) and lengths (h, z).
UNITS = {
    "time": {"s": 1.0, "ms": 1e-3},
    "length": {"m": 1.0, "cm": 1e-2, "mm": 1e-3},
}
COLUMN_QUANTITY = {"t": "time", "dt": "time", "h": "length", "z": "length"}
_UNIT = re.compile(r"\s*[\(\[](.*)[\)\]]\s*$")
# A number written with a decimal comma (0,125; -1,5).
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+$")
DECIMAL_COMMA_FIX = (
    "in a comma-separated file write decimal points (0.125), or separate the columns with ';' or a tab "
    "(a decimal comma is then read)"
)


@dataclass(frozen=True)
class DropData:
    """Checked drop-test observations.

    Attributes
    ----------
    kind : one of ``KINDS``.
    t : s, impact times (``times``) or sample times (``trajectory``); empty for ``heights``.
    values : the observations fitted: impact times, heights, or heights z.
    source : where they came from (file name or "array").
    """

    kind: str
    t: np.ndarray
    values: np.ndarray
    source: str = "array"

    @property
    def count(self):
        """Number of observations."""
        return int(self.values.size)


def _column_key(name):
    return _UNIT.sub("", name.strip()).strip().lower()


def unit_scale(header):
    """The factor to SI of the unit in ``header``'s brackets (1 without one); ValueError if unknown."""
    match = _UNIT.search(header.strip())
    if match is None:
        return 1.0
    unit = match.group(1).strip()
    table = UNITS[COLUMN_QUANTITY[_column_key(header)]]
    if unit not in table:
        raise ValueError(f"column {header!r}: unit {unit!r} is not one of {', '.join(map(repr, table))}")
    return table[unit]


def _floats(rows, column, header, decimal_comma=False):
    """Column ``header`` of ``rows`` as floats in SI; ValueError naming the row and column if not numbers."""
    out = np.empty(len(rows))
    scale = unit_scale(header)
    for i, row in enumerate(rows):
        try:
            cell = row[column].strip()
            out[i] = float(cell.replace(",", ".") if decimal_comma else cell) * scale
        except (ValueError, IndexError):
            cell = row[column] if column < len(row) else ""
            hint = f": a decimal comma? {DECIMAL_COMMA_FIX}" if _DECIMAL_COMMA.match(cell.strip()) else ""
            raise ValueError(f"row {i + 1}, column {header!r}: {cell!r} is not a number{hint}") from None
    return out


def _check_finite(values, header):
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise ValueError(
            f"row {bad[0] + 1}, column {header!r}: {float(values[bad[0]])!r} is not a finite number"
        )


def timing_jitter(t):
    """Estimated standard deviation (s) of the timing error of each impact time in ``t``.

    The log of the intervals is nearly linear in the impact's index (the flights shrink by a factor
    e_N each), so its third differences hold little but the timing errors, and the median absolute
    deviation of them is robust to a missed impact (which shifts every later index by one: a
    global fit would take that for scatter).  0 with fewer than ``JITTER_MIN_INTERVALS`` intervals.
    """
    dt = np.diff(np.asarray(t, dtype=float))
    if dt.size < JITTER_MIN_INTERVALS or np.any(dt <= 0.0):
        return 0.0
    # Third differences of log(dt) cancel the trend locally; scaled by the interval they are the
    # fourth differences of the times, sqrt(70) sigma, and a missed impact spoils only four of them.
    d3 = np.diff(np.log(dt), 3) * dt[1:-2]
    scatter = 1.4826 * np.median(np.abs(d3 - np.median(d3))) * math.sqrt(2.0 / 70.0)
    return float(scatter / math.sqrt(2.0))


def interval_tolerance_for(t):
    """The default tolerance of ``check_times``: ``INTERVAL_TOLERANCE`` or the recording's jitter.

    ``JITTER_SIGMAS`` standard deviations of the change between successive intervals
    (``sqrt(6) timing_jitter(t)``), never less than ``INTERVAL_TOLERANCE``.
    """
    return max(INTERVAL_TOLERANCE, JITTER_SIGMAS * math.sqrt(6.0) * timing_jitter(t))


def check_times(t, header="t", tolerance=None):
    """Impact times: finite, strictly increasing, each interval not longer than the one before.

    A ball under a constant load loses speed at every contact, so its flights only shorten;
    an interval longer than the one before by more than ``tolerance`` (s; by default derived from
    the recording's own timing scatter, ``interval_tolerance_for``) means a missed or a spurious
    impact.
    """
    t = np.asarray(t, dtype=float)
    _check_finite(t, header)
    if t.size < MIN_IMPACTS:
        raise ValueError(
            f"column {header!r} has {t.size} impacts; at least {MIN_IMPACTS} are needed for a fit"
        )
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0.0)
    if bad.size:
        i = bad[0] + 1
        raise ValueError(
            f"row {i + 1}, column {header!r}: time {float(t[i])!r} is not after row {i}'s {float(t[i - 1])!r}"
        )
    derived = tolerance is None
    tolerance = interval_tolerance_for(t) if derived else tolerance
    longer = np.flatnonzero(dt[1:] > dt[:-1] + tolerance)
    if longer.size:
        i = longer[0] + 2
        raise ValueError(
            f"row {i + 1}, column {header!r}: the interval {dt[i - 1]:.6g} s before this impact is longer "
            f"than the one before it ({dt[i - 2]:.6g} s) by more than {tolerance:g} s"
            f"{' (derived from the recording)' if derived else ''}; a ball's bounces only shorten (a missed "
            "or extra impact? If the timing is that noisy, set interval_tolerance, --interval-tolerance, "
            "in s)"
        )
    return t


def check_heights(h, header="h"):
    """Drop height then apex heights: finite, > 0, each below the one before."""
    h = np.asarray(h, dtype=float)
    _check_finite(h, header)
    if h.size < MIN_HEIGHTS:
        raise ValueError(
            f"column {header!r} has {h.size} heights; at least {MIN_HEIGHTS} (the drop height and 4 "
            "apexes) are needed"
        )
    bad = np.flatnonzero(h <= 0.0)
    if bad.size:
        raise ValueError(f"row {bad[0] + 1}, column {header!r}: height {float(h[bad[0]])!r} must be > 0 m")
    up = np.flatnonzero(h[1:] >= h[:-1])
    if up.size:
        i = up[0] + 1
        raise ValueError(
            f"row {i + 1}, column {header!r}: apex {float(h[i])!r} m is not below the one before "
            f"({float(h[i - 1])!r} m)"
        )
    return h


def check_trajectory(t, z):
    """Tracked samples: finite, time strictly increasing, enough of them, some flight."""
    t, z = np.asarray(t, dtype=float), np.asarray(z, dtype=float)
    _check_finite(t, "t")
    _check_finite(z, "z")
    if t.size < MIN_SAMPLES:
        raise ValueError(f"column 't' has {t.size} samples; at least {MIN_SAMPLES} are needed")
    bad = np.flatnonzero(np.diff(t) <= 0.0)
    if bad.size:
        i = bad[0] + 1
        raise ValueError(
            f"row {i + 1}, column 't': time {float(t[i])!r} is not after row {i}'s {float(t[i - 1])!r}"
        )
    if not np.any(z > 0.0):
        raise ValueError("column 'z': no sample above the ground (z > 0); the ball never flies")
    return t, z


def from_arrays(kind, t=None, values=None, source="array", interval_tolerance=None):
    """``DropData`` of ``kind`` from arrays, checked (``values``: times, heights or z)."""
    if kind == "times":
        v = check_times(values if values is not None else t, tolerance=interval_tolerance)
        return DropData(kind, v, v, source)
    if kind == "heights":
        return DropData(kind, np.empty(0), check_heights(values), source)
    if kind == "trajectory":
        tt, z = check_trajectory(t, values)
        return DropData(kind, tt, z, source)
    raise ValueError(f"kind = {kind!r} is not one of {', '.join(map(repr, KINDS))}")


def read_drop(path, interval_tolerance=None):
    """Read a drop-test CSV (see the module docstring for its columns) into checked ``DropData``.

    ``interval_tolerance`` (s) is ``check_times``' allowance for an interval longer than the one
    before it (None: derived from the recording).
    """
    with open(path, newline="", encoding="utf-8-sig") as fh:
        sample = fh.read(4096)
        fh.seek(0)
        try:
            dialect = csv.Sniffer().sniff(sample, delimiters=",;\t")
        except csv.Error:
            dialect = csv.excel
        rows = [r for r in csv.reader(fh, dialect) if any(c.strip() for c in r)]
    if not rows:
        raise ValueError(f"{path}: empty file")
    header, body = rows[0], rows[1:]
    if dialect.delimiter == ",":
        _refuse_split_decimals(path, header, body)
    keys = {_column_key(h): i for i, h in reversed(list(enumerate(header)))}
    name = str(path)
    comma = dialect.delimiter in ";\t"

    def column(key):
        return _floats(body, keys[key], header[keys[key]], comma)

    if "t" in keys and "z" in keys:
        t, z = check_trajectory(column("t"), column("z"))
        return DropData("trajectory", t, z, name)
    if "t" in keys:
        t = check_times(column("t"), header[keys["t"]], interval_tolerance)
        return DropData("times", t, t, name)
    if "dt" in keys:
        dt = column("dt")
        _check_finite(dt, header[keys["dt"]])
        t = check_times(np.concatenate([[0.0], np.cumsum(dt)]), header[keys["dt"]], interval_tolerance)
        return DropData("times", t, t, name)
    if "h" in keys:
        return DropData("heights", np.empty(0), check_heights(column("h"), header[keys["h"]]), name)
    raise ValueError(
        f"{path}: no known columns in the header {header!r}; expected 't' (impact times), 'dt' "
        "(intervals), 'h' (drop and apex heights) or 't' and 'z' (trajectory)"
    )


def _refuse_split_decimals(path, header, body):
    """ValueError if a row of a comma-separated file has more cells than the header, digits among them.

    Decimal commas in a comma-separated file split every number in two (``0,125`` -> ``0``, ``125``):
    read as they stand, the times would be their integer parts.
    """
    for i, row in enumerate(body):
        if len(row) > len(header) and any(c.strip().isdigit() for c in row[1:]):
            raise ValueError(
                f"{path}: row {i + 1} {','.join(row)!r} has {len(row)} comma-separated cells and the header "
                f"{len(header)}: decimal commas? {DECIMAL_COMMA_FIX}"
            )


# Most observations fitted: impact times and heights beyond these are the slowest bounces, each
# as costly as the first and nearly at rest; a trajectory is thinned evenly to this many samples.
MAX_OBSERVATIONS = {"times": 200, "heights": 200, "trajectory": 5000}


def capped(data):
    """``(data, note)``: ``data`` within ``MAX_OBSERVATIONS`` (note None) or cut to it, saying how."""
    most = MAX_OBSERVATIONS[data.kind]
    if data.count <= most:
        return data, None
    if data.kind == "trajectory":
        keep = np.unique(np.linspace(0, data.count - 1, most).round().astype(int))
        note = f"{data.count} trajectory samples thinned evenly to {keep.size} (MAX_OBSERVATIONS)"
        return DropData(data.kind, data.t[keep], data.values[keep], data.source), note
    note = (
        f"fitting the first {most} of {data.count} {data.kind} (MAX_OBSERVATIONS): "
        "the rest are the slowest bounces"
    )
    t = data.t[:most] if data.t.size else data.t
    return DropData(data.kind, t, data.values[:most], data.source), note


def first_guess(data, accel):
    """Rough ``(v0, e)`` from the data alone (rigid bounces), to start the fit."""
    if data.kind == "heights":
        h = data.values
        e = float(np.median(np.sqrt(h[1:] / h[:-1])))
        return math.sqrt(2.0 * accel * h[0]), e
    if data.kind == "times":
        dt = np.diff(data.values)
        e = float(np.median(dt[1:] / dt[:-1]))
        return 0.5 * accel * dt[0] / e, e
    top = float(data.values.max())
    return math.sqrt(2.0 * accel * top), 0.8
