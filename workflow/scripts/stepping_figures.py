"""Figures of docs/stepping.md: e_N over the touchdown phase at three steps; the step a tolerance needs.

Settings: none (studies.stepping.compute: ZETA, LOAD, STEPS, MAP_ZETAS, MAP_LOADS, MAP_TOL).
Outputs: phase_png, phase_pdf, map_png, map_pdf.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.io import script_logger
from contactalpha.plotting import save_figure
from contactalpha.studies.stepping import compute
from contactalpha.studies.stepping.figures import phase_figure, step_map_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("stepping_figures", sm.log[0])
curves = compute.phase_curves()
save_figure(phase_figure(curves, compute.ZETA, compute.LOAD), [sm.output.phase_png, sm.output.phase_pdf])
table = compute.step_needed()
fig = step_map_figure(table, compute.MAP_ZETAS, compute.MAP_LOADS, compute.MAP_TOL)
save_figure(fig, [sm.output.map_png, sm.output.map_pdf])
log.info(f"wrote {sm.output.phase_png} and {sm.output.map_png}")
