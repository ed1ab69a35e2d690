"""Round trips of alpha in one engine over the (eps, F) grid.

Settings (snakemake.params): scene (the ball: mass, radius, stiffness, approach_speed, gravity),
grid (eps, forces), settings (the engine's drop_impact keywords).
Inputs: none.
Outputs: roundtrip_{engine}.nc (dims run, epsilon, force), written atomically.
"""

from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.studies.engines.compute import round_trip, scene_from_config

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_roundtrip", sm.log[0])
p = sm.params
engine = sm.wildcards.engine
config = {"ball": {"scene": p.scene}, "engines": {"grid": p.grid, engine: p.settings}}
ds = round_trip(engine, scene_from_config(p.scene), p.grid["eps"], p.grid["forces"], dict(p.settings), config)
write_dataset_atomic(ds, sm.output[0])
size = f"{ds.sizes['run']} runs x {ds.sizes['epsilon']} eps x {ds.sizes['force']} forces"
log.info(f"{engine}: {size} in {ds.attrs['seconds_total']:.1f} s")
