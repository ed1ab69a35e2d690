"""The dissipation ratios eta_c, eta_r (Eqs. 36-37) implied by the computed impacts, and Eq. 40's eta.

Settings: none.
Inputs: results/surface.h5.
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_surface, script_logger
from contactalpha.paper.fit.figures import eta_figure
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_eta", sm.log[0])
save_figure(eta_figure(load_surface(sm.input[0])), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
