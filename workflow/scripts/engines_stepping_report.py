"""Figure and table of the stepping engines' round trips.

Settings: none.
Inputs: stepping_*.nc.
Outputs: png, pdf, table (docs/engines-table.md).
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import load_dataset, script_logger, write_text_atomic
from contactalpha.plotting import save_figure
from contactalpha.studies.engines.stepping_report import stepping_figure, stepping_table

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_stepping_report", sm.log[0])
datasets = [load_dataset(path) for path in sm.input]
save_figure(stepping_figure(datasets), [sm.output.png, sm.output.pdf])
head = "# Engines: the target e_N at the engine's own step\n\nWritten by `snakemake -c2 engines`.\n\n"
write_text_atomic(sm.output.table, head + stepping_table(datasets))
log.info(f"wrote {sm.output.png} and {sm.output.table}")
