"""Delivered Newton e_N of each engine's usual mapping and of the exact inverse, across target and load.

For every law of the family the engines' mapping (a registered model, ``models.engine_mappings``)
turns a target restitution into the law's damping, ignoring the load; the exact model solves the
law under the load.  Both are judged by what the law then delivers (``ContactLaw.impact``).
"""

import time
from dataclasses import asdict, dataclass

import numpy as np
import xarray as xr

from contactalpha.models import ALL_MODELS, alpha
from contactalpha.provenance import result_attrs

# (law, the engines' mapping, the exact model): the pairs the figure and table show.
PAIRS = (
    ("hunt_crossley", "hunt_crossley", "exact_solve"),
    ("hunt_crossley_linear", "drake_bound", "hunt_crossley_linear_exact"),
    ("kelvin_voigt", "classic_zeta", "kelvin_voigt_exact"),
    ("mujoco_soft", "mujoco_dampratio", "mujoco_soft_exact"),
    ("hertz_tsuji", "tsuji_beta", "hertz_tsuji_exact"),
)


@dataclass(frozen=True)
class LawStudySettings:
    """Grid of the study: targets e in [e_min, e_max] (n_e points) and load factors xi."""

    e_min: float = 0.05
    e_max: float = 0.95
    n_e: int = 19
    xi: tuple = (0.0, 0.05, 0.2, 0.5)


def _delivered(model_name, target, xi):
    """(damping, delivered e_N, end state) of ``model_name`` for targets at one load factor."""
    model = ALL_MODELS[model_name]
    # A model that takes Stronge's eps gets the target as eps (at zero load both are the same).
    restitution = "kinematic" if "kinematic" in model.restitutions else "energetic"
    p = np.asarray(alpha(target, np.full(target.shape, xi), model=model_name, restitution=restitution), float)
    r = model.contact_law.impact(p, xi)
    return p, np.asarray(r.e_n, float), np.asarray(r.state, dtype=str)


def delivered_restitution(settings=LawStudySettings()):
    """Dataset: delivered e_N of mapping and exact model per (law, xi, target)."""
    start = time.perf_counter()
    target = np.linspace(settings.e_min, settings.e_max, settings.n_e)
    xi = np.asarray(settings.xi, float)
    shape = (len(PAIRS), xi.size, target.size)
    out = {
        k: np.full(shape, np.nan) for k in ("mapping_damping", "mapping_e_n", "exact_damping", "exact_e_n")
    }
    state = np.full(shape, "", dtype=object)
    for i, (_, mapping, exact) in enumerate(PAIRS):
        for j, x in enumerate(xi):
            out["mapping_damping"][i, j], out["mapping_e_n"][i, j], state[i, j] = _delivered(
                mapping, target, x
            )
            out["exact_damping"][i, j], out["exact_e_n"][i, j], _ = _delivered(exact, target, x)
    coords = {"law": [p[0] for p in PAIRS], "xi": xi, "target": target}
    dims = ("law", "xi", "target")
    ds = xr.Dataset({k: (dims, v) for k, v in out.items()}, coords=coords)
    ds["mapping_state"] = (dims, state.astype(str))
    ds = ds.assign_coords(mapping=("law", [p[1] for p in PAIRS]), exact=("law", [p[2] for p in PAIRS]))
    ds.attrs.update(result_attrs(asdict(settings), "laws_delivered"))
    ds.attrs["compute_time_s"] = time.perf_counter() - start
    return ds


def delivered_table(ds, targets=(0.3, 0.5, 0.8)):
    """Markdown: delivered e_N of each law's mapping against the exact model at three loads."""
    rows = [
        "| law | engines' mapping | target e_N | " + " | ".join(f"ξ = {x:g}" for x in ds["xi"].values) + " |",
        "|---|---|---|" + "---|" * ds["xi"].size,
    ]
    for law in ds["law"].values:
        sub = ds.sel(law=law)
        for t in targets:
            k = int(np.argmin(np.abs(sub["target"].values - t)))
            cells = [
                f"{sub['mapping_e_n'].values[j, k]:.4f} (exact {sub['exact_e_n'].values[j, k]:.4f})"
                for j in range(sub["xi"].size)
            ]
            head = f"| {law} | {sub['mapping'].values} | {sub['target'].values[k]:.2f} | "
            rows.append(head + " | ".join(cells) + " |")
    return "\n".join(rows) + "\n"
