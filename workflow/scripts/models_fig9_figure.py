"""Fig. 9 figure: post- versus pre-restitution, one panel per load.

Settings: none.
Inputs: results/models/fig9.h5.
Outputs: the figure as PNG and PDF, written atomically.
"""

from contactalpha.io import load_dataset, script_logger
from contactalpha.paper.fig9.figures import fig9
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("models_fig9_figure", sm.log[0])
save_figure(fig9(load_dataset(sm.input[0])), [sm.output.png, sm.output.pdf])
log.info("wrote %s and %s", sm.output.png, sm.output.pdf)
