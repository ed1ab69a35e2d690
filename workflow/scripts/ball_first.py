"""Bouncing ball, the first collision for every force, restitution and model (Figs. 13-21).

Settings (snakemake.params): scene (mass, radius, stiffness, approach_speed, gravity),
first_collision (forces, eps, classical, formulas, reference), new_model (preference list),
numerics (rtol, atol, max_step). Built into paper.ball.study.BallSettings.
Inputs: none.
Outputs: data (netCDF4/HDF5: per-run results and contact paths), table (markdown: post-restitution
eps and end state of every combination); written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from contactalpha.config import settings_from
from contactalpha.io import script_logger, write_dataset_atomic, write_text_atomic
from contactalpha.paper.ball.report import first_collision_table
from contactalpha.paper.ball.study import BallSettings, default_scene, run_first_collision

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ball_first", sm.log[0])
p = sm.params
s = settings_from(BallSettings, p, ignore=["shipped_refit"])
first = s.first_collision
numerics = {k: getattr(s.numerics, k) for k in ("rtol", "atol", "max_step")}
config = {
    "ball": {
        "scene": p.scene,
        "first_collision": p.first_collision,
        "new_model": p.new_model,
        "numerics": numerics,
    }
}
ds = run_first_collision(
    default_scene(s.scene),
    list(first.forces),
    list(first.eps),
    list(first.classical),
    list(s.new_model),
    list(first.reference),
    formulas=list(first.formulas),
    config=config,
    **numerics,
)
write_dataset_atomic(ds, sm.output.data)
head = (
    "# Bouncing ball, first collision: post-restitution ε (end state)\n\n"
    f"New model: `{ds.attrs['new_model']}`; further formulas: {ds.attrs['formulas']}; "
    f"reference: `{ds.attrs['reference']}`; "
    f"models not registered and skipped: {ds.attrs['skipped_models']}.\n\n"
)
write_text_atomic(sm.output.table, head + first_collision_table(ds))
log.info(
    f"first collision: {ds.sizes['force']} forces, {ds.sizes['epsilon']} eps, {ds.sizes['model']} models"
)
