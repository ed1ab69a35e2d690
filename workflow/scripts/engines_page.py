"""Put results/engines/summary.md between the engines markers of docs/engines/index.md.

Settings (snakemake.params): page (path of docs/engines/index.md).
Inputs: summary.md.
Outputs: a flag file (touched by Snakemake); the page is edited in place, atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import fill_page
from contactalpha.studies.engines.report import PAGE_END, PAGE_START

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_page", sm.log[0])
fill_page(sm.params.page, Path(sm.input[0]).read_text(encoding="utf-8"), PAGE_START, PAGE_END)
log.info(f"filled the engines block of {sm.params.page}")
