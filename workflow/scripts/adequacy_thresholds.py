"""Physical bounce threshold of typical scenes and the scaled separation boundary for the v_crit figure.

Settings (snakemake.params): scenes (name, eps, mass, radius, modulus, accel, source), vcrit_eps;
code_version only makes an edit of the study rerun the rule.
Built into studies.adequacy.report.AdequacySettings.
Inputs: none.
Outputs: data (netCDF4/HDF5 with provenance and run time), table (markdown), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import time

from contactalpha.config import settings_from
from contactalpha.io import script_logger, write_dataset_atomic, write_text_atomic
from contactalpha.provenance import result_attrs
from contactalpha.studies.adequacy.report import (
    AdequacySettings,
    scene_thresholds,
    thresholds_dataset,
    thresholds_markdown,
)

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("adequacy_thresholds", sm.log[0])
start = time.perf_counter()
s = settings_from(AdequacySettings, sm.params, ignore=["code_version"])
scenes = [dict(scene) for scene in s.scenes]
rows = scene_thresholds(scenes)
ds = thresholds_dataset(rows, list(s.vcrit_eps))
config = {"adequacy": {"scenes": scenes, "vcrit_eps": list(s.vcrit_eps)}}
ds.attrs.update(result_attrs(config, "adequacy thresholds"), compute_seconds=time.perf_counter() - start)
write_dataset_atomic(ds, sm.output.data)
write_text_atomic(sm.output.table, thresholds_markdown(rows))
log.info("; ".join(f"{r.name}: v_crit = {r.v_crit:.4g} m/s" for r in rows))
