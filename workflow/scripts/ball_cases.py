"""Bouncing ball, cases A and B (Figs. 11-12), and case A with the variant models.

Settings (snakemake.params): scene (mass, radius, stiffness, approach_speed, gravity),
cases (eps, force, t_end, variants), new_model (preference list), numerics (rtol, atol,
max_step, flight_samples). Built into paper.ball.study.BallSettings.
Inputs: none.
Outputs: case_a, case_b (netCDF4/HDF5 runs with time series and per-contact ledger),
summary (markdown: counts, end states, counting rule, skipped models); all written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from dataclasses import asdict, replace

from contactalpha.config import settings_from
from contactalpha.io import script_logger, write_dataset_atomic, write_text_atomic
from contactalpha.paper.ball.report import cases_markdown
from contactalpha.paper.ball.study import BallSettings, default_scene, run_cases

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ball_cases", sm.log[0])
p = sm.params
s = settings_from(BallSettings, p, ignore=["shipped_refit"])
scene = replace(default_scene(s.scene), force=s.cases.force, eps=s.cases.eps, t_end=s.cases.t_end)
config = {"ball": {"scene": p.scene, "cases": p.cases, "new_model": p.new_model, "numerics": p.numerics}}
out = run_cases(scene, list(s.new_model), list(s.cases.variants), config=config, **asdict(s.numerics))
write_dataset_atomic(out["A"], sm.output.case_a)
write_dataset_atomic(out["B"], sm.output.case_b)
write_text_atomic(sm.output.summary, cases_markdown([out["A"], out["B"], *out["variants"]], out["skipped"]))
for ds in (out["A"], out["B"], *out["variants"]):
    a = ds.attrs
    log.info(f"case {a['case']} {a['model']}: {a['collisions']} collisions, {a['end_state']}")
