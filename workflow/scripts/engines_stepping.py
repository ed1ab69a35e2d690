"""Round trips in one stepping engine (MuJoCo, Drake's discrete plant, PyBullet) at its own step.

Settings: none (the study's TARGETS and LOADS).
Inputs: none.
Outputs: stepping_{engine}.nc (dims target, load), written atomically; an engine that is not
installed gives a file that says so (attribute ``skipped``), and one log line.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import xarray as xr

from contactalpha.adapters.registry import adapter, installed
from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.studies.engines.stepping import round_trips

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_stepping", sm.log[0])
engine = sm.wildcards.engine
if installed(adapter(engine)):
    ds = round_trips(engine)
    log.info(f"{engine}: {ds.sizes['target']} targets x {ds.sizes['load']} loads")
else:
    note = f"{adapter(engine).module} not installed (pip install -e '.[engines]')"
    ds = xr.Dataset(attrs={"engine": engine, "skipped": note})
    log.info(f"{engine}: skipped, {note}")
write_dataset_atomic(ds, sm.output[0])
