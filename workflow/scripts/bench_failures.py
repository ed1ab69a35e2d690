"""Failure maps: every method over an (eps, xi) grid, each point classified.

Settings (snakemake.params): failure (rtol, rk4_step, eps, xi, eps_coarse, xi_coarse),
scipy_methods, scipy_max_nfev.
Inputs: none.
Outputs: table (failure_map.csv, one row per method and point), counts (failure_counts.csv).
"""

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import run_failures

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_failures", sm.log[0])
run_failures(dict(sm.params.items()), sm.output.table, sm.output.counts, log=log.info)
