"""Solve one chunk of the alpha(eps, xi) surface: the columns xi[chunk::chunks].

Settings (snakemake.params): epsilon, xi (grid specs of config section surface), solver (tol,
rtol, atol, max_steps), chunks (number of chunks), code_version (source hash; only makes an
engine edit rerun the rule).  Wildcard: chunk.
Inputs: none.
Outputs: the chunk as netCDF4/HDF5 (attrs chunk, chunks, compute_seconds), written atomically.
Log: progress lines with points/s.
"""

from dataclasses import asdict

import numba

from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.paper.surface.compute import SolverSettings, compute_chunk, grid_from_config, log_progress

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("surface_chunk", sm.log[0])
numba.set_num_threads(min(sm.threads, numba.config.NUMBA_NUM_THREADS))
chunk, chunks = int(sm.wildcards.chunk), int(sm.params.chunks)
eps, xi = grid_from_config({"epsilon": sm.params.epsilon, "xi": sm.params.xi})
label = f"chunk {chunk + 1}/{chunks}"
solver = SolverSettings(**sm.params.solver)
ds = compute_chunk(eps, xi, chunk, chunks, **asdict(solver), progress=log_progress(log, label))
write_dataset_atomic(ds, sm.output[0])
failed = int((ds.status != 0).sum())
log.info(f"{label}: {ds.alpha.size} points in {ds.attrs['compute_seconds']:.2f} s, {failed} failed")
