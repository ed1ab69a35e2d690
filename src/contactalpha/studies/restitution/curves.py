"""e_N(eps) at several loads xi: the data of the restitution figure.

Each point is one ``convert_restitution`` (the solver's alpha for eps, and e_N of that impact);
the separation boundary eps_b(xi), below which the impact ends without separation and e_N = 0,
comes from ``separation_boundary``.
"""

import time
from dataclasses import dataclass

import numpy as np
import xarray as xr

from contactalpha.engine.boundary import separation_boundary
from contactalpha.engine.restitution import convert_restitution
from contactalpha.provenance import result_attrs


@dataclass(frozen=True)
class RestitutionCurveSettings:
    """Grid of the e_N-versus-eps figure; defaults of the workflow's ``restitution.curves`` section."""

    # Loads from none (e_N = eps) to one near the paper's largest, where e_N lags eps most.
    xi: tuple = (0.0, 0.2, 0.5, 0.8, 0.95)
    # Uniform eps points on (0, 1]; 200 resolve the bend of each curve at its boundary.
    n_eps: int = 200
    tol: float = 1e-12


def restitution_curves(
    xi=RestitutionCurveSettings.xi, n_eps=RestitutionCurveSettings.n_eps, tol=RestitutionCurveSettings.tol
):
    """Newton's e_N of the impact whose Stronge restitution is eps, on an (xi, eps) grid.

    Parameters
    ----------
    xi : sequence of float
        Loads, each 0 <= xi < 1.
    n_eps : int
        Number of eps points, uniform on [1/n_eps, 1].
    tol : float
        Tolerance of the alpha solve (``solve_alpha``'s ``tol``).

    Returns
    -------
    xarray.Dataset
        ``e_n`` (xi, eps); ``eps_boundary`` (xi), 0 at xi = 0 (every unloaded impact separates);
        attrs with settings, version, commit and compute time.
    """
    if int(n_eps) != n_eps or n_eps < 2:
        raise ValueError(f"n_eps = {n_eps!r} is not an integer >= 2")
    xi = np.asarray(xi, dtype=float)
    eps = np.linspace(1.0 / n_eps, 1.0, int(n_eps))
    start = time.perf_counter()
    e_n = convert_restitution(eps[None, :], xi[:, None], to="kinematic", tol=tol)
    loaded = xi > 0.0
    eps_b = np.zeros_like(xi)
    if loaded.any():
        eps_b[loaded] = separation_boundary(xi[loaded])[1]
    settings = dict(xi=xi.tolist(), n_eps=int(n_eps), tol=tol)
    attrs = result_attrs(settings, "restitution_curves")
    attrs["compute_time_s"] = time.perf_counter() - start
    return xr.Dataset(
        {
            "e_n": (("xi", "eps"), e_n, {"long_name": "Newton's kinematic restitution e_N"}),
            "eps_boundary": ("xi", eps_b, {"long_name": "eps on the separation boundary"}),
        },
        coords={"xi": xi, "eps": eps},
        attrs=attrs,
    )
