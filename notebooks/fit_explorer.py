# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Shen et al.'s closed form against the computed surface
#
# This notebook loads the α(ε, ξ) surface, compares Eq. 40 as published with its refit, and
# lets you change the constants and watch the error maps move. All numerics come from
# `contactalpha` (`shen`, `fit`, `fit_report`, `fit_figures`); nothing is computed here.
#
# The surface is `results/surface.h5` (run `snakemake -c2` first), or the file named by the
# environment variable `CONTACTALPHA_SURFACE`.

# %%
import os

from contactalpha.paper.fit import compute as fit

from contactalpha.paper.fit import figures as fit_figures

from contactalpha.paper.fit import report as fit_report

from contactalpha.models import shen
from contactalpha.io import load_surface

surface_path = os.environ.get("CONTACTALPHA_SURFACE", "../results/surface.h5")
ds = load_surface(surface_path)
print(f"{surface_path}: {ds.sizes['epsilon']} eps x {ds.sizes['xi']} xi values")

# %% [markdown]
# ## 1. Points used by the fits
# Failed or missing points are excluded, named and counted.

# %%
loaded, unloaded, excluded = fit.surface_points(ds)
print(f"{len(loaded)} points with xi > 0, {len(unloaded)} at xi = 0")
print(excluded.describe())

# %% [markdown]
# ## 2. Refit every constant of Eq. 40 and compare with the published values
# (`readings` can list other readings of the damaged first term: see `shen.READINGS`.)

# %%
report, fits = fit_report.refit_report(ds, readings=[shen.BEST_READING], eq26=None)
print(fit_report.comparison_markdown(report))

# %% [markdown]
# ## 3. Change the constants and see the error maps move
# Edit `my_constants` (any key of `shen.PUBLISHED`) and rerun the cell. The left column is the
# published model, the right one yours; the lower row is the restitution error, the ε your α
# actually produces through the impact engine minus the target ε.

# %%
my_constants = dict(fits["eq40"].values())
my_constants["beta"] = 0.05  # try: 1.0 (as printed), 0.02, ...
models = {
    "published": ({}, shen.BEST_READING, shen.ZERO_LOAD_EXP),
    "yours": (my_constants, shen.BEST_READING, fits["zero_load"].x[0]),
}
fig = fit_figures.fig8_errors(ds, models)

# %%
for name, (constants, reading, p0) in models.items():
    stats = fit.error_stats(fit.eq40_model(loaded, constants, reading), loaded)
    print(f"{name:10s} RMS rel. err. alpha {stats['alpha_rel_rms_area']:.3g}, "
          f"max abs. err. eps {stats['eps_abs_max']:.3g}")

# %% [markdown]
# ## 4. The building blocks: s1 against s21 (Fig. 6), s_a (Fig. 7), λ and the η ratios

# %%
fig6 = fit_figures.fig6_s1(refit=report["s21"]["constants"]["s21_coef"]["refit"])
fig7 = fit_figures.fig7_sa(ds)
fig_lam = fit_figures.lambda_figure(ds, my_constants)
fig_eta = fit_figures.eta_figure(ds)
