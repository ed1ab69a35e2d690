"""Work-precision study: references of the five regimes, then error against cost of every method.

Settings (snakemake.params): rtols, rk4_steps, scipy_methods, scipy_max_nfev.
Inputs: none.
Outputs: reference (reference.csv), table (workprecision.csv), written atomically.
"""

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import run_workprecision

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_workprecision", sm.log[0])
run_workprecision(dict(sm.params.items()), sm.output.reference, sm.output.table, log=log.info)
