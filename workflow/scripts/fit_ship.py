"""Ship the refit constants with the package: copy them to contactalpha/data/ (model shen_refit).

Settings: none (the target path is the workflow's fit.package_coefficients).
Inputs: results/fit/shen_refit.json.
Outputs: the shipped copy, written atomically.
"""

from pathlib import Path

from contactalpha.io import script_logger, write_text_atomic

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_ship", sm.log[0])
write_text_atomic(sm.output[0], Path(sm.input[0]).read_text(encoding="utf-8"))
log.info(f"copied {sm.input[0]} to {sm.output[0]}")
