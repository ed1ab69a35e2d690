"""Failure maps: every method over an (eps, xi) grid, each point classified.

Settings (snakemake.params): failure (rtol, rk4_step, eps, xi, eps_coarse, xi_coarse),
scipy_methods, scipy_max_nfev. Built into paper.bench.report.BenchSettings.
Inputs: none.
Outputs: table (failure_map.csv, one row per method and point), counts (failure_counts.csv).
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import script_logger
from contactalpha.paper.bench.report import BenchSettings, run_failures

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_failures", sm.log[0])
run_failures(settings_from(BenchSettings, sm.params), sm.output.table, sm.output.counts, log=log.info)
