"""The adequacy study's generated statements (the paper's "small xi" claim) and summary tables.

Settings (snakemake.params): report_eps (rows of the xi_ignore table).
Built into studies.adequacy.report.AdequacySettings.
Inputs: results/adequacy/maps.h5.
Outputs: statements (markdown, paper.statements table), summary (markdown: area shares, costs,
xi_ignore, cheapest-model shares), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import load_dataset, script_logger, write_text_atomic
from contactalpha.paper.statements import statements_markdown
from contactalpha.studies.adequacy.report import AdequacySettings, small_claim_statements, summary_markdown

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("adequacy_report", sm.log[0])
ds = load_dataset(sm.input[0])
rows = small_claim_statements(ds)
notes = [
    f"Maps on {ds.sizes['epsilon']} ε × {ds.sizes['xi']} ξ points of the surface "
    f"(stride {ds.attrs['stride']}); "
    "a model is adequate where its α, integrated over one impact, delivers ε within tol "
    "and the exact end state."
]
write_text_atomic(sm.output.statements, statements_markdown(rows, "The paper's levels of ξ, checked", notes))
write_text_atomic(
    sm.output.summary, summary_markdown(ds, list(settings_from(AdequacySettings, sm.params).report_eps))
)
log.info(f"{sum(r.verdict == 'holds' for r in rows)} of {len(rows)} statements hold")
