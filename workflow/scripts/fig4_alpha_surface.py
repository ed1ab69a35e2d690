"""Fig. 4: the alpha(eps, xi) surface with a log colour scale.

Settings: none.
Inputs: results/surface.h5.
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_surface, script_logger
from contactalpha.paper.surface.figures import plot_alpha_surface
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fig4_alpha_surface", sm.log[0])
save_figure(plot_alpha_surface(load_surface(sm.input[0])), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
