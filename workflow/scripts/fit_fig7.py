"""Fig. 7: the damped compression integral s_a of the computed impacts against s1 (Eq. 31).

Settings: none.
Inputs: results/surface.h5.
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_surface, script_logger
from contactalpha.paper.fit.figures import fig7_sa
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("fit_fig7", sm.log[0])
save_figure(fig7_sa(load_surface(sm.input[0])), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
