"""Fig. 12: total energy of the bouncing ball and the accumulated per-collision loss error.

Settings: none.
Inputs: case_a, case_b (runs from ball_cases).
Outputs: the figure as PNG and PDF (output png, pdf), written atomically.
"""

from contactalpha.io import load_dataset, script_logger
from contactalpha.paper.ball.figures import plot_energy
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ball_fig_energy", sm.log[0])
save_figure(
    plot_energy(load_dataset(sm.input.case_a), load_dataset(sm.input.case_b)), [sm.output.png, sm.output.pdf]
)
log.info(f"wrote {sm.output.png} and {sm.output.pdf}")
