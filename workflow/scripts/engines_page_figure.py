"""Figure of one engine page: delivered restitution against the target, usual mapping and ours.

Settings: none (studies.engines.page_figures: FORCES, LOADS).
Inputs: roundtrip_{engine}.nc (OpenSim, Exudyn) or stepping_{engine}.nc (MuJoCo, Drake, PyBullet).
Outputs: png, pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import load_dataset, script_logger
from contactalpha.plotting import save_figure
from contactalpha.studies.engines.page_figures import page_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_page_figure", sm.log[0])
save_figure(page_figure(load_dataset(sm.input[0])), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png}")
