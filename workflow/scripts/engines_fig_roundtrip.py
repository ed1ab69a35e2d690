"""Figure: target against delivered Stronge eps in OpenSim and Exudyn, ours beside the built-in mappings.

Settings: none.
Inputs: roundtrip_*.nc.
Outputs: png, pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import load_dataset, script_logger
from contactalpha.plotting import save_figure
from contactalpha.studies.engines.figures import roundtrip_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_fig_roundtrip", sm.log[0])
fig = roundtrip_figure([load_dataset(path) for path in sm.input])
save_figure(fig, [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png}")
