"""Delivered e_N of the engines' usual mappings and of the exact inverse, law by law: data, figure, table.

Settings: the package's defaults (contactalpha.studies.laws.compute.LawStudySettings); snakemake.params.
code_version (source hash) only makes an edit of the laws or the models rerun it.
Inputs: none.
Outputs: data (netCDF, with settings, version, commit and compute time), png, pdf, table (Markdown).
"""

from contactalpha.prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (contactalpha/prefork.py)

from contactalpha.io import script_logger, write_dataset_atomic, write_text_atomic
from contactalpha.plotting import save_figure
from contactalpha.studies.laws.compute import delivered_restitution, delivered_table
from contactalpha.studies.laws.figures import delivered_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("laws_delivered", sm.log[0])
ds = delivered_restitution()
write_dataset_atomic(ds, sm.output.data)
save_figure(delivered_figure(ds), [sm.output.png, sm.output.pdf])
write_text_atomic(sm.output.table, delivered_table(ds))
log.info(f"{ds['mapping_e_n'].size} points in {ds.attrs['compute_time_s']:.1f} s: {sm.output.png}")
