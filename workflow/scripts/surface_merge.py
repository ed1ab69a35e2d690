"""Merge the surface chunks into results/surface.h5.

Settings (snakemake.params): surface (grid, solver and chunks of the config section; stored as JSON
in the attrs).
Inputs: the chunk files of one run.
Outputs: the merged surface as netCDF4/HDF5, written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.paper.surface.compute import merge_chunks

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("surface_merge", sm.log[0])
ds = merge_chunks(sm.input, config={"surface": sm.params.surface})
write_dataset_atomic(ds, sm.output[0])
log.info(f"merged {ds.attrs['chunks']} chunks: {ds.sizes['epsilon']} x {ds.sizes['xi']} points")
