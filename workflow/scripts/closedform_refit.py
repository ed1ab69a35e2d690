"""Refit the closed form's constants to this run's surface (not in the default run).

Settings (snakemake.params): refit (config closedform.refit: polish_steps, max_nfev).
Inputs: the surface (results/surface.h5). The fit starts from the shipped constants.
Outputs: the constants file (models.closed_form.CONSTANTS_FILE layout) with standard errors,
the fit's report and delivered-eps scores on the fitted and the held-out points;
`snakemake -c2 closedform_ship` copies it into the package.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import time
from dataclasses import asdict

from contactalpha.config import settings_from
from contactalpha.io import load_surface, script_logger, write_json_atomic
from contactalpha.models.closed_form import alpha_closed_form, load_constants
from contactalpha.paper.closedform.compute import (
    ClosedFormRefitSettings,
    constants_record,
    fit_closed_form,
    judge,
    surface_targets,
)

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("closedform_refit", sm.log[0])
start = time.perf_counter()
ds = load_surface(sm.input[0])
t = surface_targets(ds)
refit = settings_from(ClosedFormRefitSettings, sm.params.refit)
fit = fit_closed_form(t, load_constants()["constants"], **asdict(refit))
a = alpha_closed_form(t["eps"], t["xi"], fit.extra["constants"])
scores = {"fitted": judge(a, t, ~t["holdout"]), "held_out": judge(a, t, t["holdout"])}
record = constants_record(fit, scores, dict(ds.attrs))
record["compute_seconds"] = time.perf_counter() - start
record["settings"] = asdict(refit)
write_json_atomic(sm.output[0], record)
for name, s in scores.items():
    max_, rms, share = s["eps_abs_max"], s["eps_abs_rms"], s["state_agreement"]
    log.info(f"{name}: max {max_:.3g}, RMS {rms:.3g}, same end state {share:.1%}")
