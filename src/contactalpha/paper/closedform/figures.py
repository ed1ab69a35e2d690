"""Fig. 8-style map of the delivered-restitution error of closed forms (``compute.compare_models``)."""

import numpy as np
from matplotlib.colors import SymLogNorm

from contactalpha.paper.fit.figures import XI_LINTHRESH
from contactalpha.plotting import new_figure

# Colour scale of eps_delivered - eps: linear within the RMS target of issue 13, log beyond.
ERROR_LINTHRESH = 1e-3
ERROR_LIMIT = 0.5


def error_map(ds, maps, titles=None):
    """Maps over (xi, eps) of delivered eps minus eps, one panel per model.

    Parameters
    ----------
    ds : xarray.Dataset
        The surface whose grid the maps are on.
    maps : dict
        Model name -> error grid, shape (n_eps, n_xi) (``compare_models``).
    titles : dict, optional
        Model name -> panel title (default the name).
    """
    titles = titles or {}
    fig, axes = new_figure(len(maps), 1, aspect=0.42, squeeze=False)
    eps, xi = ds["epsilon"].values, ds["xi"].values
    norm = SymLogNorm(ERROR_LINTHRESH, vmin=-ERROR_LIMIT, vmax=ERROR_LIMIT)
    for ax, (name, err) in zip(axes[0], maps.items(), strict=True):
        im = ax.pcolormesh(xi, eps, err, norm=norm, cmap="RdBu_r", shading="nearest", rasterized=True)
        worst = np.nanmax(np.abs(err)) if np.isfinite(err).any() else np.nan
        ax.set(title=f"{titles.get(name, name)}\nmax |Δε| = {worst:.3g}", xlabel="ξ", ylabel="ε")
        ax.set_xscale("symlog", linthresh=XI_LINTHRESH)
    fig.colorbar(im, ax=axes[0].tolist(), label="ε delivered − ε")
    return fig
