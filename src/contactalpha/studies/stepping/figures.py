"""Figures: e_N against the touchdown phase at three steps; the step one drop's tolerance needs."""

import numpy as np

from contactalpha.plotting import FULL_WIDTH, new_figure


def phase_figure(curves, zeta, load):
    """e_N over the touchdown phase, one line per step, with the phase mean dashed."""
    fig, ax = new_figure(width=FULL_WIDTH, aspect=0.45)
    for h, (phi, e, st) in curves.items():
        (line,) = ax.plot(phi, e, lw=1.0, label=f"ω h = {h:.3g} ({np.pi / h:.0f} steps per π/ω)")
        ax.axhline(st.mean, color=line.get_color(), lw=0.8, ls="--")
    ax.set_xlabel("touchdown phase φ (fraction of a step)")
    ax.set_ylabel("e_N of one drop")
    ax.set_title(f"MuJoCo's step, ζ = {zeta:g}, A = {load:g}: dashed, the mean over φ", fontsize="small")
    ax.legend(fontsize="x-small")
    return fig


def step_map_figure(table, zetas, loads, tol):
    """The largest step (omega h) keeping one drop within ``tol`` of the target, over (zeta, A)."""
    fig, ax = new_figure(width=FULL_WIDTH * 0.7, aspect=0.8)
    mesh = ax.pcolormesh(np.arange(len(zetas) + 1), np.arange(len(loads) + 1), table, shading="flat")
    for i in range(len(loads)):
        for j in range(len(zetas)):
            if np.isfinite(table[i, j]):
                ax.text(j + 0.5, i + 0.5, f"{np.pi / table[i, j]:.0f}", ha="center", va="center",
                        fontsize="x-small", color="w")  # fmt: skip
    ax.set_xticks(np.arange(len(zetas)) + 0.5, [f"{z:g}" for z in zetas])
    ax.set_yticks(np.arange(len(loads)) + 0.5, [f"{a:g}" for a in loads])
    ax.set_xlabel("damping ratio ζ of the law")
    ax.set_ylabel("load A = a / (ω v)")
    ax.set_title(f"largest ω h with every drop within ±{tol:g} (numbers: steps per π/ω)", fontsize="small")
    fig.colorbar(mesh, ax=ax, label="ω h")
    return fig
