"""One figure per engine page: the restitution the engine delivers against the target.

Two parameter sets side by side, at two loads: the engine's usual mapping of a restitution
(Hunt-Crossley's alpha = 3(1 - e)/2, Exudyn's impact models, MuJoCo's classic dampratio, Drake's
d = 1/(e v), Bullet's classic zeta) and this package's answer.  The numbers are the workflow's
round trips: ``roundtrip_{engine}.nc`` (OpenSim, Exudyn: Stronge's eps, integrated at tight
accuracy) and ``stepping_{engine}.nc`` (MuJoCo, Drake, PyBullet: Newton's e_N, mean over
touchdown phases at the engine's own step).
"""

from dataclasses import dataclass

import numpy as np

from contactalpha.plotting import FULL_WIDTH, plt, use_style
from contactalpha.studies.engines.report import RUN_HEADS
from contactalpha.studies.engines.stepping_report import USUAL_TEXT

# The two loads of the continuous engines' figures, N: gravity alone nearly (xi ~ 0.02) and the
# paper's heavy push (xi ~ 0.23); the nearest forces of the run's grid are drawn.
FORCES = (0.1, 60.0)
# The two scaled loads A = a / (omega v) of the stepping engines' figures (nearest of the run's).
LOADS = (0.05, 0.6)


@dataclass(frozen=True)
class Series:
    """One parameter set at one load: targets and what the engine delivered."""

    label: str
    usual: bool
    load: str
    target: np.ndarray
    delivered: np.ndarray


def _roundtrip_series(ds):
    engine = ds.attrs["engine"]
    out = []
    for force in FORCES:
        r = ds.sel(force=force, method="nearest")
        load = f"F = {float(r['force']):g} N (ξ = {float(r['xi'].mean()):.2f})"
        for run in ds["run"].values:
            name = str(run)
            if name.endswith("_implicit"):
                continue  # the same parameters, another integrator of the engine
            ours = name == f"{engine}_exact"
            label = "ours: contact_parameters" if ours else RUN_HEADS[name]
            out.append(
                Series(label, not ours, load, ds["epsilon"].values, r.sel(run=run)["eps_measured"].values)
            )
    return out


def _stepping_series(ds):
    engine = ds.attrs["engine"]
    out = []
    for A in LOADS:
        r = ds.sel(load=A, method="nearest")
        load = f"A = {float(r['load']):g} (ξ = {float(r['xi'].mean()):.2f})"
        out.append(
            Series("ours: refined at the step", False, load, ds["target"].values, r["e_n_refined"].values)
        )
        out.append(
            Series(f"usual: {USUAL_TEXT[engine]}", True, load, ds["target"].values, r["e_n_usual"].values)
        )
    return out


def page_series(ds):
    """The ``Series`` of one engine's round-trip dataset (``roundtrip_*`` or ``stepping_*``)."""
    if ds.attrs.get("skipped"):
        return []
    return _roundtrip_series(ds) if "run" in ds.dims else _stepping_series(ds)


def page_figure(ds):
    """Delivered against target: ours in blue, the usual mappings in warm colours, two loads."""
    use_style()
    fig, ax = plt.subplots(figsize=(0.62 * FULL_WIDTH, 0.48 * FULL_WIDTH), layout="constrained")
    ax.plot([0, 1], [0, 1], color="0.6", lw=0.8, zorder=0, label="target")
    series = page_series(ds)
    loads = list(dict.fromkeys(s.load for s in series))
    usual = list(dict.fromkeys(s.label for s in series if s.usual))
    colors = {label: f"C{3 + k}" for k, label in enumerate(usual)}
    for s in series:
        heavy = loads.index(s.load) == 1
        ax.plot(
            s.target, s.delivered, ls="--" if heavy else "-", marker="^" if s.usual else "o", ms=5,
            color=colors.get(s.label, "C0"), mfc="none" if heavy else colors.get(s.label, "C0"), lw=1.0,
            label=f"{s.label}, {s.load}",
        )  # fmt: skip
    restitution = "ε" if "run" in ds.dims else "e_N"
    engine = ds.attrs["engine"]
    ax.set_title(engine if not ds.attrs.get("skipped") else f"{engine}: {ds.attrs['skipped']}")
    ax.set_xlabel(f"target {restitution}")
    ax.set_ylabel(f"{restitution} delivered in {engine}")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(-0.02, 1.0)
    ax.legend(fontsize="x-small", loc="upper left")
    return fig
