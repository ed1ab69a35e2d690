"""results/bench/summary.md: machine, cost ratios at equal accuracy, references, failures, scaling.

Settings (snakemake.params): failure (grids, named in the text), scipy_max_nfev.
Built into paper.bench.report.BenchSettings.
Inputs: reference, table (workprecision.csv), counts (failure_counts.csv), failures (failure_map.csv),
scaling (scaling.json).
Outputs: the markdown file, written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import script_logger
from contactalpha.paper.bench.report import BenchSettings, run_summary

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_summary", sm.log[0])
run_summary(
    settings_from(BenchSettings, sm.params),
    sm.input.reference,
    sm.input.table,
    sm.input.counts,
    sm.input.scaling,
    sm.output[0],
    failure_csv=sm.input.failures,
)
log.info(f"wrote {sm.output[0]}")
