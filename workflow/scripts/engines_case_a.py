"""Case A of Sect. 6 in OpenSim with alpha per impact, against the package's own run.

Settings (snakemake.params): scene (the ball), cases (eps, force, t_end of Sect. 6), model
(alpha model per impact), settings (OpenSim drop keywords: accuracy, per_tstar, window).
Built into studies.engines.compute.EnginesSettings.
Inputs: none.
Outputs: case_A_opensim.nc (per-contact ledgers, counts and rest times in the attributes).
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from dataclasses import replace

from contactalpha.config import settings_from
from contactalpha.io import script_logger, write_dataset_atomic
from contactalpha.studies.engines.compute import EnginesSettings, case_a, scene_from_config

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_case_a", sm.log[0])
p = sm.params
scene = replace(
    scene_from_config(p.scene), eps=p.cases["eps"], force=p.cases["force"], t_end=p.cases["t_end"]
)
config = {
    "ball": {"scene": p.scene, "cases": p.cases},
    "engines": {"case_a_model": p.model, "opensim": p.settings},
}
s = settings_from(EnginesSettings, config["engines"])
ds = case_a(scene, s.case_a_model, s.opensim, config)
write_dataset_atomic(ds, sm.output[0])
a = ds.attrs
log.info(
    f"OpenSim {a['opensim_count']} collisions, rest at {a['opensim_rest_time']:.9f} s; "
    f"package {a['package_count']}, {a['package_rest_time']:.9f} s"
)
