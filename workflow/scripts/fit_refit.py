"""Refit Eqs. 26, 34, 39 and 40 to the surface and compare with the published constants.

Settings (snakemake.params): readings, weights, loss, verdict_k, eq26 (xi, eps_max, or null),
restitution (see contactalpha.paper.fit.report.FitSettings).
Inputs: results/surface.h5.
Outputs: coefficients (JSON report), comparison (markdown table), readings (evidence note on
Eq. 40's damaged term), package (refit constants; rule fit_ship copies them into the package).
Nothing is written when a fit does not converge: the rule fails with scipy's message.
The rule's threads are worker processes, each fit single-threaded (same bits for any number).
"""

from prefork import delegate, one_blas_thread

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)
one_blas_thread()  # before numpy loads, here and in the worker processes (the server's already is)

from contactalpha.io import load_surface, script_logger, write_json_atomic, write_text_atomic
from contactalpha.paper.fit import report as fit_report
from contactalpha.paper.fit.compute import FitNotConverged

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_refit", sm.log[0])
settings = dict(sm.params.items())
log.info(f"fits in {sm.threads} worker process(es)")
try:
    report, fits = fit_report.refit_report(load_surface(sm.input[0]), workers=sm.threads, **settings)
except FitNotConverged as err:
    log.error(str(err))
    raise
excluded = report["points"]["excluded"]
log.info(f"{report['points']['fitted']} points fitted, {excluded['count']} excluded {excluded['by_reason']}")
for p in excluded["points"]:
    log.info(f"excluded eps = {p['eps']:g}, xi = {p['xi']:g}: {p['reason']}")
for name, f in fits["readings"].items():
    log.info(f"reading {name}: converged = {f.converged}, RMS = {f.rms:.4g} ({f.message})")
write_json_atomic(sm.output.coefficients, report)
write_text_atomic(sm.output.comparison, fit_report.comparison_markdown(report))
write_text_atomic(sm.output.readings, fit_report.readings_markdown(report))
write_json_atomic(sm.output.package, fit_report.package_coefficients(report))
log.info(f"wrote {', '.join(sm.output)}")
