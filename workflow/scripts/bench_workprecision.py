"""Work-precision study: references of the five regimes, then error against cost of every method.

Settings (snakemake.params): rtols, rk4_steps, scipy_methods, scipy_max_nfev.
Built into paper.bench.report.BenchSettings.
Inputs: none.
Outputs: reference (reference.csv), table (workprecision.csv), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import script_logger
from contactalpha.paper.bench.report import BenchSettings, run_workprecision

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_workprecision", sm.log[0])
run_workprecision(settings_from(BenchSettings, sm.params), sm.output.reference, sm.output.table, log=log.info)
