"""Figure: the failure map, one panel per method, points coloured by failure category.

Settings: none.
Inputs: failure_map.csv.
Outputs: png, pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import pandas as pd

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import plot_failure_map

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_fig_failure_map", sm.log[0])
plot_failure_map(pd.read_csv(sm.input[0]), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png}")
