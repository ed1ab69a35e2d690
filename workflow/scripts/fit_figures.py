"""Figs. 6-8, lambda and the dissipation ratios of the fit stage: the figures a rule names.

Each named output (fig6, fig7, fig8, lambda, eta) is a (png, pdf) pair; one job draws several
figures, so that they share one Python start-up and one set of imports.
Settings (snakemake.params): restitution (Fig. 8 measures the error as restitution), when the
rule draws fig8.
Inputs: surface (results/surface.h5); coefficients (results/fit/coefficients.json) for fig6,
fig8 and lambda (the refit constants).
Outputs: the figures, written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import json
from functools import cache
from pathlib import Path

from contactalpha.io import load_surface, script_logger
from contactalpha.models import shen
from contactalpha.paper.fit.figures import eta_figure, fig6_s1, fig7_sa, fig8_errors, lambda_figure
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_figures", sm.log[0])


@cache
def surface():
    return load_surface(sm.input.surface)


@cache
def report():
    return json.loads(Path(sm.input.coefficients).read_text(encoding="utf-8"))


def refit():
    return {k: v["refit"] for k, v in report()["eq40"]["constants"].items()}


def fig8():
    reading = report()["reading"]["used"]
    zero = report()["zero_load"]["constants"]["zero_load_exp"]["refit"]
    models = {"published": ({}, reading, shen.ZERO_LOAD_EXP), "refit": (refit(), reading, zero)}
    return fig8_errors(surface(), models, restitution=sm.params.restitution)


DRAW = {
    "fig6": lambda: fig6_s1(refit=report()["s21"]["constants"]["s21_coef"]["refit"]),
    "fig7": lambda: fig7_sa(surface()),
    "fig8": fig8,
    "lambda": lambda: lambda_figure(surface(), refit()),
    "eta": lambda: eta_figure(surface()),
}
for name in sm.output.keys():
    paths = list(sm.output[name])
    save_figure(DRAW[name](), paths)
    log.info(f"wrote {' and '.join(paths)}")
