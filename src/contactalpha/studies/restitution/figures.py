"""Figure: Newton's e_N against Stronge's eps for several loads xi."""

from typing import Any

import numpy as np
from matplotlib.lines import Line2D

from contactalpha.plotting import COLUMN_WIDTH, new_figure

# The separation boundary eps_b of each load: a dotted vertical line in the load's colour.
BOUNDARY_STYLE: dict[str, Any] = dict(lw=0.6, ls=":")


def restitution_figure(ds):
    """e_N(eps) per xi from ``restitution_curves``; the diagonal is the unloaded e_N = eps.

    A dotted line in each load's colour marks its separation boundary eps_b (below it the
    impact does not separate and e_N = 0); the legend says so.
    """
    fig, ax = new_figure(width=COLUMN_WIDTH * 1.4, aspect=0.8)
    eps = ds["eps"].values
    ax.plot([0, 1], [0, 1], color="0.7", lw=0.8, ls="--", label="e_N = ε")
    for k, xi in enumerate(ds["xi"].values):
        e_n = ds["e_n"].isel(xi=k).values
        eps_b = float(ds["eps_boundary"].isel(xi=k))
        # The boundary point joins the zero branch to the separating one.
        x = np.concatenate([eps[eps < eps_b], [eps_b] if eps_b > 0 else [], eps[eps >= eps_b]])
        y = np.concatenate([e_n[eps < eps_b], [0.0] if eps_b > 0 else [], e_n[eps >= eps_b]])
        (line,) = ax.plot(x, y, lw=1.2, label=f"ξ = {xi:g}")
        if eps_b > 0:
            ax.axvline(eps_b, color=line.get_color(), **BOUNDARY_STYLE)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_xlabel("Stronge's energetic restitution ε")
    ax.set_ylabel("Newton's kinematic restitution e_N")
    handles, _ = ax.get_legend_handles_labels()
    handles.append(
        Line2D([], [], color="0.3", label="separation boundary ε_b:\nbelow it e_N = 0", **BOUNDARY_STYLE)
    )
    ax.legend(handles=handles, loc="upper left")
    return fig
