"""Figure and table of the stepping engines' round trips (``studies.engines.stepping``).

The figure: one panel per engine, the delivered mean e_N against the target at each load (filled:
the lightest load, hollow: the others, shifted a little to the right), for the continuous law's
damping, the refined one and the engine's usual mapping.  The table (Markdown):
engine, law, the parameters it sets, and the measured accuracy of each parameter set.
"""

import numpy as np

from contactalpha.plotting import FULL_WIDTH, plt, use_style

# Parameter set -> (variable, marker, colour, legend).
SETS = {
    "refined": ("e_n_refined", "o", "C0", "ours (refined at the engine's step)"),
    "law": ("e_n_law", "s", "C1", "continuous law, no refinement"),
    "usual": ("e_n_usual", "^", "C3", "engine's usual mapping"),
}
# What each engine's parameters are (the adapters' names).
SETS_ENGINE = {
    "mujoco": "solref = (−k/m, −2ζ√(k/m)), solimp = (0.9, 0.9, …)",
    "drake": "point_contact_stiffness = 2k, hunt_crossley_dissipation = α/v on both geometries",
    "pybullet": "contactStiffness = 2k, contactDamping = ζ√(km) on both bodies",
}
USUAL_TEXT = {
    "mujoco": "dampratio ζ = −ln e/√(π² + ln² e)",
    "drake": "Drake's guidance d = 1/(e v)",
    "pybullet": "c = 2ζ√(km), ζ = −ln e/√(π² + ln² e)",
}


def stepping_figure(datasets):
    """Delivered e_N against the target, one panel per engine (skipped engines are left out)."""
    use_style()
    run = [ds for ds in datasets if not ds.attrs.get("skipped")]
    fig, axes = plt.subplots(
        1, max(len(run), 1), figsize=(FULL_WIDTH, 0.4 * FULL_WIDTH), sharey=True, layout="constrained",
        squeeze=False,
    )  # fmt: skip
    for ax, ds in zip(axes[0], run, strict=False):
        targets = ds["target"].values
        ax.plot([0, 1], [0, 1], color="0.6", lw=0.8, zorder=0)
        for var, marker, color, label in SETS.values():
            for j in range(ds.sizes["load"]):
                y = ds[var].isel(load=j).values
                ax.scatter(
                    targets + 0.012 * (j - 1), y, marker=marker, s=18, facecolors="none" if j else color,
                    edgecolors=color, lw=0.8, label=label if j == 0 else None,
                )  # fmt: skip
        ax.set_title(f"{ds.attrs['engine']} (h = {ds.attrs['timestep']:.3g} s)")
        ax.set_xlabel("target e_N")
        ax.set_xlim(0.0, 1.0)
        ax.set_ylim(-0.02, 1.0)
    axes[0, 0].set_ylabel("mean e_N delivered in the engine")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3)
    return fig


def _worst(ds, var):
    err = np.abs(ds[var].values - ds["target"].values[:, None])
    return float(np.nanmax(err)) if np.isfinite(err).any() else float("nan")


def stepping_table(datasets, notes=()):
    """Markdown table: engine, law, parameters, and the worst |delivered − target| of each set."""
    lines = [
        "| engine | law | parameters | step | ours (refined) | continuous law | usual mapping | s/scene |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for ds in datasets:
        e = ds.attrs["engine"]
        if ds.attrs.get("skipped"):
            lines.append(f"| {e} | — | — | — | skipped: {ds.attrs['skipped']} | | | |")
            continue
        secs = float(np.median(ds["seconds"].values))
        lines.append(
            f"| {e} | {ds.attrs['law']} | {SETS_ENGINE[e]} | {ds.attrs['timestep']:.4g} s "
            f"| {_worst(ds, 'e_n_refined'):.1e} | {_worst(ds, 'e_n_law'):.1e} "
            f"| {_worst(ds, 'e_n_usual'):.1e} ({USUAL_TEXT[e]}) | {secs:.2g} |"
        )
    lines += [
        "",
        "Worst |mean e_N delivered − target| over targets e_N = 0.2, 0.5, 0.8 and scaled loads "
        "A = a/(ωv) = 0.05, 0.3, 0.6, each contact spanning 30 (MuJoCo) or 60 (Drake, PyBullet) "
        "steps; e_N is averaged over touchdown phases within a step.  s/scene: the adapter's median "
        "wall time (law inverse, refinement, check).",
        *notes,
    ]
    return "\n".join(lines) + "\n"
