"""Adequacy maps over (eps, xi): where each model delivers the requested restitution.

On the grid of the alpha surface (``results/surface.h5``, its log-spaced small-xi columns
included), each registered model's alpha is integrated over one impact at each point; the
model is adequate there when ``scene.advisor.is_adequate`` says so (delivered eps within
``tol`` and the exact end state, the surface's ``state``).  The exact solved alpha is the
surface's own alpha (not solved again).  Ignoring the load means the exact alpha at
``xi = 0``; ``xi_ignore(eps; tol)`` is the largest grid ``xi`` up to which that stays
adequate at every grid column.
"""

import json
import time
from dataclasses import asdict, dataclass

import numpy as np
import xarray as xr

from contactalpha import models
from contactalpha.engine.codes import FAILED, STATE_CODES
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL, impact
from contactalpha.engine.exact import alpha_exact
from contactalpha.provenance import result_attrs
from contactalpha.scene import advisor
from contactalpha.scene.advisor import cheapest, is_adequate

# The registry name whose alpha is the surface itself.
SURFACE_MODEL = "exact_solve"
# Code of "no model adequate" in the map of the cheapest model.
NONE_ADEQUATE = -1


def delivered(alpha, xi):
    """Delivered eps and end-state codes of one impact per point; NaN/FAILED where alpha is not valid."""
    alpha, xi = np.broadcast_arrays(np.asarray(alpha, dtype=float), np.asarray(xi, dtype=float))
    eps = np.full(alpha.shape, np.nan)
    state = np.full(alpha.shape, FAILED, dtype=np.int8)
    ok = np.isfinite(alpha) & (alpha >= 0.0)
    if ok.any():
        r = impact(alpha[ok], xi[ok])
        eps[ok] = np.where(r.ok, r.eps, np.nan)
        state[ok] = [STATE_CODES[s] for s in np.atleast_1d(r.state)]
    return eps, state


def delivered_all(alpha, xi):
    """``delivered`` of every (alpha, xi) pair in one parallel call; equal pairs integrated once.

    One call keeps both threads busy over all models and points together (the per-model
    calls left a thread idle at each call's tail), and models that give the same alpha (the
    unloaded exact alpha is both ``exact_unloaded`` and "ignore the load") cost one impact.
    The kernel's result for a pair does not depend on the others, so this is bit for bit
    the same as ``delivered`` point by point.
    """
    alpha = np.asarray(alpha, dtype=float)
    pairs = np.stack([alpha.ravel(), np.asarray(xi, dtype=float).ravel()], axis=1)
    unique, back = np.unique(pairs, axis=0, return_inverse=True)
    eps, state = delivered(unique[:, 0], unique[:, 1])
    back = back.ravel()
    return eps[back].reshape(alpha.shape), state[back].reshape(alpha.shape)


@dataclass(frozen=True)
class StrideSettings:
    """The mapped subgrid (``subgrid``): the workflow's ``adequacy.stride`` section.

    The default, every 2nd eps row and every 2nd xi column above 0.01 with the log-spaced columns
    below kept, maps 50 x 75 of the 99 x 124 surface points with area shares within 0.6% of the
    whole grid's; strides of 1 map the whole grid.
    """

    epsilon: int = 2
    xi: int = 2
    keep_xi_below: float = 0.01


def subgrid(surface, eps_stride=1, xi_stride=1, keep_xi_below=0.0):
    """The surface on every ``eps_stride``-th eps row and every ``xi_stride``-th xi column.

    Columns with ``xi <= keep_xi_below`` are all kept (the log-spaced small-xi columns that
    resolve the ridge near xi = 0); the stride applies to the columns above.  Strides of 1
    keep the whole grid.
    """
    for name, value in (("eps_stride", eps_stride), ("xi_stride", xi_stride)):
        if int(value) != value or value < 1:
            raise ValueError(f"{name} = {value!r} is outside the valid range: an integer >= 1")
    xi = surface["xi"].values
    fine = np.flatnonzero(xi <= keep_xi_below)
    coarse = np.flatnonzero(xi > keep_xi_below)[:: int(xi_stride)]
    columns = np.union1d(fine, coarse)
    return surface.isel(epsilon=slice(None, None, int(eps_stride)), xi=columns)


def model_alpha(name, surface):
    """Alpha of model ``name`` on the surface grid (NaN where the model refuses the point)."""
    if name == SURFACE_MODEL:
        return surface["alpha"].values
    e, x = np.meshgrid(surface["epsilon"].values, surface["xi"].values, indexing="ij")
    try:
        return np.asarray(models.alpha(e, x, model=name), dtype=float)
    except ValueError:  # a domain narrower than the grid: point by point, refused points NaN
        out = np.full(e.shape, np.nan)
        for idx in np.ndindex(e.shape):
            try:
                out[idx] = float(models.alpha(e[idx], x[idx], model=name))
            except ValueError:
                pass  # this point is outside the model's domain: NaN, never adequate
        return out


def compute_maps(surface, tols, costs):
    """Adequacy of every registered model, and of ignoring the load, over the surface's grid.

    Parameters
    ----------
    surface : xarray.Dataset
        ``io.load_surface`` of ``results/surface.h5``.
    tols : sequence of float
        Tolerances on the delivered eps.
    costs : mapping name -> operations per evaluation (``advisor.COST_MODEL``)

    Returns
    -------
    xarray.Dataset
        Dims ``model``, ``tol``, ``epsilon``, ``xi``: ``alpha``, ``delivered_eps``, ``state``,
        ``adequate`` (int8), ``cheapest`` (index into ``model``, -1 none), ``cost``,
        ``ignore_adequate``, ``xi_ignore`` (tol, epsilon) and ``area_share`` (tol, model).
    """
    names = list(models.MODELS)
    eps = surface["epsilon"].values
    xi = surface["xi"].values
    E, X = np.meshgrid(eps, xi, indexing="ij")
    exact_state = surface["state"].values
    alphas = np.array(
        [model_alpha(name, surface) for name in names]
        + [np.broadcast_to(np.asarray(alpha_exact(eps))[:, None], E.shape)]
    )
    deliv, states = delivered_all(alphas, np.broadcast_to(X, alphas.shape))
    adequate = np.array([is_adequate(deliv, states, E, exact_state, tol) for tol in tols])
    errors = np.abs(deliv - E)
    n = len(names)
    best = np.full((len(tols), *E.shape), NONE_ADEQUATE, dtype=np.int16)
    for t in range(len(tols)):
        for idx in np.ndindex(E.shape):
            pick = cheapest(
                names, adequate[t, :n][(slice(None), *idx)], costs, errors[:n][(slice(None), *idx)]
            )
            if pick is not None:
                best[(t, *idx)] = names.index(pick)
    weights = _area_weights(xi)[None, :] * np.ones_like(E)
    share = (adequate[:, :n] * weights).sum(axis=(2, 3)) / weights.sum()
    ds = xr.Dataset(
        {
            "alpha": (("model", "epsilon", "xi"), alphas[:n]),
            "delivered_eps": (("model", "epsilon", "xi"), deliv[:n]),
            "state": (("model", "epsilon", "xi"), states[:n]),
            "adequate": (("tol", "model", "epsilon", "xi"), adequate[:, :n].astype(np.int8)),
            "cheapest": (("tol", "epsilon", "xi"), best),
            "cost": (("model",), np.array([costs[m] for m in names])),
            "area_share": (("tol", "model"), share),
            "ignore_alpha": (("epsilon", "xi"), alphas[n]),
            "ignore_delivered_eps": (("epsilon", "xi"), deliv[n]),
            "ignore_adequate": (("tol", "epsilon", "xi"), adequate[:, n].astype(np.int8)),
            "xi_ignore": (
                ("tol", "epsilon"),
                np.array([xi_ignore(xi, adequate[t, n]) for t in range(len(tols))]),
            ),
            "exact_state": (("epsilon", "xi"), exact_state),
        },
        coords={"model": names, "tol": np.asarray(tols, dtype=float), "epsilon": eps, "xi": xi},
    )
    ds["cheapest"].attrs["legend"] = "; ".join(f"{i}: {m}" for i, m in enumerate(names)) + "; -1: none"
    ds["area_share"].attrs["long_name"] = "share of the (eps, xi) area where the model is adequate"
    ds["xi_ignore"].attrs["long_name"] = "largest grid xi up to which alpha at xi = 0 stays adequate"
    return ds


def xi_ignore(xi, adequate):
    """Per row: the largest ``xi`` such that every column up to it is adequate (NaN if not even xi[0])."""
    adequate = np.asarray(adequate, dtype=bool)
    first_bad = np.where(adequate.all(axis=1), adequate.shape[1], np.argmin(adequate, axis=1))
    return np.where(first_bad > 0, np.asarray(xi)[np.maximum(first_bad - 1, 0)], np.nan)


def _area_weights(xi):
    """Trapezoid weights of the xi columns (a log-spaced column stands for its own tiny width)."""
    xi = np.asarray(xi, dtype=float)
    if xi.size == 1:
        return np.ones(1)
    w = np.zeros(xi.size)
    d = np.diff(xi) / 2.0
    w[:-1] += d
    w[1:] += d
    return w


def run_maps(surface, tols, stride, config=None):
    """``compute_maps`` on ``subgrid(surface, **stride)`` with measured costs, provenance and run time.

    Parameters
    ----------
    surface : xarray.Dataset
        ``io.load_surface`` of ``results/surface.h5``.
    tols : sequence of float
    stride : StrideSettings
        The mapped subgrid (``subgrid``'s strides).
    config : dict, optional
        The settings that made the maps, stored as JSON in ``attrs["config"]``.

    Returns
    -------
    xarray.Dataset
        ``compute_maps``'s, with attrs: provenance (``provenance.result_attrs``), the impact
        integrator's ``rtol``/``atol``/``max_steps``, ``cost_tie`` (the costs themselves, the
        advisor's fixed cost model, are ``cost``, so the cheapest-model map is reproducible
        from the file), the surface's commit and config,
        ``grid_fraction`` (points mapped over the surface's) and ``compute_seconds``.
    """
    start = time.perf_counter()
    sub = subgrid(surface, stride.epsilon, stride.xi, stride.keep_xi_below)
    costs = advisor.model_costs()
    ds = compute_maps(sub, tols, costs)
    ds.attrs.update(
        {
            **result_attrs(config or {}, "adequacy maps"),
            "rtol": RTOL,
            "atol": ATOL,
            "max_steps": MAX_STEPS,
            "cost_tie": advisor.COST_TIE,
            "stride": json.dumps(asdict(stride), sort_keys=True),
            "surface_git_commit": str(surface.attrs.get("git_commit", "unknown")),
            "surface_config": str(surface.attrs.get("config", "")),
            "grid_fraction": sub["alpha"].size / surface["alpha"].size,
            "compute_seconds": time.perf_counter() - start,
        }
    )
    return ds
