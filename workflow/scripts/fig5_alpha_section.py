"""Fig. 5: alpha(eps) at one xi (the paper: 0.2) with regions I-III, Eq. 25 and Eq. 26.

Settings (snakemake.params.figures): section_xi, eq26 (tau, sigma, beta).
Inputs: results/surface.h5.
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_surface, script_logger
from contactalpha.paper.surface.figures import plot_section
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fig5_alpha_section", sm.log[0])
figures = sm.params.figures
fig = plot_section(load_surface(sm.input[0]), figures["section_xi"], **figures["eq26"])
save_figure(fig, [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
