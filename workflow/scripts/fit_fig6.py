"""Fig. 6: s1 (Eq. 31, quadrature) against s21 (Eq. 34, published and refit factor).

Settings: none.
Inputs: results/fit/coefficients.json (the refit factor of Eq. 34).
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

import json
from pathlib import Path

from contactalpha.io import script_logger
from contactalpha.paper.fit.figures import fig6_s1
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_fig6", sm.log[0])
report = json.loads(Path(sm.input[0]).read_text(encoding="utf-8"))
save_figure(fig6_s1(refit=report["s21"]["constants"]["s21_coef"]["refit"]), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
