"""The engines' markdown summary: round-trip table, errors, static checks, case A.

Settings (snakemake.params): eps_tol (the issue's 1e-3 target).
Built into studies.engines.compute.EnginesSettings.
Inputs: roundtrips (roundtrip_*.nc), static (static.nc), case_a (case_A_opensim.nc).
Outputs: summary.md, written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import load_dataset, script_logger, write_text_atomic
from contactalpha.studies.engines.compute import EnginesSettings
from contactalpha.studies.engines.report import summary_markdown

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("engines_summary", sm.log[0])
s = settings_from(EnginesSettings, sm.params)
roundtrips = [load_dataset(path) for path in sm.input.roundtrips]
text = summary_markdown(roundtrips, load_dataset(sm.input.static), load_dataset(sm.input.case_a), s.eps_tol)
write_text_atomic(sm.output[0], text)
log.info(f"wrote {sm.output[0]}")
