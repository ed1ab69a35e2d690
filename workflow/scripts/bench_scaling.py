"""Scaling: grid time against size and threads, impact cost against alpha, the ridge's share.

Settings (snakemake.params.scaling): sizes, thread_points, stiff_xi, alphas, scipy_methods,
scipy_rtol, scipy_alphas, alpha_fit_min. Built into paper.bench.report.BenchSettings.
Inputs: none.
Outputs: scaling.json (with the machine), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import script_logger
from contactalpha.paper.bench.report import BenchSettings, run_scaling

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_scaling", sm.log[0])
run_scaling(settings_from(BenchSettings, sm.params), sm.output[0], log=log.info)
