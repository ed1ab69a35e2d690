"""Newton's e_N against Stronge's eps for several loads xi: data and figure in one job.

Settings (snakemake.params.curves): xi, n_eps, tol (contactalpha.studies.restitution.curves).
Inputs: none (convert_restitution on the grid).
Outputs: data (netCDF, with settings, version, commit and compute time), png, pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.plotting import save_figure
from contactalpha.studies.restitution.curves import RestitutionCurveSettings, restitution_curves
from contactalpha.studies.restitution.figures import restitution_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("restitution_figure", sm.log[0])
s = RestitutionCurveSettings(**sm.params.curves)
ds = restitution_curves(s.xi, s.n_eps, s.tol)
write_dataset_atomic(ds, sm.output.data)
save_figure(restitution_figure(ds), [sm.output.png, sm.output.pdf])
log.info(f"{ds['e_n'].size} points in {ds.attrs['compute_time_s']:.1f} s: {sm.output.png}")
