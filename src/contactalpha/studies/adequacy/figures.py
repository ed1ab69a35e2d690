"""Figures of the adequacy study: where each model is adequate, the cheapest one, xi_ignore, v_crit."""

import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

from contactalpha.plotting import FULL_WIDTH, plt, use_style
from contactalpha.scene.threshold import boundary_load_fit
from contactalpha.studies.adequacy.maps import NONE_ADEQUATE
from contactalpha.studies.adequacy.report import SMALL_XI

# Points of the fit's line in the v_crit figure.
FIT_POINTS = 200
# Panels per row of the per-model adequacy figure.
MAP_COLUMNS = 4
# The maps' xi axis: a scale that is logarithmic below about XI_SCALE_KNEE and linear above, so
# the log-spaced small-xi columns and the linear ones both get room; cells sit at their xi values.
XI_SCALE_KNEE = 1e-4
# Points of the table that inverts the xi scale (it has no closed-form inverse).
XI_SCALE_POINTS = 4001
XI_TICKS = (0.0, 1e-3, 0.1, 0.5, 0.9)
EPS_TICKS = (0.1, 0.3, 0.5, 0.7, 0.9)


def _xi_forward(xi):
    """The xi axis coordinate: asinh(xi / knee) / asinh(1 / knee) + xi, 0 at xi = 0, 2 at xi = 1."""
    xi = np.asarray(xi, dtype=float)
    return np.arcsinh(xi / XI_SCALE_KNEE) / np.arcsinh(1.0 / XI_SCALE_KNEE) + xi


_XI_TABLE = np.concatenate([[0.0], np.geomspace(1e-9, 1.0, XI_SCALE_POINTS)])
# Newton steps that refine the table's inverse to rounding.
XI_INVERSE_NEWTON = 3


def _xi_inverse(u):
    """Inverse of ``_xi_forward``: a table lookup refined by Newton (the scale is strictly increasing)."""
    u = np.asarray(u, dtype=float)
    xi = np.interp(u, _xi_forward(_XI_TABLE), _XI_TABLE)
    for _ in range(XI_INVERSE_NEWTON):
        slope = (
            1.0 / (XI_SCALE_KNEE * np.hypot(1.0, xi / XI_SCALE_KNEE) * np.arcsinh(1.0 / XI_SCALE_KNEE)) + 1.0
        )
        xi = xi - (_xi_forward(xi) - u) / slope
    return xi


def _grid_image(ax, values, ds, **kwargs):
    """``values`` (eps x xi) as cells over the grid's xi and eps values; xi = 0.1 dotted."""
    xi, eps = ds["xi"].values, ds["epsilon"].values
    image = ax.pcolormesh(xi, eps, values, shading="nearest", rasterized=True, **kwargs)
    ax.set_xscale("function", functions=(_xi_forward, _xi_inverse))
    ax.set_xlim(xi.min(), xi.max())
    ticks = [t for t in XI_TICKS if xi.min() <= t <= xi.max()]
    ax.set_xticks(ticks, [f"{t:g}" for t in ticks], fontsize=6)
    ax.xaxis.set_minor_locator(plt.NullLocator())
    ax.set_yticks([t for t in EPS_TICKS if eps.min() <= t <= eps.max()])
    ax.axvline(SMALL_XI, color="k", lw=0.6, ls=":")
    return image


def adequacy_figure(ds, tol):
    """One panel per model: grid points where it is adequate at ``tol`` (filled), over (xi, eps)."""
    use_style()
    names = list(ds["model"].values)
    rows = -(-len(names) // MAP_COLUMNS)
    fig, axes = plt.subplots(
        rows,
        MAP_COLUMNS,
        figsize=(FULL_WIDTH, 0.3 * FULL_WIDTH * rows),
        sharex=True,
        sharey=True,
        layout="constrained",
        squeeze=False,
    )
    cmap = ListedColormap(["0.92", "C2"])
    for ax, name in zip(axes.flat, names, strict=False):
        ok = ds["adequate"].sel(tol=tol, model=name).values
        _grid_image(ax, ok, ds, cmap=cmap, vmin=0, vmax=1)
        share = float(ds["area_share"].sel(tol=tol, model=name))
        ax.set_title(f"{name} ({share:.1%})", fontsize=8)
    for ax in axes.flat[len(names) :]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("ξ")
    for ax in axes[:, 0]:
        ax.set_ylabel("ε")
    fig.suptitle(f"Adequate (green): |ε delivered − ε| ≤ {tol:g} and the exact end state; dotted: ξ = 0.1")
    return fig


def cheapest_figure(ds):
    """The recommended model at each grid point, one panel per tol (grey: none adequate)."""
    use_style()
    tols = ds["tol"].values
    names = list(ds["model"].values)
    fig, axes = plt.subplots(
        1, len(tols), figsize=(FULL_WIDTH, 0.45 * FULL_WIDTH), sharey=True, layout="constrained"
    )
    axes = np.atleast_1d(axes)
    colours: list = ["0.6", *[plt.cm.tab20(i % 20) for i in range(len(names))]]
    cmap = ListedColormap(colours)
    norm = BoundaryNorm(np.arange(NONE_ADEQUATE - 0.5, len(names)), cmap.N)
    for ax, t in zip(axes, tols, strict=True):
        mesh = _grid_image(ax, ds["cheapest"].sel(tol=t).values, ds, cmap=cmap, norm=norm)
        ax.set_title(f"tol = {t:g}")
        ax.set_xlabel("ξ")
    axes[0].set_ylabel("ε")
    bar = fig.colorbar(mesh, ax=axes, ticks=np.arange(NONE_ADEQUATE, len(names)))
    bar.ax.set_yticklabels(["none", *names], fontsize=7)
    fig.suptitle("Cheapest adequate model (most accurate among costs within 1.5x of the cheapest)")
    return fig


def xi_ignore_figure(ds):
    """xi_ignore(eps; tol): below it the load may be ignored, one line per tol, and xi = 0.1."""
    use_style()
    fig, ax = plt.subplots(figsize=(0.6 * FULL_WIDTH, 0.4 * FULL_WIDTH), layout="constrained")
    eps = ds["epsilon"].values
    for t in ds["tol"].values:
        ax.plot(eps, ds["xi_ignore"].sel(tol=t).values, marker=".", label=f"tol = {t:g}")
    ax.axhline(SMALL_XI, color="k", lw=0.8, ls=":", label="ξ = 0.1 (paper's 'small')")
    ax.set_yscale("log")
    ax.set_xlabel("ε")
    ax.set_ylabel("ξ_ignore")
    ax.legend()
    return fig


def critical_speed_figure(th):
    """Left: the scaled boundary as v_crit / (a L1)^(5/6) = A_b^(-5/6), exact and fit; right: the scenes."""
    use_style()
    fig, (left, right) = plt.subplots(1, 2, figsize=(FULL_WIDTH, 0.4 * FULL_WIDTH), layout="constrained")
    e = th["eps_curve"].values
    left.plot(e, th["load_boundary"].values ** (-5.0 / 6.0), "o", ms=3, label="exact boundary")
    fine = np.linspace(e.min(), e.max(), FIT_POINTS)
    left.plot(fine, boundary_load_fit(fine) ** (-5.0 / 6.0), "-", lw=1, label="6-constant fit")
    left.set_yscale("log")
    left.set_xlabel("ε")
    left.set_ylabel("v_crit / (a L₁)^(5/6)")
    left.legend()
    names = list(th["scene"].values)
    v = th["v_crit"].values
    right.barh(names, v, color="C0", label="v_crit (exact α)")
    right.axvline(2.0, color="C3", lw=1.2, label="PhysX default 2 m/s")
    right.set_xscale("log")
    right.set_xlabel("approach speed (m/s)")
    right.legend(fontsize=7)
    return fig
