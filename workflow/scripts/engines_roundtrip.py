"""Round trips of alpha in one engine over the (eps, F) grid.

Settings (snakemake.params): scene (the ball: mass, radius, stiffness, approach_speed, gravity),
grid (eps, forces), settings (the engine's drop_impact keywords).
Built into studies.engines.compute.EnginesSettings.
Inputs: none.
Outputs: roundtrip_{engine}.nc (dims run, epsilon, force), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.studies.engines.compute import EnginesSettings, round_trip, scene_from_config

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_roundtrip", sm.log[0])
p = sm.params
engine = sm.wildcards.engine
config = {"ball": {"scene": p.scene}, "engines": {"grid": p.grid, engine: p.settings}}
s = settings_from(EnginesSettings, config["engines"])
ds = round_trip(engine, scene_from_config(p.scene), s.grid.eps, s.grid.forces, getattr(s, engine), config)
write_dataset_atomic(ds, sm.output[0])
size = f"{ds.sizes['run']} runs x {ds.sizes['epsilon']} eps x {ds.sizes['force']} forces"
log.info(f"{engine}: {size} in {ds.attrs['seconds_total']:.1f} s")
