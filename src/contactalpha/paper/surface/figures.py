"""Figures of the alpha surface: Fig. 4 (the surface), Fig. 5 (a section at fixed xi), end states.

Each function takes the surface Dataset (``surface.compute_surface`` or
``io.load_surface``) and returns a matplotlib Figure; ``plotting.save_figure``
writes it.  The right-hand panels put xi on a symlog axis (log above
``XI_LINTHRESH``, linear below, so xi = 0 stays visible) and eps on a log axis:
that is where the steep ridge lives (docs/science.md, "Shape of the surface").
"""

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm
from matplotlib.patches import Patch

from contactalpha.engine.codes import END_STATES, STATE_CODES
from contactalpha.models import shen
from contactalpha.plotting import new_figure

from .compute import XI_MATCH, section_regions

# Below this xi the symlog axis is linear: half a cell below the smallest log-spaced xi.
XI_LINTHRESH = 1e-5
# Labelled ticks of the symlog xi axis (1e-5 would crowd xi = 0).
XI_TICKS = [0.0, 1e-4, 1e-3, 1e-2, 1e-1]
# Colours of the end states (and of failed points), colour-blind safe (Okabe-Ito).
STATE_COLOURS = {
    "failed": "#000000",
    "separation": "#0072B2",
    "nonseparation": "#E69F00",
    "creep": "#009E73",
    "no_restitution": "#CC79A7",
}
# Contour labels sit at least this far (axes fraction) from every edge of their panel, so that
# none is clipped; a contour with no point that far in gets no label.
LABEL_MARGIN = 0.08
# Shading of the regions I, II, III in Fig. 5.
REGION_COLOURS = {1: "#009E73", 2: "#E69F00", 3: "#0072B2"}
REGION_NAMES = {1: "I", 2: "II", 3: "III"}


def _zoom_axes(ax):
    """Symlog xi and log eps, so the ridge near (eps, xi) = (0, 0) is resolved."""
    ax.set_xscale("symlog", linthresh=XI_LINTHRESH, linscale=0.3)
    ax.set_xticks(XI_TICKS, [rf"$10^{{{np.log10(t):.0f}}}$" if t else "0" for t in XI_TICKS])
    ax.set_yscale("log")
    ax.set_xlabel(r"influence factor $\xi$ (symlog)")
    ax.set_ylabel(r"restitution coefficient $\varepsilon$ (log)")


def plot_alpha_surface(ds):
    """Fig. 4: alpha over (eps, xi) with a log colour scale; linear axes left, log axes right."""
    alpha = ds["alpha"].where(ds["alpha"] > 0)
    vmin, vmax = float(alpha.min()), float(alpha.max())
    norm = LogNorm(vmin, vmax)
    decades = 10.0 ** np.arange(np.ceil(np.log10(vmin)), np.floor(np.log10(vmax)) + 1)
    fig, axes = new_figure(2)
    xi, eps = ds["xi"].values, ds["epsilon"].values
    _zoom_axes(axes[1])
    for ax in axes:
        mesh = ax.pcolormesh(
            xi, eps, alpha.values, norm=norm, shading="nearest", cmap="magma", rasterized=True
        )
        if eps.size > 1 and xi.size > 1:
            lines = ax.contour(xi, eps, alpha.values, levels=decades, colors="w", linewidths=0.6)
            _label_inside(ax, lines)
    axes[0].set_xlabel(r"influence factor $\xi$")
    axes[0].set_ylabel(r"restitution coefficient $\varepsilon$")
    axes[0].set_title(r"(a) $\alpha(\varepsilon, \xi)$")
    axes[1].set_title(r"(b) the ridge at small $\varepsilon$, small $\xi$")
    bar = fig.colorbar(mesh, ax=axes, shrink=0.95)
    bar.set_label(r"hysteresis damping factor $\alpha$")
    _mark_failed(axes, ds)
    return fig


def _label_inside(ax, lines, margin=LABEL_MARGIN):
    """Label each contour level once, at its point farthest from the panel's edges.

    Matplotlib's own placement may put a label across an edge, where it is clipped.  Positions
    are chosen in axes fractions (so on log and symlog axes too); a level whose every point lies
    within ``margin`` of an edge is left unlabelled.
    """
    ax.autoscale_view()
    to_axes = ax.transData + ax.transAxes.inverted()
    levels, positions = [], []
    for level, path in zip(lines.levels, lines.get_paths(), strict=True):
        if path.vertices.size == 0:
            continue
        frac = to_axes.transform(path.vertices)
        room = np.min(np.hstack([frac, 1.0 - frac]), axis=1)
        best = int(np.argmax(room))
        if room[best] >= margin:
            levels.append(level)
            positions.append(tuple(path.vertices[best]))
    if levels:
        ax.clabel(lines, levels=levels, manual=positions, fmt=lambda v: f"{v:g}", fontsize=7)


def _mark_failed(axes, ds):
    failed = ds["status"] != 0
    if bool(failed.any()):
        e, x = np.nonzero(failed.values)
        for ax in axes:
            ax.plot(ds["xi"].values[x], ds["epsilon"].values[e], "x", color="c", ms=4, label="failed")
        axes[0].legend(loc="upper right")


def plot_end_states(ds):
    """Map of the end states over (eps, xi), points counted in the legend; failed points black."""
    codes = np.where(ds["status"].values == 0, ds["state"].values, STATE_CODES["failed"])
    names = [END_STATES[c] for c in sorted(END_STATES)]
    cmap = ListedColormap([STATE_COLOURS[n] for n in names])
    norm = BoundaryNorm(np.arange(len(names) + 1) - 0.5, len(names))
    fig, axes = new_figure(2)
    xi, eps = ds["xi"].values, ds["epsilon"].values
    for ax in axes:
        ax.pcolormesh(xi, eps, codes, cmap=cmap, norm=norm, shading="nearest", rasterized=True)
    axes[0].set_xlabel(r"influence factor $\xi$")
    axes[0].set_ylabel(r"restitution coefficient $\varepsilon$")
    axes[0].set_title(r"(a) end state of the impact at $\alpha(\varepsilon, \xi)$")
    _zoom_axes(axes[1])
    axes[1].set_title(r"(b) small $\varepsilon$, small $\xi$")
    handles = [
        Patch(color=STATE_COLOURS[n], label=f"{n.replace('_', ' ')} ({int(np.sum(codes == STATE_CODES[n]))})")
        for n in names
    ]
    fig.legend(handles=handles, loc="outside right center", title="end state (points)")
    return fig


def _region_spans(eps, regions):
    """(region, eps_from, eps_to) runs, split halfway between neighbouring grid points."""
    edges = np.concatenate([[eps[0]], 0.5 * (eps[1:] + eps[:-1]), [eps[-1]]])
    spans, start = [], 0
    for i in range(1, eps.size + 1):
        if i == eps.size or regions[i] != regions[start]:
            spans.append((int(regions[start]), edges[start], edges[i]))
            start = i
    return spans


def plot_section(ds, xi, *, tau, sigma, beta):
    """Fig. 5: alpha(eps) at one xi with regions I-III, Eq. 25 and Eq. 26, and their ratios.

    Parameters
    ----------
    ds : xarray.Dataset
        The surface; ``xi`` must be on its grid.
    xi : float
        The section (the paper: 0.2).
    tau, sigma, beta : float
        Constants of Eq. 26 at this xi (the paper: 0.01, 0.011, 0.113).
    """
    section = ds.sel(xi=xi, method="nearest", tolerance=XI_MATCH)
    eps = section["epsilon"].values
    alpha = section["alpha"].values
    ok = section["status"].values == 0
    regions = np.where(ok, section_regions(section["state"].values), 0)
    eq25 = shen.eq25(eps)
    eq26 = shen.eq26(eps, tau, sigma, beta)
    fig, (top, bottom) = new_figure(1, 2, width=5.0, aspect=1.05, sharex=True, height_ratios=[2, 1])
    for ax in (top, bottom):
        for region, lo, hi in _region_spans(eps, regions):
            if region:
                ax.axvspan(lo, hi, color=REGION_COLOURS[region], alpha=0.12, lw=0)
        ax.set_yscale("log")
    for region, lo, hi in _region_spans(eps, regions):
        if region:
            top.text(
                0.5 * (lo + hi), 1.02, REGION_NAMES[region], transform=top.get_xaxis_transform(), ha="center"
            )
    top.plot(eps[ok], alpha[ok], "k-", lw=1.6, label=rf"exact surface, $\xi$ = {xi:g}")
    top.plot(eps, eq25, "--", color="C3", label=r"Eq. 25: $3(1-\varepsilon)/(2\varepsilon)$")
    eq26_label = rf"Eq. 26: $e^{{-(\varepsilon+{tau:g})^2/{sigma:g}}}/{beta:g}$"
    top.plot(eps, eq26, ":", color="C2", lw=1.6, label=eq26_label)
    top.set_ylim(0.5 * np.nanmin(alpha[ok]), 2.0 * np.nanmax(alpha[ok]))
    top.set_ylabel(r"$\alpha$")
    top.legend(loc="upper right")
    bottom.plot(eps, alpha / eq25, "--", color="C3", label="surface / Eq. 25")
    bottom.plot(eps, alpha / eq26, ":", color="C2", lw=1.6, label="surface / Eq. 26")
    bottom.axhline(1.0, color="k", lw=0.6)
    bottom.set_ylim(0.3, 30.0)
    bottom.set_xlim(eps[0], eps[-1])
    bottom.set_xlabel(r"restitution coefficient $\varepsilon$")
    bottom.set_ylabel("ratio")
    bottom.legend(loc="upper right")
    fig.suptitle(
        "regions by end state: I creep / no restitution, II non-separation, III separation", fontsize=8
    )
    return fig
