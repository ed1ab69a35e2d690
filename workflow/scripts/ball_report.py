"""The bouncing ball's statements (results/ball/statements.md) and Figs. 11-21, in one job.

Settings (snakemake.params.first_figures): output name -> (kind, force index) of each
first-collision figure (Figs. 13-21).
Inputs: case_a, case_b (the runs of ball_cases), first (the first collisions of
ball_first_collision).
Outputs: statements (markdown: each statement of the paper's Sect. 6 with its verdict), and
fig11_ball_motion, fig12_ball_energy and the first-collision figures as (png, pdf) pairs;
all written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import json

from contactalpha.io import load_dataset, script_logger, write_text_atomic
from contactalpha.paper.ball.figures import plot_energy, plot_first_collision, plot_motion
from contactalpha.paper.ball.report import statements, statements_markdown
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ball_report", sm.log[0])
a, b, first = (load_dataset(sm.input[k]) for k in ("case_a", "case_b", "first"))
new = first.attrs["new_model"]
notes = [
    f"'The new model' is `{new}` (cases A and B: `{a.attrs['model']}`); "
    f"reference: `{first.attrs['reference']}`; not registered, skipped: {first.attrs['skipped_models']}.",
    f"Case B's contact leaves the load out (Eq. 43) and takes alpha from `{b.attrs['model']}` at ξ = 0.",
]
rows = statements(first, a, b, new, json.loads(first.attrs["classical"]))
write_text_atomic(sm.output.statements, statements_markdown(rows, notes))
log.info(f"{sum(r.verdict == 'holds' for r in rows)} of {len(rows)} statements hold")

figures = {"fig11_ball_motion": lambda: plot_motion(a, b), "fig12_ball_energy": lambda: plot_energy(a, b)}
for name, (kind, force_index) in sm.params.first_figures.items():
    figures[name] = lambda kind=kind, i=force_index: plot_first_collision(
        first, i, kind, reference=first.attrs["reference"]
    )
for name, draw in figures.items():
    paths = list(sm.output[name])
    save_figure(draw(), paths)
    log.info(f"wrote {' and '.join(paths)}")
