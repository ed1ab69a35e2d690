"""Figs. 13-21: deformation, deformation rate or hysteresis loop of the first collision at one force.

Settings (snakemake.params): force_index (which force of the study), kind (deformation, velocity
or hysteresis).
Inputs: results/ball/first_collision.nc.
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_dataset, script_logger
from contactalpha.paper.ball.figures import plot_first_collision
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ball_fig_first", sm.log[0])
ds = load_dataset(sm.input[0])
fig = plot_first_collision(ds, sm.params.force_index, sm.params.kind, reference=ds.attrs["reference"])
save_figure(fig, [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
