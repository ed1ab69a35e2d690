"""Figures of the bouncing ball (paper Figs. 11-21), drawn from the study Datasets.

- ``plot_motion`` (Fig. 11): height and velocity of the centre, cases A and B.
- ``plot_energy`` (Fig. 12): total energy, and the accumulated per-collision
  loss error between the cases.
- ``plot_first_collision`` (Figs. 13-21): one panel per eps, one line per
  model, of deformation, deformation rate or contact force (hysteresis loop)
  during the first contact at one force F.
"""

import numpy as np

from contactalpha.plotting import new_figure
from contactalpha.scene.ball import RESTS

from .report import loss_error
from .study import model_label

# Line style per case of Figs. 11-12.
CASE_STYLE = {"A": {"color": "C0", "lw": 1.2}, "B": {"color": "C3", "lw": 1.0, "ls": "--"}}
# Kinds of first-collision figure: variable on x, on y, axis labels and units scales.
FIRST_KINDS = {
    "deformation": ("time", "delta", "time (ms)", "deformation δ (µm)", 1e3, 1e6),
    "velocity": ("time", "ddelta", "time (ms)", "deformation rate dδ/dt (m/s)", 1e3, 1.0),
    "hysteresis": ("delta", "contact_force", "deformation δ (µm)", "contact force (N)", 1e6, 1.0),
}
# Panel letters of the four eps panels, as in the paper.
LETTERS = "abcdefghijklmnopqrstuvwxyz"
# Line styles that keep the reference model distinguishable from the rest.
REFERENCE_STYLE = {"color": "k", "lw": 0.9, "ls": ":"}


def _case_label(ds):
    return f"case {ds.attrs['case']} ({model_label(ds.attrs['model'])})"


def plot_motion(case_a, case_b):
    """Fig. 11: (a) height y of the centre, (b) its velocity, against time, for both cases."""
    fig, (ax_y, ax_v) = new_figure(2, 1, aspect=0.45)
    for ds in (case_a, case_b):
        style = CASE_STYLE[ds.attrs["case"]]
        ax_y.plot(ds["t"], ds["y"] * 1e3, label=_case_label(ds), **style)
        ax_v.plot(ds["t"], ds["ydot"], **style)
    radius = float(np.asarray(case_a["y"])[0] + np.asarray(case_a["delta"])[0])
    ax_y.axhline(radius * 1e3, color="0.5", lw=0.6, label="contact begins or ends (y = R)")
    if case_a.attrs["end_state"] == RESTS:
        rest = radius - case_a.attrs["rest_deformation"]
        ax_y.axhline(rest * 1e3, color="C0", lw=0.6, ls=":", label="case A rests at y = R − δ_eq")
    ax_y.set_ylabel("height of the centre y (mm)")
    ax_v.set_ylabel("velocity dy/dt (m/s)")
    ax_y.set_xlabel("time (s)")
    ax_v.set_xlabel("time (s)")
    ax_y.set_title("(a) position", loc="left")
    ax_v.set_title("(b) velocity", loc="left")
    ax_y.legend(loc="upper right")
    return fig


def plot_energy(case_a, case_b):
    """Fig. 12: (a) total energy against time, (b) accumulated loss error against collision number."""
    fig, (ax_e, ax_d) = new_figure(2, 1, aspect=0.45)
    for ds in (case_a, case_b):
        ax_e.plot(ds["t"], ds["energy_total"] * 1e3, label=_case_label(ds), **CASE_STYLE[ds.attrs["case"]])
    ax_e.set_xlabel("time (s)")
    ax_e.set_ylabel("total energy (mJ)")
    ax_e.set_title("(a) kinetic + elastic + gravity + potential of F", loc="left")
    ax_e.legend(loc="upper right")
    d = loss_error(case_a, case_b)
    i = np.arange(1, d.size + 1)
    ax_d.plot(i, np.cumsum(d) * 1e3, "o-", color="C2", ms=3)
    ax_d.axhline(0.0, color="0.5", lw=0.6)
    ax_d.set_xlabel("collision i")
    ax_d.set_ylabel("Σ (ΔE_A,i − ΔE_B,i) (mJ)")
    ax_d.set_title("(b) accumulated error of the energy loss per collision", loc="left")
    return fig


def plot_first_collision(ds, force_index, kind, reference=None):
    """Figs. 13-21: the first contact at force ``ds.force[force_index]``, one panel per eps.

    Parameters
    ----------
    ds : xarray.Dataset
        From ``ball_study.first_collision``.
    force_index : int
    kind : "deformation", "velocity" or "hysteresis"
    reference : str, optional
        Model drawn as the dotted black reference line.
    """
    if kind not in FIRST_KINDS:
        raise ValueError(f"kind = {kind!r} is outside the valid choices {tuple(FIRST_KINDS)}")
    xname, yname, xlabel, ylabel, xs, ys = FIRST_KINDS[kind]
    n_eps = ds.sizes["epsilon"]
    ncols = min(n_eps, 2)
    nrows = int(np.ceil(n_eps / ncols))
    fig, axes = new_figure(ncols, nrows, aspect=0.36 * nrows, squeeze=False)
    sub = ds.isel(force=force_index)
    for j, ax in enumerate(axes.ravel()):
        if j >= n_eps:
            ax.set_visible(False)
            continue
        for k, name in enumerate(sub["model"].values):
            x = sub[xname].values[j, k] * xs
            y = sub[yname].values[j, k] * ys
            style = REFERENCE_STYLE if name == reference else {"lw": 1.0, "color": f"C{k}"}
            ax.plot(x, y, label=model_label(name), **style)
        ax.set_title(f"({LETTERS[j]}) ε = {sub['epsilon'].values[j]:g}", loc="left")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if kind == "velocity":
            ax.axhline(0.0, color="0.5", lw=0.5)
    axes.ravel()[0].legend(loc="best")
    fig.suptitle(f"first collision, F = {float(sub['force']):g} N, ξ = {float(sub['xi']):.4f}")
    return fig
