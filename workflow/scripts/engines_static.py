"""Static penetration in each engine against (m a / k)^(2/3): the stiffness conversions.

Settings (snakemake.params): scene (the ball), forces (N).
Inputs: none.
Outputs: static.nc (dims engine, force), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.studies.engines.compute import (
    ENGINES,
    engine_version,
    provenance,
    scene_from_config,
    static_checks,
)

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_static", sm.log[0])
p = sm.params
ds = static_checks(scene_from_config(p.scene), p.forces)
config = {"ball": {"scene": p.scene}, "engines": {"grid": {"forces": p.forces}}}
ds.attrs.update(provenance(config, "static penetration", {e: engine_version(e) for e in ENGINES}))
write_dataset_atomic(ds, sm.output[0])
log.info(f"max |relative error| {float(abs(ds['relative_error']).max()):.1e}")
