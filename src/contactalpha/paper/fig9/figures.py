"""Fig. 9: post- versus pre-restitution coefficient, one panel per load."""

import numpy as np

from contactalpha.models import MODELS
from contactalpha.plotting import new_figure

from .compute import nonseparation_mask

# Line style per model: the exact reference is drawn thin and dark.
_STYLE = {"exact": dict(color="k", lw=0.8, ls="--")}


def fig9(ds):
    """Post versus pre restitution, panels over ``ds.xi``; crosses mark non-separating impacts."""
    n = ds.sizes["xi"]
    ncols = 3
    nrows = int(np.ceil(n / ncols))
    fig, axes = new_figure(ncols, nrows, aspect=0.33 * nrows, sharex=True, sharey=True)
    axes = np.atleast_1d(axes).ravel()
    pre = ds.eps_pre.values
    ns = nonseparation_mask(ds)
    for k, (ax, xi) in enumerate(zip(axes, ds.xi.values, strict=False)):
        ax.plot([0, 1], [0, 1], color="0.75", lw=0.8, zorder=0)
        for m in ds.model.values:
            name = str(m)
            post = ds.eps_post.sel(model=m, xi=xi).values
            style = dict(lw=1.2) | _STYLE.get(name, {})
            line = ax.plot(pre, post, label=MODELS[name].label if name in MODELS else name, **style)
            mask = ns.sel(model=m, xi=xi).values
            if mask.any():
                ax.plot(pre[mask], post[mask], "x", ms=3, color=line[0].get_color())
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
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle("Fig. 9: restitution each model delivers (× = impact ends without separation)")
    return fig
