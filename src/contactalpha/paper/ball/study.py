"""Studies of the bouncing ball (Sect. 6) as xarray Datasets: whole runs and the first collision.

- ``run_dataset``: one run of ``ball.simulate`` (Figs. 11-12) with its time
  series (dim ``sample``), its per-contact table (dim ``collision``) and the
  end state and counts in the attributes.
- ``first_collision``: the first contact of the ball for every force F,
  restitution eps and model (Figs. 13-21), with the recorded contact paths
  padded with NaN to a common length (dim ``sample``).

Models are named, and a study may ask for one that is not registered yet (the
fitted Shen et al. models arrive later): ``resolve_model`` picks the first
registered name of a preference list and says what it skipped.
"""

import json
from dataclasses import asdict, dataclass, field, replace

import numpy as np
import xarray as xr

from contactalpha import models
from contactalpha.engine.boundary import separation_boundary
from contactalpha.engine.codes import (
    END_STATES,
    NO_RESTITUTION,
    OUT_EPS2,
    OUT_STATE,
    OUT_STATUS,
    OUT_T_END,
    OUT_V_END,
    OUT_X_END,
    OUT_X_MAX,
    REC_T,
    REC_V,
    REC_X,
    SEPARATION,
    STATUS,
)
from contactalpha.engine.driver import ATOL, RTOL
from contactalpha.engine.scaling import time_scale
from contactalpha.io import json_text
from contactalpha.provenance import result_attrs
from contactalpha.scene.ball import (
    COLLISION_FIELDS,
    CONTACT,
    CONTACT_MAX_STEP,
    FLIGHT,
    ContactNumerics,
    Scene,
    contact_alpha,
    damping_work_reference,
    end_state_name,
    energy_terms,
    run_contact,
)


def _legend(codes):
    return "; ".join(f"{k}: {v}" for k, v in codes.items())


def resolve_model(preference):
    """First registered model of ``preference`` (a name or a list of names).

    Returns
    -------
    name : str
    skipped : list of str
        Names before it that are not registered.

    Raises
    ------
    ValueError
        If none is registered.
    """
    names = [preference] if isinstance(preference, str) else list(preference)
    for i, name in enumerate(names):
        if name in models.MODELS:
            return name, names[:i]
    raise ValueError(
        f"models = {names!r}: none is registered; valid: one of {', '.join(sorted(models.MODELS))}"
    )


def registered(names):
    """Split ``names`` into (registered, not registered), keeping the order."""
    names = list(names)
    return [n for n in names if n in models.MODELS], [n for n in names if n not in models.MODELS]


def model_label(name):
    """Legend label of a model name."""
    return models.MODELS[name].label if name in models.MODELS else name


def _provenance(config, step):
    return {
        **result_attrs(config, step),
        "solver": "contactalpha.engine.kernel.impact_kernel (DOP853) per contact; flights in closed form",
    }


def rebounds_above(run, height):
    """Number of rebounds of ``run`` whose apex ``v_out^2 / (2 a)`` exceeds ``height`` (m)."""
    v = run.collisions["v_out"]
    return int(np.sum(v**2 / (2.0 * run.scene.accel) > height))


def run_dataset(run, config=None, *, rtol=RTOL, atol=ATOL):
    """One ``BallRun`` as a Dataset (time series, per-contact ledger, counts in the attrs)."""
    terms = energy_terms(run.scene, run.delta, run.ddelta, run.case, in_contact=run.phase == CONTACT)
    s = run.scene
    ds = xr.Dataset(
        {
            "t": ("sample", run.t, {"units": "s", "long_name": "time since the first contact"}),
            "delta": ("sample", run.delta, {"units": "m", "long_name": "deformation R - y (Eq. 42)"}),
            "ddelta": ("sample", run.ddelta, {"units": "m/s", "long_name": "deformation rate"}),
            "y": ("sample", s.radius - run.delta, {"units": "m", "long_name": "height of the centre"}),
            "ydot": ("sample", -run.ddelta, {"units": "m/s", "long_name": "velocity of the centre (up > 0)"}),
            "phase": ("sample", run.phase, {"legend": f"{FLIGHT}: flight; {CONTACT}: contact"}),
            "contact_index": (
                "sample",
                run.collision,
                {"long_name": "0-based index of the contact of the sample"},
            ),
        }
    )
    for name, values in terms.items():
        ds[f"energy_{name}"] = ("sample", values, {"units": "J", "long_name": f"energy ledger: {name}"})
    for name, (units, meaning) in COLLISION_FIELDS.items():
        ds[f"c_{name}"] = ("collision", run.collisions[name], {"units": units, "long_name": meaning})
    ds["c_state"].attrs["legend"] = _legend(END_STATES)
    ds["c_status"].attrs["legend"] = _legend(STATUS)
    ds.attrs.update(_provenance(config or {}, f"ball run, case {run.case}, model {run.model}"))
    ds.attrs.update(
        {
            "case": run.case,
            "model": run.model,
            "scene": json_text(asdict(s)),
            "end_state": run.end_state,
            "end_time": run.end_time,
            "status": run.status,
            "collisions": run.count,
            "rebounds": run.rebounds,
            "rest_deformation": s.rest_deformation,
            "rebounds_above_rest_deformation": rebounds_above(run, s.rest_deformation),
            "rtol": rtol,
            "atol": atol,
            "counting_rule": (
                "a collision is a contact that begins (delta = 0, ddelta > 0) before t_end; "
                "the final, non-separating contact counts"
            ),
        }
    )
    return ds


# Variables of the first-collision study over (force, epsilon, model).
FIRST_FIELDS = {
    "alpha": ("1", "damping factor given by the model"),
    "eps_post": ("1", "post-restitution coefficient: Stronge's eps of the integrated contact"),
    "state": ("1", "end state of the contact"),
    "status": ("1", "engine status (0 = ok)"),
    "v_out": ("m/s", "rebound speed (0 without separation)"),
    "delta_max": ("m", "maximum deformation"),
    "delta_end": ("m", "deformation at the end of the contact"),
    "t_stop": ("s", "duration of the contact (inf: creeps to rest)"),
}


def first_collision(
    scene, forces, eps_values, model_names, *, rtol=RTOL, atol=ATOL, max_step=CONTACT_MAX_STEP
):
    """The first contact for every force, restitution and model (case A, Eq. 24).

    Parameters
    ----------
    scene : Scene
        Mass, radius, stiffness, approach speed and gravity; its ``force`` and
        ``eps`` are replaced by each combination.
    forces : sequence of float
        Constant forces F, N (>= 0).
    eps_values : sequence of float
        Restitution coefficients asked of the models, each in (0, 1].
    model_names : sequence of str
        Registered model names.

    Returns
    -------
    xarray.Dataset
        Dims ``force``, ``epsilon``, ``model``, ``sample``; ``xi`` over force;
        ``FIRST_FIELDS`` and the paths ``time``, ``delta``, ``ddelta`` and
        ``contact_force`` ``k delta^{3/2} (1 + alpha ddelta / v0)`` (Eq. 13).
    """
    forces = [float(f) for f in forces]
    eps_values = [float(e) for e in eps_values]
    names = list(model_names)
    _, missing = registered(names)
    if missing:
        raise ValueError(f"models {missing} are not registered; valid: {', '.join(sorted(models.MODELS))}")
    shape = (len(forces), len(eps_values), len(names))
    out = {name: np.full(shape, np.nan) for name in FIRST_FIELDS}
    paths = {}
    v0 = scene.approach_speed
    for i, force in enumerate(forces):
        for j, eps in enumerate(eps_values):
            sc = replace(scene, force=force, eps=eps)
            for k, name in enumerate(names):
                alpha = contact_alpha(sc, v0, name, "A")
                path, res, _, ds, ts = run_contact(sc, v0, alpha, "A", rtol, atol, max_step)
                code = int(res[OUT_STATE])
                values = {
                    "alpha": alpha,
                    "eps_post": 0.0 if code == NO_RESTITUTION else np.sqrt(max(res[OUT_EPS2], 0.0)),
                    "state": code,
                    "status": res[OUT_STATUS],
                    "v_out": -res[OUT_V_END] * v0 if code == SEPARATION else 0.0,
                    "delta_max": res[OUT_X_MAX] * ds,
                    "delta_end": res[OUT_X_END] * ds,
                    "t_stop": res[OUT_T_END] * ts,
                }
                for field_name, value in values.items():
                    out[field_name][i, j, k] = value
                paths[i, j, k] = (path[:, REC_T] * ts, path[:, REC_X] * ds, path[:, REC_V] * v0, alpha)
    n = max(p[0].size for p in paths.values())
    series = {name: np.full((*shape, n), np.nan) for name in ("time", "delta", "ddelta", "contact_force")}
    for (i, j, k), (t, d, dd, alpha) in paths.items():
        m = t.size
        series["time"][i, j, k, :m] = t
        series["delta"][i, j, k, :m] = d
        series["ddelta"][i, j, k, :m] = dd
        series["contact_force"][i, j, k, :m] = (
            scene.stiffness * np.maximum(d, 0.0) ** 1.5 * (1.0 + alpha * dd / v0)
        )
    xi = [replace(scene, force=f).influence(v0) for f in forces]
    ds = xr.Dataset(
        coords={
            "force": ("force", forces, {"units": "N", "long_name": "constant force F"}),
            "epsilon": ("epsilon", eps_values, {"units": "1", "long_name": "restitution asked of the model"}),
            "model": ("model", names),
            "model_label": ("model", [model_label(n) for n in names]),
        }
    )
    ds["xi"] = ("force", xi, {"units": "1", "long_name": "influence factor of m (g + F/m) (Eq. 10)"})
    ds["eps_boundary"] = (
        "force",
        exact_separation_boundary(xi, rtol=rtol, atol=atol),
        {"units": "1", "long_name": "exact contact separates for eps above this (0 at xi = 0)"},
    )
    dims = ("force", "epsilon", "model")
    for name, (units, meaning) in FIRST_FIELDS.items():
        ds[name] = (dims, out[name], {"units": units, "long_name": meaning})
    ds["state"] = ds["state"].astype(np.int8)
    ds["status"] = ds["status"].astype(np.int8)
    ds["state"].attrs.update({"legend": _legend(END_STATES), "units": "1"})
    ds["status"].attrs.update({"legend": _legend(STATUS), "units": "1"})
    series_units = {"time": "s", "delta": "m", "ddelta": "m/s", "contact_force": "N"}
    for name, samples in series.items():
        ds[name] = (
            (*dims, "sample"),
            samples,
            {"units": series_units[name], "long_name": f"contact path: {name}"},
        )
    ds.attrs["scene"] = json_text(asdict(scene))
    return ds


def exact_separation_boundary(xi, **tolerances):
    """Restitution ``eps_b(xi)`` on the exact separation boundary; 0 where ``xi = 0`` (always separates).

    Raises ``RuntimeError`` if the boundary search fails.
    """
    xi = np.asarray(xi, dtype=float)
    out = np.zeros_like(xi)
    loaded = xi > 0
    if np.any(loaded):
        _, eps_b, status = separation_boundary(xi[loaded], **tolerances)
        if np.any(status != 0):
            raise RuntimeError(f"separation boundary search failed at xi = {xi[loaded][status != 0]}")
        out[loaded] = eps_b
    return out


def state_names(codes):
    """End-state names of an array of codes (NaN -> 'failed')."""
    codes = np.asarray(codes)
    return np.vectorize(lambda c: end_state_name(c) if np.isfinite(c) else "failed", otypes=[object])(codes)


# The keys of the ``ball.scene`` section: the ``Scene`` fields that are not set per case.
SCENE_KEYS = ("mass", "radius", "stiffness", "approach_speed", "gravity")


@dataclass(frozen=True)
class CaseSettings:
    """Cases A and B of Figs. 11-12: the ``ball.cases`` section (eps, force, t_end: ``Scene``'s).

    ``variants`` are the models case A is also run with (names not registered are skipped).
    """

    eps: float = Scene.eps
    force: float = Scene.force
    t_end: float = Scene.t_end
    variants: tuple = ("shen_published", "shen_refit", "exact")


@dataclass(frozen=True)
class FirstCollisionSettings:
    """The first collision of Figs. 13-21: the ``ball.first_collision`` section.

    One figure per force (N) and kind, one panel per ``eps``; ``classical`` models beside the new
    one, ``formulas`` (further closed forms, e.g. issue 13's; not counted among the classical),
    and the exact ``reference`` as a preference list (the first registered name is used).
    """

    forces: tuple = (0.1, 60.0, 495.0)
    eps: tuple = (0.3, 0.5, 0.7, 0.9)
    classical: tuple = ("hunt_crossley", "flores", "hu_guo")
    formulas: tuple = ("closed_form",)
    reference: tuple = ("exact", "exact_solve")


@dataclass(frozen=True)
class BallSettings:
    """The ball stage's settings: the workflow's ``ball`` section.

    ``scene`` holds the ``SCENE_KEYS`` of ``Scene`` (``default_scene`` builds it); ``new_model`` is
    the paper's new model as a preference list (``resolve_model``).
    """

    scene: dict = field(default_factory=lambda: {k: getattr(Scene, k) for k in SCENE_KEYS})
    new_model: tuple = ("shen_published", "shen_zero_load")
    cases: CaseSettings = field(default_factory=CaseSettings)
    first_collision: FirstCollisionSettings = field(default_factory=FirstCollisionSettings)
    numerics: ContactNumerics = field(default_factory=ContactNumerics)


def default_scene(section):
    """``Scene`` from the ``ball.scene`` config section (mass, radius, stiffness, approach_speed, gravity)."""
    return Scene(**{k: section[k] for k in SCENE_KEYS})


def ledger_closure(ds):
    """Largest ``|E_in - E_out - D| / E_0`` over the contacts of a run Dataset, with ``D`` from SciPy.

    ``D`` is the damping work integrated independently of the engine
    (``ball.damping_work_reference``) up to the contact's end time; contacts that
    creep to rest (end time inf) are left out.  ``E_0`` is the initial total energy.
    """
    scene = Scene(**json.loads(ds.attrs["scene"]))
    worst = 0.0
    for i in range(ds.sizes["collision"]):
        c = {name: float(ds[f"c_{name}"].values[i]) for name in COLLISION_FIELDS}
        if not np.isfinite(c["t_stop"]):
            continue
        tau = (c["t_stop"] - c["t_start"]) / float(time_scale(scene.mass, scene.stiffness, c["v_in"]))
        w, _, _ = damping_work_reference(c["alpha"], c["A"], tau)
        gap = c["energy_in"] - c["energy_out"] - scene.mass * c["v_in"] ** 2 * w
        worst = max(worst, abs(gap))
    return worst / float(ds["c_energy_in"].values[0])


def run_cases(scene, new_model, variants=(), *, config=None, **numerics):
    """Cases A and B with the new model, and case A with each variant model.

    Parameters
    ----------
    scene : Scene
        The scene of Figs. 11-12 (its force, eps and t_end included).
    new_model : str or list of str
        The model of both cases; the first registered name of a list is used.
    variants : sequence of str
        Models to run case A with as well; unregistered ones are skipped.
    config : dict, optional
        Stored in the attributes.
    **numerics
        ``rtol``, ``atol``, ``max_step``, ``flight_samples`` of ``ball.simulate``.

    Returns
    -------
    dict
        ``A``, ``B``: Datasets; ``variants``: list of Datasets (case A);
        ``model``: the model used; ``skipped``: list of (name, reason).
    """
    from contactalpha.scene.ball import simulate

    name, missing = resolve_model(new_model)
    skipped = [(m, f"not registered; the new model falls back to `{name}`") for m in missing]
    tol = {k: numerics[k] for k in ("rtol", "atol") if k in numerics}
    out = {"model": name, "variants": [], "skipped": skipped}
    for case in ("A", "B"):
        out[case] = run_dataset(simulate(scene, name, case, **numerics), config, **tol)
        out[case].attrs["ledger_closure"] = ledger_closure(out[case])
    ok, absent = registered(variants)
    out["skipped"] += [(m, "not registered yet (no variant run)") for m in absent]
    for m in ok:
        if m == name:
            out["skipped"].append((m, "its case A run is the first row"))
            continue
        out["variants"].append(run_dataset(simulate(scene, m, "A", **numerics), config, **tol))
    return out


def run_first_collision(
    scene, forces, eps_values, classical, new_model, reference, *, formulas=(), config=None, **numerics
):
    """``first_collision`` for the classical models, the new model, ``formulas`` and the reference.

    ``new_model`` and ``reference`` are preference lists (``resolve_model``); ``formulas`` are
    further registered models (names not registered are skipped and listed).

    Returns
    -------
    ds : xarray.Dataset
        With attributes ``new_model``, ``reference``, ``classical`` and ``skipped_models``.
    """
    new, miss_new = resolve_model(new_model)
    ref, miss_ref = resolve_model(reference)
    classical = list(classical)
    formulas, miss_formulas = registered(formulas)
    ds = first_collision(scene, forces, eps_values, [*classical, new, *formulas, ref], **numerics)
    ds.attrs.update(_provenance(config or {}, "ball first collision"))
    ds.attrs.update(
        {
            "new_model": new,
            "reference": ref,
            "classical": json_text(classical),
            "formulas": json_text(formulas),
            "skipped_models": json_text(miss_new + miss_formulas + miss_ref),
        }
    )
    return ds
