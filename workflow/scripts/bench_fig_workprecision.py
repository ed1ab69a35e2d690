"""Figure: error against cost, one curve per method, one column per regime.

Settings: none.
Inputs: reference (reference.csv), table (workprecision.csv).
Outputs: png, pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import pandas as pd

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import plot_work_precision

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_fig_workprecision", sm.log[0])
plot_work_precision(
    pd.read_csv(sm.input.table), pd.read_csv(sm.input.reference), [sm.output.png, sm.output.pdf]
)
log.info(f"wrote {sm.output.png}")
