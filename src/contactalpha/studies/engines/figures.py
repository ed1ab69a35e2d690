"""Figure: target against delivered Stronge eps in the engines, ours beside the built-in mappings."""

import numpy as np

from contactalpha.engine.codes import STATE_CODES
from contactalpha.plotting import FULL_WIDTH, plt, use_style
from contactalpha.studies.engines.report import RUN_HEADS

# Marker, colour and size of each run (the built-in Hunt-Crossley runs of the two engines coincide).
RUN_STYLE = {
    "opensim_exact": ("o", "C0", 30),
    "exudyn_exact": ("x", "C1", 30),
    "exudyn_exact_implicit": ("+", "C2", 40),
    "opensim_hunt_crossley": ("s", "C3", 34),
    "exudyn_model1": ("D", "C4", 12),
    "exudyn_model2": ("^", "C5", 26),
}
# Floor of the error axis: errors below it are drawn on it.
ERROR_FLOOR = 1e-10


def roundtrip_figure(datasets):
    """One column per force: delivered eps against the target (top) and its error (bottom).

    Hollow markers: the ball did not leave the ground in the engine.
    """
    use_style()
    first = datasets[0]
    forces = first["force"].values
    eps = first["epsilon"].values
    fig, axes = plt.subplots(
        2,
        len(forces),
        figsize=(FULL_WIDTH, 0.62 * FULL_WIDTH),
        sharex=True,
        sharey="row",
        layout="constrained",
        squeeze=False,
    )
    for k, force in enumerate(forces):
        top, bottom = axes[0, k], axes[1, k]
        top.plot([0, 1], [0, 1], color="0.6", lw=0.8, zorder=0)
        for ds in datasets:
            for run in ds["run"].values:
                r = ds.sel(run=run).isel(force=k)
                marker, color, size = RUN_STYLE[str(run)]
                sep = (r["state_measured"].values == STATE_CODES["separation"]) | (
                    r["left_ground_after_end"].values > 0
                )
                y = r["eps_measured"].values
                err = np.maximum(np.abs(y - eps), ERROR_FLOOR)
                for mask in (sep, ~sep):
                    label = RUN_HEADS[str(run)] if mask is sep else None
                    if marker in "x+":  # line markers have no face: colour them whole
                        style = dict(marker=marker, s=size, color=color, lw=0.9)
                    else:
                        face = color if mask is sep else "none"
                        style = dict(marker=marker, s=size, facecolors=face, edgecolors=color, lw=0.9)
                    top.scatter(eps[mask], y[mask], label=label, **style)
                    bottom.scatter(eps[mask], err[mask], **style)
        top.set_title(f"F = {force:g} N, ξ = {float(first['xi'].isel(force=k).mean()):.3f}")
        top.set_ylim(0.0, 1.0)
        bottom.set_yscale("log")
        bottom.set_ylim(0.3 * ERROR_FLOOR, 1.0)
        bottom.set_xlabel("target ε")
        bottom.set_xlim(0.2, 1.0)
    axes[0, 0].set_ylabel("ε delivered in the engine")
    axes[1, 0].set_ylabel("|delivered − target|")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3)
    return fig
