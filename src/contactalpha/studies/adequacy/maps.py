"""Adequacy maps over (eps, xi): where each model delivers the requested restitution.

On the grid of the alpha surface (``results/surface.h5``, its log-spaced small-xi columns
included), each registered model's alpha is integrated over one impact at each point; the
model is adequate there when ``scene.advisor.is_adequate`` says so (delivered eps within
``tol`` and the exact end state, the surface's ``state``).  The exact solved alpha is the
surface's own alpha (not solved again).  Ignoring the load means the exact alpha at
``xi = 0``; ``xi_ignore(eps; tol)`` is the largest grid ``xi`` up to which that stays
adequate at every grid column.
"""

import numpy as np
import xarray as xr

from contactalpha import models
from contactalpha.engine.codes import FAILED, STATE_CODES
from contactalpha.engine.driver import impact
from contactalpha.engine.exact import alpha_exact
from contactalpha.scene.advisor import cheapest, is_adequate

# The registry name whose alpha is the surface itself.
SURFACE_MODEL = "exact_solve"
# Name of the "load ignored" variant in the maps.
IGNORE = "ignore_load"
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
    costs : mapping name -> seconds per evaluation (``advisor.measure_costs``)

    Returns
    -------
    xarray.Dataset
        Dims ``model``, ``tol``, ``epsilon``, ``xi``: ``alpha``, ``delivered_eps``, ``state``,
        ``adequate`` (int8), ``cheapest`` (index into ``model``, -1 none), ``cost_seconds``,
        ``ignore_adequate``, ``xi_ignore`` (tol, epsilon) and ``area_share`` (tol, model).
    """
    names = list(models.MODELS)
    eps = surface["epsilon"].values
    xi = surface["xi"].values
    E, X = np.meshgrid(eps, xi, indexing="ij")
    exact_state = surface["state"].values
    alphas, deliv, states = [], [], []
    for name in [*names, IGNORE]:
        a = (
            np.broadcast_to(alpha_exact(eps)[:, None], E.shape)
            if name == IGNORE
            else model_alpha(name, surface)
        )
        d, s = delivered(a, X)
        alphas.append(a)
        deliv.append(d)
        states.append(s)
    alphas, deliv, states = np.array(alphas), np.array(deliv), np.array(states)
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
            "cost_seconds": (("model",), np.array([costs[m] for m in names])),
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
