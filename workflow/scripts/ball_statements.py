"""The paper's Sect. 6 statements on the bouncing ball, each marked holds / does not hold.

Settings: none.
Inputs: case_a, case_b (runs from ball_cases), first (from ball_first).
Outputs: the statements as a markdown table (results/ball/statements.md), written atomically.
"""

import json

from contactalpha.io import load_dataset, script_logger, write_text_atomic
from contactalpha.paper.ball.report import statements, statements_markdown

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ball_statements", sm.log[0])
a, b, first = (load_dataset(sm.input[k]) for k in ("case_a", "case_b", "first"))
new = first.attrs["new_model"]
notes = [
    f"'The new model' is `{new}` (cases A and B: `{a.attrs['model']}`); "
    f"reference: `{first.attrs['reference']}`; not registered, skipped: {first.attrs['skipped_models']}.",
    f"Case B's contact leaves the load out (Eq. 43) and takes alpha from `{b.attrs['model']}` at ξ = 0.",
]
rows = statements(first, a, b, new, json.loads(first.attrs["classical"]))
write_text_atomic(sm.output[0], statements_markdown(rows, notes))
log.info(f"{sum(r.verdict == 'holds' for r in rows)} of {len(rows)} statements hold")
