"""The alpha(eps, xi) surface (the paper's Fig. 4) as an xarray Dataset, computed in chunks.

A surface is ``solve_alpha`` over a grid: dims ``epsilon`` and ``xi``.  Each
point is solved from a guess that depends on its own ``(eps, xi)`` only
(``solver.py``), so splitting the grid into chunks of ``xi`` columns, solving
them in separate processes and merging them gives the same bits as one run.
Chunk ``k`` of ``n`` holds the columns ``xi[k::n]``: every chunk then mixes
cheap and expensive columns and the jobs cost about the same.

The grid is built from the workflow's ``surface`` config section
(``grid_from_config``); ``check_surface_config`` rejects what the JSON schema
cannot (unsorted values, ranges that do not fit their step).
"""

import hashlib
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from contactalpha.engine.codes import (
    CREEP,
    END_STATES,
    N_SOLVE_OUT,
    NO_RESTITUTION,
    NONSEPARATION,
    OK,
    SEPARATION,
    SOL_ALPHA,
    SOL_EPS,
    SOL_IMPACTS,
    SOL_NFEV,
    SOL_STATE,
    SOL_STATUS,
    SOL_STEPS,
    SOL_X_END,
    SOL_X_MAX,
    STATUS,
)
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL
from contactalpha.engine.solver import EPS_TOL, solve_table
from contactalpha.engine.table import DEFAULT_FILE, table_arrays
from contactalpha.io import json_text
from contactalpha.models.shen import EQ26_PUBLISHED
from contactalpha.provenance import git_commit, history_line
from contactalpha.validation import check_eps, check_xi
from contactalpha.version import __version__

# Grid values are rounded to this many significant digits, so that 0.01 * 37
# is stored as the double nearest to 0.37 and overlapping ranges merge exactly.
GRID_DIGITS = 12
# How far (stop - start) / step may be from an integer and still count as one.
STEP_FIT_RTOL = 1e-9
# Points solved per call of the jitted kernel when progress is reported.
BLOCK_POINTS = 400
# Largest distance at which a requested xi (a section) counts as a grid value.
XI_MATCH = 1e-9
# Seconds between two progress log lines.
PROGRESS_EVERY = 5.0


@dataclass(frozen=True)
class SolverSettings:
    """Root-finder and integrator settings of every surface point (``solve_alpha``'s own defaults).

    They are the defaults of the workflow's ``surface.solver`` section
    (tests/workflow/test_settings.py diffs the two).
    """

    tol: float = EPS_TOL
    rtol: float = RTOL
    atol: float = ATOL
    max_steps: int = MAX_STEPS


@dataclass(frozen=True)
class SurfaceFigureSettings:
    """Settings of Fig. 5 and the summary's section: the workflow's ``surface.figures`` section.

    ``section_xi`` is the xi of the alpha(eps) section (the paper's Fig. 5 uses 0.2; it must be on
    the grid); ``eq26`` the constants ``tau``, ``sigma``, ``beta`` of Eq. 26 drawn beside it
    (the paper's, ``shen.EQ26_PUBLISHED``).
    """

    section_xi: float = 0.2
    eq26: dict = field(default_factory=lambda: dict(EQ26_PUBLISHED))


@dataclass(frozen=True)
class SurfaceSettings:
    """The surface stage's settings: the workflow's ``surface`` section (defaults: the paper's Fig. 4 grid).

    ``epsilon`` and ``xi`` are the grid specs read by ``grid_from_config`` (``range`` with
    ``start, stop, step``; for xi also ``log_range`` with ``start, stop, num``; extra ``values``;
    an axis is the sorted union of its parts).  ``chunks`` is the number of jobs (it changes no bit).
    """

    epsilon: dict = field(
        default_factory=lambda: {"range": {"start": 0.01, "stop": 0.99, "step": 0.01}, "values": []}
    )
    # The log-spaced columns resolve the steep ridge at small eps, 1e-4 < xi < 1e-2
    # (docs/science.md, "Shape of the surface").
    xi: dict = field(
        default_factory=lambda: {
            "range": {"start": 0.0, "stop": 0.99, "step": 0.01},
            "log_range": {"start": 1e-5, "stop": 0.01, "num": 25},
            "values": [],
        }
    )
    solver: SolverSettings = field(default_factory=SolverSettings)
    chunks: int = 2
    figures: SurfaceFigureSettings = field(default_factory=SurfaceFigureSettings)

    def grid(self):
        """The ``(eps, xi)`` grid (``grid_from_config``)."""
        return grid_from_config({"epsilon": self.epsilon, "xi": self.xi})


SOLVER_NAME = "contactalpha.solve_alpha: Newton on ln eps vs ln alpha, DOP853 impacts, exact at xi = 0"


VARIABLES = {
    "alpha": ("1", "hysteresis damping factor alpha"),
    "state": ("1", "end state of the impact at alpha"),
    "status": ("1", "solver status (0 = ok)"),
    "eps_reached": ("1", "Stronge restitution coefficient reached at alpha"),
    "lambda": ("1", "end compression over maximum compression x_end / x_max"),
    "x_max": ("delta_star", "maximum compression, scaled by the unloaded undamped one"),
    "x_end": ("delta_star", "compression at the end of the impact, scaled"),
    "impacts": ("1", "impacts integrated by the root finder"),
    "steps": ("1", "integrator steps, all impacts of the point"),
    "nfev": ("1", "right-hand-side evaluations, all impacts of the point"),
}


def _legend(codes):
    return "; ".join(f"{k}: {v}" for k, v in codes.items())


def _round_grid(values):
    return np.array([float(f"{v:.{GRID_DIGITS}g}") for v in np.asarray(values, dtype=float)])


def _linear(spec, key):
    start, stop, step = float(spec["start"]), float(spec["stop"]), float(spec["step"])
    if not step > 0:
        raise ValueError(f"{key}.step = {step!r} is outside the valid range (0, inf)")
    if stop < start:
        raise ValueError(f"{key}: stop = {stop!r} is below start = {start!r}; valid: stop >= start")
    count = (stop - start) / step
    if abs(count - round(count)) > STEP_FIT_RTOL * max(1.0, count):
        raise ValueError(
            f"{key}: stop - start = {stop - start!r} is not a multiple of step = {step!r}; "
            "valid: stop = start + n * step for an integer n"
        )
    return _round_grid(start + step * np.arange(round(count) + 1))


def _logarithmic(spec, key):
    start, stop, num = float(spec["start"]), float(spec["stop"]), int(spec["num"])
    if not 0 < start < stop:
        raise ValueError(f"{key}: start = {start!r}, stop = {stop!r}; valid: 0 < start < stop")
    return _round_grid(np.geomspace(start, stop, num))


def _increasing(values, key):
    """``values`` as a float array, or ``ValueError`` if not strictly increasing."""
    arr = np.asarray(values, dtype=float)
    bad = np.flatnonzero(np.diff(arr) <= 0)
    if bad.size:
        i = bad[0]
        what = "repeats" if arr[i + 1] == arr[i] else "comes after"
        raise ValueError(
            f"{key} is not strictly increasing: {float(arr[i + 1])!r} {what} {float(arr[i])!r}; "
            "valid: sorted values without duplicates"
        )
    return arr


def _explicit(values, key):
    return _round_grid(_increasing(values, key))


def _axis(spec, key):
    parts = [_explicit(spec.get("values") or [], f"{key}.values")]
    if spec.get("range"):
        parts.append(_linear(spec["range"], f"{key}.range"))
    if spec.get("log_range"):
        parts.append(_logarithmic(spec["log_range"], f"{key}.log_range"))
    axis = np.unique(np.concatenate(parts))
    if axis.size == 0:
        raise ValueError(f"{key} is empty; valid: at least one value from range, log_range or values")
    return axis


def grid_from_config(section, key="surface"):
    """The ``(eps, xi)`` grid of a ``surface`` config section.

    Parameters
    ----------
    section : dict
        With ``epsilon`` and ``xi`` entries, each holding ``range``
        (``start, stop, step``), for ``xi`` also ``log_range`` (``start, stop,
        num``), and ``values``.  An axis is the sorted union of its parts.
    key : str
        Name of the section, for error messages.

    Returns
    -------
    eps, xi : ndarray
        Strictly increasing; eps in (0, 1], xi in [0, 1).

    Raises
    ------
    ValueError
        Naming the config key at fault and the valid range.
    """
    eps = _axis(section["epsilon"], f"{key}.epsilon")
    xi = _axis(section["xi"], f"{key}.xi")
    if eps[0] <= 0.0 or eps[-1] > 1.0:
        bad = eps[(eps <= 0.0) | (eps > 1.0)]
        raise ValueError(f"{key}.epsilon has {float(bad[0])!r}, outside the valid range (0, 1]")
    if xi[0] < 0.0 or xi[-1] >= 1.0:
        bad = xi[(xi < 0.0) | (xi >= 1.0)]
        raise ValueError(f"{key}.xi has {float(bad[0])!r}, outside the valid range [0, 1)")
    return eps, xi


def check_surface_config(section, key="surface"):
    """Raise ``ValueError`` naming the key if the section's grid or figure settings are unusable."""
    _, xi = grid_from_config(section, key)
    section_xi = section.get("figures", {}).get("section_xi")
    if section_xi is not None and not np.any(xi == _round_grid([section_xi])[0]):
        raise ValueError(
            f"{key}.figures.section_xi = {section_xi!r} is not on the xi grid; "
            "valid: one of the xi values, e.g. add it to surface.xi.values"
        )


def chunk_columns(xi, chunk, chunks):
    """The ``xi`` values of chunk ``chunk`` of ``chunks``: ``xi[chunk::chunks]``."""
    if not 0 <= chunk < chunks:
        raise ValueError(f"chunk = {chunk!r} is outside the valid range [0, {chunks - 1}]")
    return np.asarray(xi)[chunk::chunks]


def _solve_blocks(eps, xi, solver, progress, guess="table"):
    """Solve the grid column block by column block; returns the (n_eps, n_xi, N_SOLVE_OUT) table."""
    table = np.empty((eps.size, xi.size, N_SOLVE_OUT))
    cols = max(1, BLOCK_POINTS // eps.size) if progress else xi.size
    start = time.perf_counter()
    for j in range(0, xi.size, cols):
        e, x = np.meshgrid(eps, xi[j : j + cols], indexing="ij")
        flat, _ = solve_table(e, x, guess=guess, **solver)
        table[:, j : j + cols] = flat.reshape(e.shape + (N_SOLVE_OUT,))
        if progress:
            progress(eps.size * min(j + cols, xi.size), eps.size * xi.size, time.perf_counter() - start)
    return table


def compute_surface(eps, xi, *, tol=EPS_TOL, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS, progress=None):
    """Damping factor alpha and the end state over the grid ``eps x xi`` (the paper's Fig. 4).

    Parameters
    ----------
    eps : array_like, shape (m,)
        Target restitution coefficients, strictly increasing, in (0, 1].
    xi : array_like, shape (n,)
        Influence factors, strictly increasing, in [0, 1).
    tol, rtol, atol, max_steps
        Solver settings, as in ``solve_alpha``.
    progress : callable or bool, optional
        ``progress(done_points, total_points, seconds)`` after each block of
        about ``BLOCK_POINTS`` points; True shows a tqdm bar.  None: silent.

    Returns
    -------
    xarray.Dataset
        Dims ``epsilon`` (m) and ``xi`` (n); variables ``VARIABLES``, each with
        ``units`` and ``long_name``; ``state`` and ``status`` are int8 codes
        with a ``legend`` attribute.  Failed points have NaN ``alpha`` and a
        nonzero ``status``.  Attributes record the solver, its settings, the
        starting guess and the table file it came from (``guess_record``), the
        compute time and a ``history`` line.
    """
    eps = _increasing(check_eps(np.atleast_1d(eps)), "eps")
    xi = _increasing(check_xi(np.atleast_1d(xi)), "xi")
    solver = {"tol": float(tol), "rtol": float(rtol), "atol": float(atol), "max_steps": int(max_steps)}
    if progress is True:
        progress = _tqdm_progress()
    started = time.time()
    clock = time.perf_counter()
    guess = guess_record()
    table = _solve_blocks(eps, xi, solver, progress, guess["guess"])
    seconds = time.perf_counter() - clock
    ds = _to_dataset(eps, xi, table)
    ds.attrs.update(
        solver=SOLVER_NAME,
        **solver,
        contactalpha_version=__version__,
        **guess,
        git_commit=git_commit(),
        compute_seconds=seconds,
        started=started,
        finished=started + seconds,
        history=history_line(f"compute_surface on {eps.size} x {xi.size} points in {seconds:.2f} s"),
    )
    return ds


def compute_chunk(eps, xi, chunk, chunks, **settings):
    """``compute_surface`` on the columns ``xi[chunk::chunks]``, tagged for ``merge_chunks``.

    ``settings`` are passed on to ``compute_surface`` (solver settings, ``progress``).
    """
    ds = compute_surface(eps, chunk_columns(xi, chunk, chunks), **settings)
    ds.attrs.update(chunk=int(chunk), chunks=int(chunks))
    ds.attrs["history"] += f" [chunk {chunk} of {chunks}]"
    return ds


def _tqdm_progress():
    from tqdm import tqdm

    bar = tqdm(unit="pt", desc="alpha surface")

    def update(done, total, _seconds):
        bar.total = total
        bar.update(done - bar.n)
        if done >= total:
            bar.close()

    return update


def guess_record(path=DEFAULT_FILE):
    """Which starting guess ``solve_alpha`` uses (``guess="table"``), as surface attributes.

    The guess changes the Newton path and so the last bits of alpha: ``guess`` is "table" with
    ``guess_table`` naming the file and its SHA-256, or "formula" with why the table is unusable
    (the surface is then solved from the exact unloaded alpha, ``guess="formula"``).
    """
    try:
        table_arrays(path)
    except (FileNotFoundError, ValueError) as err:
        return {"guess": "formula", "guess_table": f"none ({err})"}
    digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return {"guess": "table", "guess_table": f"{Path(path).name} sha256 {digest}"}


def _to_dataset(eps, xi, table):
    status = table[..., SOL_STATUS].astype(np.int8)
    ok = status == OK
    x_max, x_end = table[..., SOL_X_MAX], table[..., SOL_X_END]
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = np.where(ok & (x_max > 0), x_end / x_max, np.nan)
    data = {
        "alpha": np.where(ok, table[..., SOL_ALPHA], np.nan),
        "state": np.nan_to_num(table[..., SOL_STATE], nan=0.0).astype(np.int8),
        "status": status,
        "eps_reached": table[..., SOL_EPS],
        "lambda": lam,
        "x_max": x_max,
        "x_end": x_end,
        "impacts": table[..., SOL_IMPACTS].astype(np.int32),
        "steps": table[..., SOL_STEPS].astype(np.int64),
        "nfev": table[..., SOL_NFEV].astype(np.int64),
    }
    import xarray as xr  # here: the Snakefile imports this module (through config) and builds none

    ds = xr.Dataset(
        {name: (("epsilon", "xi"), values) for name, values in data.items()},
        coords={"epsilon": eps, "xi": xi},
    )
    for name, (units, long_name) in VARIABLES.items():
        ds[name].attrs.update(units=units, long_name=long_name)
    ds["state"].attrs["legend"] = _legend(END_STATES)
    ds["status"].attrs["legend"] = _legend(STATUS)
    ds["epsilon"].attrs.update(units="1", long_name="target restitution coefficient (Stronge)")
    ds["xi"].attrs.update(units="1", long_name="influence factor of the external load")
    return ds


def section_regions(state):
    """Regions I, II, III of the paper's Fig. 5 along a section, from the end states.

    The paper draws the regions without giving their limits.  Here they are the
    end-state bands that a section at fixed xi crosses as eps grows: I where
    the impact ends in creep or without restitution (heavy damping, the Eq. 26
    part of Eq. 39), II where it ends in non-separation, III where the bodies
    separate (the Eq. 25 part, derived for separating impacts).

    Parameters
    ----------
    state : array_like of int
        End-state codes (``codes.END_STATES``).

    Returns
    -------
    ndarray of int
        1, 2 or 3 per point; 0 where the point failed.
    """
    state = np.asarray(state)
    regions = np.zeros(state.shape, dtype=int)
    regions[np.isin(state, (CREEP, NO_RESTITUTION))] = 1
    regions[state == NONSEPARATION] = 2
    regions[state == SEPARATION] = 3
    return regions


def merge_chunks(paths, config=None):
    """Merge chunk files of one surface into the full Dataset, columns sorted by ``xi``.

    Parameters
    ----------
    paths : sequence of path-like
        Every chunk ``0 .. n-1`` of one run (attrs ``chunk``, ``chunks``), any order.
    config : dict, optional
        Configuration stored as JSON in the ``config`` attribute.

    Returns
    -------
    xarray.Dataset
        Bit-identical data to a single ``compute_surface`` call over the grid;
        ``compute_seconds`` is the sum over chunks, ``wall_seconds`` the span
        from the first chunk's start to the last one's end.

    Raises
    ------
    ValueError
        If chunks are missing or repeated, or were computed with other settings.
    """
    import xarray as xr

    from contactalpha.io import load_surface_chunk

    parts = [load_surface_chunk(p) for p in paths]
    if not parts:
        raise ValueError("paths is empty; valid: the files of chunks 0 .. n-1")
    chunks = int(parts[0].attrs["chunks"])
    found = sorted(int(p.attrs["chunk"]) for p in parts)
    if found != list(range(chunks)) or any(int(p.attrs["chunks"]) != chunks for p in parts):
        raise ValueError(
            f"chunks = {found} do not make up one run of {chunks}; valid: each of 0 .. {chunks - 1}"
        )
    for key in ("tol", "rtol", "atol", "max_steps", "solver", "guess", "guess_table"):
        values = {p.attrs[key] for p in parts}
        if len(values) > 1:
            raise ValueError(f"chunks disagree on {key} = {sorted(values)}; valid: one value")
    merged = xr.concat(parts, dim="xi", combine_attrs="override").sortby("xi")
    merged.attrs.clear()
    if not np.all(np.diff(merged.xi.values) > 0):
        raise ValueError("chunks share xi values; valid: disjoint slices of one grid")
    first = parts[0].attrs
    compute = float(sum(p.attrs["compute_seconds"] for p in parts))
    started = min(p.attrs["started"] for p in parts)
    finished = max(p.attrs["finished"] for p in parts)
    ordered = sorted(parts, key=lambda p: p.attrs["chunk"])
    history = [line for p in ordered for line in p.attrs["history"].splitlines()]
    history.append(history_line(f"merge_chunks of {chunks} chunks"))
    merged.attrs.update(
        {
            key: first[key]
            for key in ("solver", "tol", "rtol", "atol", "max_steps", "guess", "guess_table")
            + ("contactalpha_version",)
        },
        git_commit=git_commit(),
        config=json_text(config if config is not None else {}, sort_keys=True),
        chunks=chunks,
        compute_seconds=compute,
        wall_seconds=finished - started,
        started=started,
        finished=finished,
        history="\n".join(history),
    )
    return merged


def log_progress(logger, label, every=PROGRESS_EVERY):
    """A ``progress`` callback for ``compute_surface`` that logs points, points/s and time left.

    Logs at most once per ``every`` seconds, and always at the end.
    """
    last = [-np.inf]

    def report(done, total, seconds):
        if done < total and seconds - last[0] < every:
            return
        last[0] = seconds
        rate = done / seconds if seconds > 0 else float("inf")
        left = (total - done) / rate if rate > 0 else float("inf")
        logger.info(
            f"{label}: {done}/{total} points, {rate:.0f} points/s, {seconds:.1f} s, ~{left:.0f} s left"
        )

    return report
