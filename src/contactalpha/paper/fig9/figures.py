"""Fig. 9: post- versus pre-restitution coefficient, one panel per load."""

from typing import Any

import numpy as np
from matplotlib.lines import Line2D

from contactalpha.models import MODELS
from contactalpha.plotting import new_figure

from .compute import nonseparation_mask

# Line style per model: the exact reference is drawn dark, dashed and on top of the others.
_STYLE = {"exact": dict(color="k", lw=1.0, ls="--", zorder=4)}
# Least spacing in pre-restitution eps between two non-separation markers of a curve: enough to
# show where the impacts stick, few enough that the curves under them (the exact line above all)
# stay visible.
MARKER_SPACING = 0.06
# Non-separation markers sit under the lines.
MARKER_STYLE: dict[str, Any] = dict(marker="x", ls="none", ms=3.5, mew=0.7, zorder=1.5)
# Height added for the legend below the panels, as a fraction of the figure's width.
LEGEND_ASPECT = 0.1


def _thinned(indices, pre, spacing=MARKER_SPACING):
    """Of ``indices`` (increasing ``pre``), the first and then each ``spacing`` or more further on."""
    kept: list[int] = []
    for i in indices:
        if not kept or pre[i] - pre[kept[-1]] >= spacing:
            kept.append(i)
    return np.asarray(kept, dtype=int)


def fig9(ds):
    """Post versus pre restitution, panels over ``ds.xi``; crosses mark non-separating impacts.

    The legend sits outside the panels, and each curve's non-separating impacts are marked by at
    least ``MARKER_SPACING`` apart, drawn under the lines.
    """
    n = ds.sizes["xi"]
    ncols = 3
    nrows = int(np.ceil(n / ncols))
    fig, axes = new_figure(ncols, nrows, aspect=0.33 * nrows + LEGEND_ASPECT, sharex=True, sharey=True)
    axes = np.atleast_1d(axes).ravel()
    pre = ds.eps_pre.values
    ns = nonseparation_mask(ds)
    for k, (ax, xi) in enumerate(zip(axes, ds.xi.values, strict=False)):
        ax.plot([0, 1], [0, 1], color="0.75", lw=0.8, zorder=0)
        for m in ds.model.values:
            name = str(m)
            post = ds.eps_post.sel(model=m, xi=xi).values
            style = dict(lw=1.2, zorder=2) | _STYLE.get(name, {})
            line = ax.plot(pre, post, label=MODELS[name].label if name in MODELS else name, **style)
            marks = _thinned(np.flatnonzero(ns.sel(model=m, xi=xi).values), pre)
            if marks.size:
                ax.plot(pre[marks], post[marks], color=line[0].get_color(), **MARKER_STYLE)
        ax.set_title(f"({'abcdefghi'[k]}) ξ = {float(xi):g}")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.set_aspect("equal")
    for ax in axes[n:]:
        ax.set_visible(False)
    for ax in axes[(nrows - 1) * ncols :]:
        ax.set_xlabel("pre-restitution ε")
    for ax in axes[::ncols]:
        ax.set_ylabel("post-restitution ε")
    handles, _ = axes[0].get_legend_handles_labels()
    handles.append(Line2D([], [], color="0.3", label="impact ends without separation", **MARKER_STYLE))
    fig.legend(handles=handles, loc="outside lower center", ncols=3, fontsize=7)
    return fig
