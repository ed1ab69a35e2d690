"""Adequacy maps of every registered model over the surface's grid (studies.adequacy.maps.run_maps).

Settings (snakemake.params): tols, stride (epsilon, xi, keep_xi_below); code_version only makes an
edit of the study rerun the rule. Built into studies.adequacy.report.AdequacySettings.
Inputs: surface (results/surface.h5).
Outputs: results/adequacy/maps.h5 (netCDF4/HDF5, with provenance, the measured model costs and
the run time), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from dataclasses import asdict

import numba

from contactalpha.config import settings_from
from contactalpha.io import load_surface, script_logger, write_dataset_atomic
from contactalpha.studies.adequacy.maps import run_maps
from contactalpha.studies.adequacy.report import AdequacySettings

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("adequacy_maps", sm.log[0])
numba.set_num_threads(min(sm.threads, numba.config.NUMBA_NUM_THREADS))
s = settings_from(AdequacySettings, sm.params, ignore=["shipped_refit", "code_version"])
config = {"adequacy": {"tols": list(s.tols), "stride": asdict(s.stride)}}
ds = run_maps(load_surface(sm.input.surface), list(s.tols), s.stride, config=config)
write_dataset_atomic(ds, sm.output[0])
log.info(
    f"{ds.sizes['model']} models on {ds.sizes['epsilon']} x {ds.sizes['xi']} points "
    f"in {ds.attrs['compute_seconds']:.2f} s ({numba.get_num_threads()} threads)"
)
