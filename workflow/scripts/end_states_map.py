"""Map of the impact end states over (eps, xi): separation, non-separation, creep, no restitution.

Settings: none.
Inputs: results/surface.h5.
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_surface, script_logger
from contactalpha.paper.surface.figures import plot_end_states
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("end_states_map", sm.log[0])
save_figure(plot_end_states(load_surface(sm.input[0])), [sm.output.png, sm.output.pdf])
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
