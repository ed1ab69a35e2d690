"""Put results/bench/summary.md between the bench markers of README.md.

Settings (snakemake.params): readme (path of README.md).
Inputs: summary.md.
Outputs: a flag file (touched by Snakemake); README.md is edited in place, atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import fill_readme

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_readme", sm.log[0])
fill_readme(sm.params.readme, Path(sm.input[0]).read_text(encoding="utf-8"))
log.info(f"filled the bench block of {sm.params.readme}")
