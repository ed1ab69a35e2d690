"""``results/summary.md``: the surface in numbers, generated from the data, nothing typed in."""

from datetime import UTC, datetime

import numpy as np

from contactalpha.engine.codes import END_STATES, STATUS
from contactalpha.models.shen import eq25, eq26

from .compute import XI_MATCH, section_regions

# Failed points listed one by one in the summary; the rest are counted.
MAX_FAILED_LISTED = 30


def _fmt(value):
    return f"{value:.6g}"


def _axis_line(name, values):
    diffs = np.diff(values)
    steps = f"{_fmt(diffs.min())} to {_fmt(diffs.max())}" if diffs.size else "-"
    return f"| {name} | {values.size} | {_fmt(values[0])} | {_fmt(values[-1])} | {steps} |"


def _grid(ds):
    eps, xi = ds["epsilon"].values, ds["xi"].values
    return [
        "## Grid",
        "",
        "| axis | points | first | last | spacing |",
        "|---|---|---|---|---|",
        _axis_line("epsilon", eps),
        _axis_line("xi", xi),
        "",
        f"{ds['alpha'].size} points; xi values below 0.01: {int(np.sum(xi < 0.01))} "
        f"(the log-spaced refinement of the ridge and xi = 0).",
        "",
        f"Solver: {ds.attrs['solver']}; tol = {ds.attrs['tol']:g}, rtol = {ds.attrs['rtol']:g}, "
        f"atol = {ds.attrs['atol']:g}, max_steps = {ds.attrs['max_steps']}.",
        f"Package {ds.attrs['contactalpha_version']}, git commit `{ds.attrs['git_commit']}`.",
    ]


def _timings(ds, chunks):
    points = ds["alpha"].size
    compute = float(ds.attrs["compute_seconds"])
    lines = [
        "## Timings",
        "",
        f"Surface compute time, summed over {len(chunks)} chunk jobs: {compute:.2f} s "
        f"({points / compute:.0f} points/s per job); first chunk start to last chunk end: "
        f"{float(ds.attrs['wall_seconds']):.2f} s.",
        "Integrator work: "
        f"{int(ds['steps'].sum())} steps, {int(ds['nfev'].sum())} right-hand-side evaluations, "
        f"{int(ds['impacts'].sum())} impacts.",
        "",
        "| chunk | points | compute (s) | points/s |",
        "|---|---|---|---|",
    ]
    for c in sorted(chunks, key=lambda c: c.attrs["chunk"]):
        n, s = c["alpha"].size, float(c.attrs["compute_seconds"])
        lines.append(f"| {c.attrs['chunk']} | {n} | {s:.2f} | {n / s:.0f} |")
    return lines


def _end_states(ds):
    ok = ds["status"].values == 0
    state = ds["state"].values
    lines = ["## End states", "", "| end state | points | share |", "|---|---|---|"]
    for code, name in END_STATES.items():
        count = int(np.sum(ok & (state == code))) if code else int(np.sum(~ok))
        lines.append(f"| {name} | {count} | {100 * count / state.size:.1f} % |")
    return lines


def _extremes(ds):
    alpha = ds["alpha"]
    top = alpha.where(np.isfinite(alpha), -np.inf).argmax(...)
    at = {dim: int(i) for dim, i in top.items()}
    point = ds.isel(at)
    miss = np.abs(ds["eps_reached"] - ds["epsilon"]).where(ds["status"] == 0)
    return [
        "## Largest alpha",
        "",
        f"alpha = {_fmt(float(point['alpha']))} at eps = {_fmt(float(point['epsilon']))}, "
        f"xi = {_fmt(float(point['xi']))} (end state {END_STATES[int(point['state'])]}, "
        f"{int(point['impacts'])} impacts, {int(point['steps'])} steps).",
        "",
        f"Largest |eps reached - eps target| over the solved points: {float(miss.max()):.2e}.",
    ]


def _failures(ds):
    failed = np.argwhere(ds["status"].values != 0)
    lines = ["## Failed points", "", f"{len(failed)} of {ds['alpha'].size} points failed."]
    if len(failed):
        lines += ["", "| eps | xi | status |", "|---|---|---|"]
        for i, j in failed[:MAX_FAILED_LISTED]:
            status = STATUS[int(ds["status"].values[i, j])]
            lines.append(f"| {_fmt(ds.epsilon.values[i])} | {_fmt(ds.xi.values[j])} | {status} |")
        if len(failed) > MAX_FAILED_LISTED:
            lines.append(f"| ... | ... | {len(failed) - MAX_FAILED_LISTED} more |")
    return lines


def _section(ds, xi, eq26_constants):
    section = ds.sel(xi=xi, method="nearest", tolerance=XI_MATCH)
    eps, alpha = section["epsilon"].values, section["alpha"].values
    regions = np.where(section["status"].values == 0, section_regions(section["state"].values), 0)
    ratio25 = alpha / eq25(eps)
    ratio26 = alpha / eq26(eps, **eq26_constants)
    lines = [
        f"## Section xi = {xi:g} (Fig. 5)",
        "",
        "Regions by end state (the paper draws them without limits): I creep or no restitution, "
        "II non-separation, III separation.",
        "",
        "| region | eps from | eps to | surface / Eq. 25 | surface / Eq. 26 |",
        "|---|---|---|---|---|",
    ]
    for region, name in ((1, "I"), (2, "II"), (3, "III")):
        sel = regions == region
        if not sel.any():
            lines.append(f"| {name} | - | - | - | - |")
            continue
        r25, r26 = ratio25[sel], ratio26[sel]
        lines.append(
            f"| {name} | {_fmt(eps[sel].min())} | {_fmt(eps[sel].max())} | "
            f"{_fmt(r25.min())} to {_fmt(r25.max())} | {_fmt(r26.min())} to {_fmt(r26.max())} |"
        )
    lines += [
        "",
        f"Eq. 26 with tau = {eq26_constants['tau']:g}, sigma = {eq26_constants['sigma']:g}, "
        f"beta = {eq26_constants['beta']:g}: "
        f"at eps = {_fmt(eps[0])} it gives {_fmt(eq26(eps[0], **eq26_constants))} "
        f"where the surface has {_fmt(alpha[0])}.",
    ]
    return lines


def surface_summary(ds, chunks, *, section_xi=None, eq26=None):
    """Markdown summary of a surface: grid, timings, end-state counts, largest alpha, failures.

    Parameters
    ----------
    ds : xarray.Dataset
        The merged surface (``surface.merge_chunks``).
    chunks : sequence of xarray.Dataset
        Its chunk datasets, for the per-chunk timings.
    section_xi : float, optional
        Also compare the section at this xi with the paper's Eqs. 25 and 26.
    eq26 : dict, optional
        ``tau``, ``sigma``, ``beta`` of Eq. 26; needed with ``section_xi``.

    Returns
    -------
    str
    """
    stamp = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    parts = [
        ["# alpha(eps, xi) surface: summary", "", f"Generated from `results/surface.h5` on {stamp}."],
        _grid(ds),
        _timings(ds, chunks),
        _end_states(ds),
        _extremes(ds),
        _failures(ds),
    ]
    if section_xi is not None:
        parts.append(_section(ds, section_xi, eq26))
    return "\n\n".join("\n".join(p) for p in parts) + "\n"
