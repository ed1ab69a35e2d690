"""Figures of the closed-form study: Figs. 6-8 of the paper, lambda and the dissipation ratios.

Each function takes data (a surface Dataset, constants) and returns a matplotlib
figure; the numbers come from ``shen`` and ``fit``.  Workflow scripts save them
with ``plotting.save_figure``; the notebooks call them directly.
"""

import numpy as np
from matplotlib.colors import LogNorm, SymLogNorm

from contactalpha.models import shen
from contactalpha.paper.fit import compute as fit
from contactalpha.plotting import COLUMN_WIDTH, new_figure

# Below this xi the symlog xi axes are linear; the ridge (1e-4 < xi < 1e-2) stays on the log part.
XI_LINTHRESH = 1e-5
# Sections drawn in the line figures (the nearest grid value is used).
EPS_LINES = (0.05, 0.1, 0.3, 0.5, 0.7, 0.9)
XI_LINES = (0.01, 0.1, 0.2, 0.5, 0.8)
# Number of xi values of the s1 and s21 curves (Fig. 6).
S1_POINTS = 199


def _nearest(values, targets):
    values = np.asarray(values)
    return sorted({float(values[np.argmin(np.abs(values - t))]) for t in targets})


def fig6_s1(xi=None, coef=shen.S21_COEF, refit=None):
    """Fig. 6: s1 by quadrature (Eq. 31) against s21 (Eq. 34), and their relative difference."""
    xi = np.linspace(0.0, 0.99, S1_POINTS) if xi is None else np.asarray(xi, dtype=float)
    s1 = shen.s1(xi)
    fig, (ax, bx) = new_figure(2, aspect=0.36)
    ax.plot(xi, s1, "k-", label="s1, Eq. 31 (quadrature)")
    ax.plot(xi, shen.s21(xi, coef), "C0--", label=f"s21, Eq. 34 ({coef:g})")
    bx.plot(xi, shen.s21(xi, coef) / s1 - 1, "C0--", label=f"{coef:g}")
    if refit is not None:
        ax.plot(xi, shen.s21(xi, refit), "C1:", label=f"s21, refit ({refit:.4g})")
        bx.plot(xi, shen.s21(xi, refit) / s1 - 1, "C1:", label=f"refit {refit:.4g}")
    bx.axhline(0, color="0.6", lw=0.6)
    ax.set(xlabel="ξ", ylabel="s", title="s1 and s21")
    bx.set(xlabel="ξ", ylabel="s21 / s1 − 1", title="relative difference")
    ax.legend()
    bx.legend()
    return fig


def fig7_sa(ds, eps_lines=EPS_LINES):
    """Fig. 7: s_a from the computed impacts (Eqs. 28, 30) against s1 (Eq. 31), over xi."""
    d = _dissipation(ds)
    xi = ds["xi"].values
    fig, ax = new_figure(1, width=COLUMN_WIDTH * 1.4, aspect=0.75)
    for i, e in enumerate(_nearest(ds["epsilon"].values, eps_lines)):
        j = int(np.argmin(np.abs(ds["epsilon"].values - e)))
        ax.plot(xi, d.s_a[j], color=f"C{i}", label=f"s_a, ε = {e:g}")
    xs = np.linspace(0.0, min(0.99, xi.max()), S1_POINTS)
    ax.plot(xs, shen.s1(xs), "k--", lw=1.5, label="s1 (undamped, Eq. 31)")
    ax.set(xlabel="ξ", ylabel="compression damping integral", title="s_a against s1")
    ax.set_xscale("symlog", linthresh=XI_LINTHRESH)
    ax.legend(ncols=2)
    return fig


def _dissipation(ds):
    E, X = np.meshgrid(ds["epsilon"].values, ds["xi"].values, indexing="ij")
    ok = ds["status"].values == 0
    alpha = np.where(ok, ds["alpha"].values, np.nan)
    return shen.dissipation(E, X, alpha, ds["x_max"].values, ds["x_end"].values)


def eta_figure(ds, xi_lines=XI_LINES):
    """eta_c and eta_r of Eqs. 36-37 from the computed impacts, and Eq. 40's eta (= eta_r / eta_c)."""
    d = _dissipation(ds)
    eps = ds["epsilon"].values
    fig, axes = new_figure(3, aspect=0.33)
    for i, x in enumerate(_nearest(ds["xi"].values[ds["xi"].values > 0], xi_lines)):
        j = int(np.argmin(np.abs(ds["xi"].values - x)))
        c = f"C{i}"
        axes[0].plot(eps, d.eta_c[:, j], color=c, label=f"ξ = {x:g}")
        axes[1].plot(eps, d.eta_r[:, j], color=c)
        axes[2].plot(eps, d.eta_r[:, j] / d.eta_c[:, j], color=c)
        axes[2].plot(eps, shen.eta_eq40(eps, x), color=c, ls="--")
    axes[0].set(xlabel="ε", ylabel="η_c", title="η_c (Eq. 36), computed")
    axes[1].set(xlabel="ε", ylabel="η_r", title="η_r (Eq. 37), computed")
    axes[2].set(xlabel="ε", ylabel="η", title="η_r/η_c (solid), Eq. 40's η (dashed)")
    axes[1].set_yscale("log")
    axes[2].set_yscale("log")
    axes[0].legend()
    return fig


def lambda_figure(ds, refit=None, xi_lines=XI_LINES, reading=shen.BEST_READING):
    """λ = x_end / x_max of the surface (solid) against Eq. 40's formula (dashed; refit dotted)."""
    eps = ds["epsilon"].values
    fig, ax = new_figure(1, width=COLUMN_WIDTH * 1.4, aspect=0.75)
    for i, x in enumerate(_nearest(ds["xi"].values[ds["xi"].values > 0], xi_lines)):
        j = int(np.argmin(np.abs(ds["xi"].values - x)))
        c = f"C{i}"
        ax.plot(eps, ds["lambda"].values[:, j], color=c, label=f"ξ = {x:g}")
        ax.plot(eps, shen.lambda_eq40(eps, x), color=c, ls="--")
        if refit is not None:
            ax.plot(eps, shen.lambda_eq40(eps, x, {**shen.PUBLISHED, **refit}), color=c, ls=":")
    ax.set(xlabel="ε", ylabel="λ", title="λ: surface (—), Eq. 40 (--), refit (··)")
    ax.legend()
    return fig


def error_maps(ds, constants, reading=shen.BEST_READING, zero_load_exp=shen.ZERO_LOAD_EXP, restitution=True):
    """Relative alpha error and restitution error of Eq. 40 with ``constants`` over the surface grid.

    Returns
    -------
    rel, deps : ndarray, shape (n_eps, n_xi)
        ``alpha_model / alpha - 1`` and ``eps_produced - eps`` (NaN where the
        surface failed or the model could not be integrated; ``deps`` is None
        unless ``restitution``).
    """
    E, X = np.meshgrid(ds["epsilon"].values, ds["xi"].values, indexing="ij")
    ok = (ds["status"].values == 0) & (ds["alpha"].values > 0)
    c = {**shen.PUBLISHED, **constants}
    with np.errstate(all="ignore"):
        model = shen.eq40(E, X, c, reading, zero_load_exp)
        rel = np.where(ok, model / ds["alpha"].values - 1.0, np.nan)
    if not restitution:
        return rel, None
    produced, _ = fit.produced_restitution(np.where(ok, model, np.nan), X)
    return rel, produced - E


def fig8_errors(ds, models, restitution=True):
    """Fig. 8: maps over (eps, xi) of the error of each model in ``models``.

    Parameters
    ----------
    ds : xarray.Dataset
        The surface.
    models : dict
        title -> ``(constants, reading, zero_load_exp)``.
    restitution : bool
        Add a row with the restitution error (the eps the model's alpha produces).
    """
    maps = {t: error_maps(ds, *m, restitution=restitution) for t, m in models.items()}  # type: ignore[misc]
    rows = 2 if restitution else 1
    fig, axes = new_figure(len(models), rows, aspect=0.36 * rows, squeeze=False)
    eps, xi = ds["epsilon"].values, ds["xi"].values
    rnorm = LogNorm(1e-3, 1e1)
    enorm = SymLogNorm(1e-3, vmin=-0.5, vmax=0.5)
    for k, (title, (rel, deps)) in enumerate(maps.items()):
        ax = axes[0, k]
        im = ax.pcolormesh(
            xi, eps, np.abs(rel), norm=rnorm, cmap="magma_r", shading="nearest", rasterized=True
        )
        ax.set(title=f"{title}: |α_model/α − 1|", xlabel="ξ", ylabel="ε")
        ax.set_xscale("symlog", linthresh=XI_LINTHRESH)
        fig.colorbar(im, ax=ax)
        if restitution:
            bx = axes[1, k]
            im = bx.pcolormesh(xi, eps, deps, norm=enorm, cmap="RdBu_r", shading="nearest", rasterized=True)
            bx.set(title=f"{title}: ε produced − ε", xlabel="ξ", ylabel="ε")
            bx.set_xscale("symlog", linthresh=XI_LINTHRESH)
            fig.colorbar(im, ax=bx)
    return fig
