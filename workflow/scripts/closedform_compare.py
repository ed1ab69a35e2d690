"""Judge the closed form and Eq. 40 (published, refit) in delivered restitution on the surface.

Settings (snakemake.params): models (registered model names, config closedform.models).
Inputs: surface (results/surface.h5); shipped (the package's constants files the models read).
Outputs: comparison (JSON: max and RMS |eps_delivered - eps|, end-state agreement, worst point,
targets met, per model, with provenance and run time); figure (PNG and PDF error maps).
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import time

from contactalpha.config import settings_from
from contactalpha.io import load_surface, script_logger, write_json_atomic
from contactalpha.paper.closedform.compute import TARGETS, ClosedFormSettings, compare_models
from contactalpha.paper.closedform.figures import error_map
from contactalpha.plotting import save_figure
from contactalpha.provenance import result_attrs

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("closedform_compare", sm.log[0])
start = time.perf_counter()
ds = load_surface(sm.input.surface)
settings = settings_from(ClosedFormSettings, sm.params, ignore=["shipped"])
scores, maps = compare_models(ds, list(settings.models))
record = {
    "models": scores,
    "targets": TARGETS,
    "surface": {k: ds.attrs.get(k) for k in ("git_commit", "solver", "tol", "rtol", "atol")},
    "points": int(next(iter(scores.values()))["n"]),
    "compute_seconds": time.perf_counter() - start,
    **result_attrs({"models": list(settings.models)}, "closedform_compare"),
}
write_json_atomic(sm.output.comparison, record)
save_figure(error_map(ds, maps), list(sm.output.figure))
for name, s in scores.items():
    max_, rms, share = s["eps_abs_max"], s["eps_abs_rms"], s["state_agreement"]
    log.info(f"{name}: max {max_:.3g}, RMS {rms:.3g}, same end state {share:.1%}")
