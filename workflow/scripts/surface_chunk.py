"""Solve one chunk of the alpha(eps, xi) surface: the columns xi[chunk::chunks].

Settings (snakemake.params): epsilon, xi (grid specs of config section surface), solver (tol,
rtol, atol, max_steps), chunks (number of chunks), code_version (source hash; only makes an
engine edit rerun the rule), built into paper.surface.compute.SurfaceSettings.  Wildcard: chunk.
Inputs: none.
Outputs: the chunk as netCDF4/HDF5 (attrs chunk, chunks, compute_seconds), written atomically.
Log: progress lines with points/s.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from dataclasses import asdict

import numba

from contactalpha.config import settings_from
from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.paper.surface.compute import SurfaceSettings, compute_chunk, log_progress

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("surface_chunk", sm.log[0])
numba.set_num_threads(min(sm.threads, numba.config.NUMBA_NUM_THREADS))
s = settings_from(SurfaceSettings, sm.params, ignore=["code_version"])
chunk, chunks = int(sm.wildcards.chunk), s.chunks
eps, xi = s.grid()
label = f"chunk {chunk + 1}/{chunks}"
ds = compute_chunk(eps, xi, chunk, chunks, **asdict(s.solver), progress=log_progress(log, label))
write_dataset_atomic(ds, sm.output[0])
failed = int((ds.status != 0).sum())
log.info(f"{label}: {ds.alpha.size} points in {ds.attrs['compute_seconds']:.2f} s, {failed} failed")
