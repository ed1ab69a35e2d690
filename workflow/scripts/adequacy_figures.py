"""Figures of the adequacy study: adequacy per tol, the cheapest adequate model, xi_ignore, v_crit.

Settings: none.
Inputs: maps (results/adequacy/maps.h5), thresholds (results/adequacy/thresholds.nc).
Outputs: results/figures/adequacy_tol<tol>, adequacy_cheapest, adequacy_xi_ignore, critical_speed
(.png and .pdf each), written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.io import load_dataset, script_logger
from contactalpha.plotting import save_figure
from contactalpha.studies.adequacy import figures

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("adequacy_figures", sm.log[0])
ds = load_dataset(sm.input.maps)
made = {f"adequacy_tol{t:g}": figures.adequacy_figure(ds, t) for t in ds["tol"].values}
made["adequacy_cheapest"] = figures.cheapest_figure(ds)
made["adequacy_xi_ignore"] = figures.xi_ignore_figure(ds)
made["critical_speed"] = figures.critical_speed_figure(load_dataset(sm.input.thresholds))
outputs = {}
for path in sm.output:
    outputs.setdefault(Path(path).stem, []).append(path)
if set(outputs) != set(made):
    raise ValueError(f"figure outputs {sorted(outputs)} differ from the figures made {sorted(made)}")
for name, fig in made.items():
    save_figure(fig, outputs[name])
log.info(f"{len(made)} figures")
