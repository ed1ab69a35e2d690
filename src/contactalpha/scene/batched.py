"""The front door for arrays of scenes: every engine's parameters as arrays, for domain randomisation.

``contact_parameters`` sends array input here.  Each scene is a mass, a stiffness, an approach
speed, a load and a target restitution; the arrays broadcast.  The law's damping comes from the
law's fast evaluator (``ContactLaw.fast_damping``; for Hunt-Crossley, n = 3/2, the shipped exact
table at ``engine.scaling``'s xi, as the scalar front door), and each registered engine of that law
converts it (``adapters.registry.engine_parameters``).  A law written per unit mass (MuJoCo's) takes
mass 1 and the stiffness per unit mass, as ``contactalpha.laws`` documents.  No impact is integrated
per scene: the restitutions delivered are the evaluator's (the table's ~1e-7 in alpha).

Scenes outside the evaluator's domain (a target below its smallest restitution, a load factor above
its largest, a load so large that the load factor rounds to 1) get NaN parameters and ``ok = False``,
and the other rows are what they would be without them; bad values (a negative mass, a target above 1,
a bool or a string) raise ``ValueError`` naming them.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from contactalpha.adapters.registry import check_radius_used, engine_parameters
from contactalpha.engine.scaling import A_ROUNDS_TO_ONE, length_scale, xi_of_load_kernel
from contactalpha.engine.table import EPS_MIN, XI_MAX, alpha_tabulated
from contactalpha.laws import get_law
from contactalpha.laws.domain import check_restitution
from contactalpha.laws.fast import ENGINE_TABLE
from contactalpha.validation import check_positive, check_range


@dataclass(frozen=True)
class BatchedParameters:
    """``contact_parameters`` of many scenes; every field an array of the scenes' broadcast shape.

    Attributes
    ----------
    law : name of the contact law.
    xi : load factor of each scene.
    damping : the law's damping parameter (alpha for Hunt-Crossley, zeta for the spring-dashpots).
    ok : True where the scene is inside the evaluator's domain (elsewhere the numbers are NaN).
    engines : ``{engine: {parameter: array}}`` for every registered engine of the law.
    """

    law: str
    xi: np.ndarray
    damping: np.ndarray
    ok: np.ndarray
    engines: dict


@dataclass(frozen=True)
class _Scenes:
    mass: np.ndarray
    stiffness: np.ndarray
    approach_speed: np.ndarray
    radius: object


@njit(cache=True, error_model="numpy")
def _xi_of_loads(A):
    """``engine.scaling``'s Eq. 10 (its jitted ``xi_of_load_kernel``) over an array, in one loop."""
    out = np.empty(A.size)
    flat = A.ravel()
    for i in range(flat.size):
        out[i] = xi_of_load_kernel(flat[i])
    return out.reshape(A.shape)


def hertz_load_factor(mass, stiffness, approach_speed, accel):
    """The paper's influence factor xi (Eq. 10) of arrays of Hunt-Crossley scenes.

    ``engine.scaling.influence_factor``'s direct path (``A = a delta* / v^2``), with Eq. 10 solved
    in one compiled loop; a load so large that xi rounds to 1 gives NaN here.
    """
    with np.errstate(all="ignore"):
        A = accel * length_scale(mass, stiffness, approach_speed) / approach_speed**2
    A = np.where(np.isfinite(A) & (A < A_ROUNDS_TO_ONE), A, np.nan)
    xi = _xi_of_loads(np.ascontiguousarray(A, dtype=float))
    return np.where(xi < 1.0, xi, np.nan)


def law_load_factor(law, mass, stiffness, approach_speed, accel):
    """Load factor xi of arrays of scenes of ``law``; NaN where the load is so large that it rounds to 1."""
    A = np.asarray(law.load(mass, stiffness, approach_speed, accel), dtype=float)
    xi = np.full(A.shape, np.nan)
    finite = np.isfinite(A)
    xi[finite] = law.load_factor(A[finite])
    return np.where(xi < 1.0, xi, np.nan)


def batched_parameters(
    mass,
    stiffness,
    approach_speed,
    accel,
    target,
    *,
    restitution="kinematic",
    law="hunt_crossley",
    radius=None,
):
    """Every engine's parameters for arrays of scenes (see the module docstring).

    Parameters
    ----------
    mass, stiffness, approach_speed : array_like
        kg, the law's stiffness (N/m^1.5 for n = 3/2, N/m for n = 1), m/s; all > 0.
    accel : array_like
        Acceleration of the load pressing the bodies together, m/s^2 (>= 0).
    target : array_like
        Target restitution in (0, 1].
    restitution : {"kinematic", "energetic"}
        Newton's e_N or Stronge's eps.
    law : str or ContactLaw
        The contact law (``contactalpha.laws``).
    radius : array_like, optional
        Sphere radius, m (adds OpenSim's stiffness).

    Returns
    -------
    BatchedParameters
    """
    law = get_law(law)
    target_name = "eps" if check_restitution(restitution) == "energetic" else "e_N"
    check_radius_used(law, radius)
    m, k, v = (
        np.asarray(check_positive(n, x), dtype=float)
        for n, x in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed))
    )
    a = np.asarray(check_range("accel", accel, 0.0, np.inf, hi_open=True), dtype=float)
    e = np.asarray(check_range(target_name, target, 0.0, 1.0, lo_open=True), dtype=float)
    r = None if radius is None else np.asarray(check_positive("radius", radius), dtype=float)
    m, k, v, a, e, r_all = np.broadcast_arrays(m, k, v, a, e, 1.0 if r is None else r)
    r = None if r is None else r_all
    if law.fast is ENGINE_TABLE:  # n = 3/2: the front door's own xi and table, bit for bit
        xi = hertz_load_factor(m, k, v, a)
        ok = (e >= EPS_MIN) & (xi <= XI_MAX)
        damping = np.full(e.shape, np.nan)
        damping[ok] = alpha_tabulated(e[ok], xi[ok], restitution=restitution)
    else:
        xi = law_load_factor(law, m, k, v, a)
        damping = np.full(e.shape, np.nan)
        inside = np.isfinite(xi)
        damping[inside] = law.fast_damping(e[inside], xi[inside], restitution)
        ok = np.isfinite(damping)
    engines = engine_parameters(law, np.where(ok, damping, 0.0), _Scenes(m, k, v, r))
    for values in engines.values():
        for name, x in values.items():
            if isinstance(x, np.ndarray) and x.shape == ok.shape:
                values[name] = np.where(ok, x, np.nan)
    return BatchedParameters(law.name, xi, damping, ok, engines)
