"""Fig. 9: post-restitution eps of each model at each load, the deviation table, the statements, the figure.

Settings (snakemake.params.fig9): xi (panels), models, new_model, reference, eps (start, stop, step),
rtol, atol (paper.fig9.compute.Fig9Settings).
Inputs: none.
Outputs: results/models/fig9.h5 (dims model, xi, eps_pre), fig9_max_deviation.md, fig9_statements.md,
and the figure (png, pdf), drawn from the written file.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import time

from contactalpha.config import settings_from
from contactalpha.io import json_text, load_dataset, script_logger, write_dataset_atomic, write_text_atomic
from contactalpha.models import MODELS
from contactalpha.paper.fig9.compute import Fig9Settings, deviation_table, fig9_statements, post_vs_pre
from contactalpha.paper.fig9.figures import fig9
from contactalpha.paper.statements import statements_markdown
from contactalpha.plotting import save_figure
from contactalpha.provenance import git_commit, history_line
from contactalpha.version import __version__

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("models_fig9", sm.log[0])
p = sm.params.fig9
s = settings_from(Fig9Settings, p)
missing = [m for m in (*s.models, s.reference) if m not in MODELS]
if missing:
    raise SystemExit(f"Fig. 9: model(s) {missing} not registered; known: {sorted(MODELS)}")
start = time.perf_counter()
ds = post_vs_pre([*s.models, s.reference], list(s.xi), s.eps_values(), rtol=s.rtol, atol=s.atol)
wall = time.perf_counter() - start
ds.attrs.update(
    config=json_text(dict(p)),
    contactalpha_version=__version__,
    git_commit=git_commit(),
    solver="contactalpha.engine.driver (DOP853, events by change of variable)",
    rtol=s.rtol,
    atol=s.atol,
    wall_time_s=wall,
    history=history_line("models_fig9: post- versus pre-restitution"),
)
footer = f"\n_contactalpha {__version__}, commit {ds.attrs['git_commit']}, computed in {wall:.1f} s._\n"
write_dataset_atomic(ds, sm.output.data)
write_text_atomic(
    sm.output.table,
    "# Fig. 9: largest |post − pre| per model and load (at which pre-restitution ε)\n\n"
    + deviation_table(ds)
    + "\n"
    + footer,
)
statements = fig9_statements(ds, new=s.new_model, reference=s.reference)
write_text_atomic(
    sm.output.statements,
    statements_markdown(statements, "The paper's conclusions about Fig. 9, checked on our numbers") + footer,
)
save_figure(fig9(load_dataset(sm.output.data)), [sm.output.png, sm.output.pdf])
log.info("wrote %s", ", ".join(sm.output))
