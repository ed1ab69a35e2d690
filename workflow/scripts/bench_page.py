"""Put results/bench/summary.md between the bench markers of docs/performance.md.

Settings (snakemake.params): page (path of docs/performance.md).
Inputs: summary.md.
Outputs: a flag file (touched by Snakemake); the page is edited in place, atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import fill_page

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_page", sm.log[0])
fill_page(sm.params.page, Path(sm.input[0]).read_text(encoding="utf-8"))
log.info(f"filled the bench block of {sm.params.page}")
