"""Fig. 8: maps over (eps, xi) of the error of Eq. 40, published and refit, in alpha and as restitution.

Settings (snakemake.params): restitution (add the row of restitution errors).
Inputs: surface (results/surface.h5), coefficients (results/fit/coefficients.json).
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

import json
from pathlib import Path

from contactalpha.io import load_surface, script_logger
from contactalpha.models import shen
from contactalpha.paper.fit.figures import fig8_errors
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_fig8", sm.log[0])
report = json.loads(Path(sm.input.coefficients).read_text(encoding="utf-8"))
reading = report["reading"]["used"]
refit = {k: v["refit"] for k, v in report["eq40"]["constants"].items()}
zero = report["zero_load"]["constants"]["zero_load_exp"]["refit"]
models = {"published": ({}, reading, shen.ZERO_LOAD_EXP), "refit": (refit, reading, zero)}
fig = fig8_errors(load_surface(sm.input.surface), models, restitution=sm.params.restitution)
save_figure(fig, [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
