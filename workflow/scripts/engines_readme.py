"""Put results/engines/summary.md between the engines markers of README.md.

Settings (snakemake.params): readme (path of README.md).
Inputs: summary.md.
Outputs: a flag file (touched by Snakemake); README.md is edited in place, atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import fill_readme
from contactalpha.studies.engines.report import README_END, README_START

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_readme", sm.log[0])
fill_readme(sm.params.readme, Path(sm.input[0]).read_text(encoding="utf-8"), README_START, README_END)
log.info(f"filled the engines block of {sm.params.readme}")
