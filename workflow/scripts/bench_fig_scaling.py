"""Figure: grid time against size, 1 against 2 threads, impact cost against alpha.

Settings: none.
Inputs: scaling.json.
Outputs: png, pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import json
from pathlib import Path

from contactalpha.io import script_logger
from contactalpha.paper.bench.report import plot_scaling

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("bench_fig_scaling", sm.log[0])
plot_scaling(json.loads(Path(sm.input[0]).read_text()), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png}")
