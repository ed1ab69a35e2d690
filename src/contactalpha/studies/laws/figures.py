"""Figure: delivered e_N against the target, per law, for the engines' mapping and the exact inverse."""

from contactalpha.plotting import FULL_WIDTH, new_figure


def delivered_figure(ds):
    """One panel per law: the mapping's delivered e_N (solid) and the exact model's (dotted), per load."""
    n = ds["law"].size
    fig, axes = new_figure(ncols=n, width=FULL_WIDTH * 1.6, aspect=0.3, sharey=True)
    target = ds["target"].values
    for ax, law in zip(axes, ds["law"].values, strict=True):
        sub = ds.sel(law=law)
        ax.plot([0, 1], [0, 1], color="0.7", lw=0.8, ls="--")
        for j, xi in enumerate(sub["xi"].values):
            (line,) = ax.plot(target, sub["mapping_e_n"].values[j], lw=1.2, label=f"ξ = {xi:g}")
            ax.plot(target, sub["exact_e_n"].values[j], lw=0.8, ls=":", color=line.get_color())
        ax.set_title(f"{law}\n{sub['mapping'].values}", fontsize="small")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.set_xlabel("target e_N")
    axes[0].set_ylabel("delivered e_N")
    # The exact model's dotted lines lie on the diagonal at every load: say so once.
    axes[0].plot([], [], color="0.3", lw=1.2, label="solid: the mapping in the title")
    axes[0].plot([], [], color="0.3", lw=0.8, ls=":", label="dotted: exact model (every ξ)")
    axes[0].legend(loc="upper left", fontsize="x-small")
    return fig
