"""Check that the shipped refit constants (model shen_refit) are the refit of this surface.

Settings (snakemake.params): tol_se (contactalpha.paper.fit.shipped.SHIPPED_TOL_SE);
shipped_refit (the shipped file's digest) only makes shipping rerun the check.
Inputs: report (results/fit/coefficients.json, the fresh refit with its standard errors); the
shipped constants are read from the package (contactalpha/data/shen_refit.json).
Outputs: the comparison as markdown. The rule fails when the shipped constants are a refit
of the same surface and reading but differ by more than tol_se standard errors (stale:
`snakemake -c2 ship` ships the fresh refit).
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import json
from pathlib import Path

from contactalpha.io import script_logger, write_text_atomic
from contactalpha.models.shen import load_refit
from contactalpha.paper.fit.shipped import agreement_markdown, shipped_agreement

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_shipped_check", sm.log[0])
report = json.loads(Path(sm.input.report).read_text(encoding="utf-8"))
shipped = load_refit()
result = shipped_agreement(report, shipped, tol_se=sm.params.tol_se)
text = agreement_markdown(result)
log.info(text)
if result["stale"]:
    raise SystemExit(text.splitlines()[2])
write_text_atomic(sm.output[0], text)
