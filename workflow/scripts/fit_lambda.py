"""lambda = x_end / x_max of the surface against Eq. 40's lambda formula (published and refit).

Settings: none.
Inputs: surface (results/surface.h5), coefficients (results/fit/coefficients.json).
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

import json
from pathlib import Path

from contactalpha.io import load_surface, script_logger
from contactalpha.paper.fit.figures import lambda_figure
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_lambda", sm.log[0])
report = json.loads(Path(sm.input.coefficients).read_text(encoding="utf-8"))
refit = {k: v["refit"] for k, v in report["eq40"]["constants"].items()}
save_figure(lambda_figure(load_surface(sm.input.surface), refit), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
