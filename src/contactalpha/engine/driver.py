"""One impact: the public, validated, broadcasting face of ``kernel.impact_kernel``."""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from contactalpha.defaults import ATOL, RTOL
from contactalpha.validation import (
    PLAIN_FLOATS,
    FloatOrArray,
    RealLike,
    check_alpha,
    check_count,
    check_max_steps,
    check_scalar,
    check_tolerances,
    check_xi,
    plain_in,
    plain_integrator_settings,
)

from .codes import (
    END_STATES,
    N_OUT,
    N_REC,
    OUT_DEPS2,
    OUT_E_N,
    OUT_EPS2,
    OUT_NFEV,
    OUT_STATE,
    OUT_STATUS,
    OUT_STEPS,
    OUT_T_END,
    OUT_T_MAX,
    OUT_V_END,
    OUT_X_END,
    OUT_X_MAX,
    STATUS,
)
from .firstcall import FirstCall
from .kernel import impact_kernel
from .scaling import scaled_load, scaled_load_unchecked
from .threads import flat_owned, run_rows

# Default tolerances (their home is the leaf ``contactalpha.defaults``, which --help reads).
# Step budget of one impact; the stiff ridge (alpha ~ 1e4) needs ~1e5.
MAX_STEPS = 2_000_000


@dataclass(frozen=True)
class ImpactResult:
    """Outcome of one scaled impact (arrays when the inputs were arrays).

    Attributes
    ----------
    eps : Stronge's energetic restitution coefficient (Eq. 17); NaN when the run failed.
    e_n : Newton's kinematic coefficient, separation speed / approach speed (``-v_end``);
        0 when the impact ends without separation, NaN when the run failed or the
        integrator does not report it.
    state : end state name: separation, nonseparation, creep, no_restitution, failed.
    x_max, x_end, v_end : maximum compression and end state, scaled by delta_star
        and v0.  For creep and no restitution the end is the limit t -> inf.
    t_max, t_end : scaled times of maximum compression and of the end (inf for limits).
    steps, nfev : attempted steps and right-hand-side evaluations.
    status : "ok" or the reason the integrator stopped (see ``STATUS``).
    deps_dalpha : sensitivity of eps to alpha.
    """

    eps: FloatOrArray
    state: str | np.ndarray
    x_max: FloatOrArray
    x_end: FloatOrArray
    v_end: FloatOrArray
    t_max: FloatOrArray
    t_end: FloatOrArray
    steps: int | np.ndarray
    nfev: int | np.ndarray
    status: str | np.ndarray
    deps_dalpha: FloatOrArray
    e_n: FloatOrArray = np.nan

    @property
    def ok(self):
        """True where the integrator finished."""
        return np.asarray(self.status) == "ok"


# Below this many points the serial loop wins: waking the worker threads costs more,
# and far more (milliseconds) when other processes hold the cores.
PARALLEL_MIN = 32

# The scalar path's kernel: its Python twin until compiled code is at hand (``firstcall``),
# then the compiled kernel itself.
# Largest alpha the twin integrates: the steps grow with alpha (a few hundred at 1e3, where one
# interpreted impact still costs a fraction of a compile); above it the kernel is compiled.
TWIN_ALPHA_MAX = 1e3
SCALAR_KERNEL: list = []
SCALAR_KERNEL.append(
    FirstCall(
        impact_kernel,
        on_compiled=lambda dispatcher: SCALAR_KERNEL.__setitem__(0, dispatcher),
        interpret_if=lambda alpha, *rest: alpha <= TWIN_ALPHA_MAX,
    )
)

# Empty trajectory record: impacts that record nothing share it.
NO_RECORD = np.empty((0, N_REC))


@njit(cache=True, nogil=True, error_model="numpy")
def impact_rows(alpha, A, rtol, atol, max_steps, out, start, stop):
    """Rows ``start .. stop - 1`` of ``impact_many``'s table, written into ``out``."""
    no_record = np.empty((0, N_REC))
    for i in range(start, stop):
        res, _ = impact_kernel(alpha[i], A[i], rtol, atol, max_steps, no_record, np.inf)
        # Element by element: a row assignment ``out[i] = res`` compiles numba's shape-mismatch
        # error (string formatting), 3 s of CPU on a cold cache.
        for j in range(N_OUT):
            out[i, j] = res[j]


def impact_many(alpha, A, rtol, atol, max_steps, threads=None):
    """Run ``impact_kernel`` over flat arrays ``alpha``, ``A``; returns shape (n, N_OUT).

    Inputs shorter than ``PARALLEL_MIN`` run in this thread; longer ones in
    ``threads.thread_count()`` threads (or ``threads``).  Same bits either way.
    """
    out = np.empty((alpha.size, N_OUT))
    if alpha.size < PARALLEL_MIN:
        threads = 1
    run_rows(impact_rows, alpha.size, alpha, A, rtol, atol, max_steps, out, threads=threads)
    return out


def _as_result(table, shape):
    eps2 = table[:, OUT_EPS2]
    eps = np.sqrt(np.maximum(eps2, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        deps = np.where(eps > 0, table[:, OUT_DEPS2] / (2 * eps), np.nan)
    codes = table[:, OUT_STATE].astype(int)
    status = table[:, OUT_STATUS].astype(int)

    def shaped(a):
        a = a.reshape(shape)
        return a[()] if a.ndim == 0 else a

    return ImpactResult(
        eps=shaped(eps),
        state=shaped(np.array([END_STATES[c] for c in codes], dtype=object)),
        x_max=shaped(table[:, OUT_X_MAX]),
        x_end=shaped(table[:, OUT_X_END]),
        v_end=shaped(table[:, OUT_V_END]),
        t_max=shaped(table[:, OUT_T_MAX]),
        t_end=shaped(table[:, OUT_T_END]),
        steps=shaped(table[:, OUT_STEPS].astype(np.int64)),
        nfev=shaped(table[:, OUT_NFEV].astype(np.int64)),
        status=shaped(np.array([STATUS[s] for s in status], dtype=object)),
        deps_dalpha=shaped(deps),
        e_n=shaped(table[:, OUT_E_N]),
    )


def frozen_instance(cls, **values):
    """``cls(**values)`` for a frozen dataclass ``cls``, built without its ``__init__``.

    A frozen dataclass's ``__init__`` sets each field through ``object.__setattr__`` (~0.3 us a
    field); the scalar fast paths build one result per call, so they fill ``__dict__`` at once.
    The object is the same: equal to ``cls(**values)``, still frozen.  ``values`` must name
    every field (checked: a missing one would surface later as an AttributeError).
    """
    if values.keys() != cls.__dataclass_fields__.keys():
        fields = sorted(cls.__dataclass_fields__)
        raise TypeError(f"{cls.__name__} takes the fields {fields}; got {sorted(values)}")
    obj = object.__new__(cls)
    obj.__dict__.update(values)
    return obj


def _scalar_result(out):
    """``_as_result`` of one kernel row, as Python scalars (the scalar fast path, same numbers)."""
    eps2, de2, code, status = out[OUT_EPS2], out[OUT_DEPS2], out[OUT_STATE], out[OUT_STATUS]
    eps = math.sqrt(eps2) if eps2 > 0.0 else (0.0 if eps2 <= 0.0 else math.nan)
    return frozen_instance(
        ImpactResult,
        eps=eps,
        state=END_STATES[int(code)],
        x_max=float(out[OUT_X_MAX]),
        x_end=float(out[OUT_X_END]),
        v_end=float(out[OUT_V_END]),
        t_max=float(out[OUT_T_MAX]),
        t_end=float(out[OUT_T_END]),
        steps=int(out[OUT_STEPS]),
        nfev=int(out[OUT_NFEV]),
        status=STATUS[int(status)],
        deps_dalpha=float(de2 / (2 * eps)) if eps > 0 else math.nan,
        e_n=float(out[OUT_E_N]),
    )


def impact(
    alpha: RealLike, xi: RealLike, *, rtol: float = RTOL, atol: float = ATOL, max_steps: int = MAX_STEPS
) -> "ImpactResult":
    """Integrate the scaled impact (Eq. 24) for damping ``alpha`` and load ``xi``.

    Parameters
    ----------
    alpha : float or array_like
        Hysteresis damping factor, >= 0.
    xi : float or array_like
        Influence factor of the external load, 0 <= xi < 1 (Eq. 10).
        Broadcast against ``alpha``.
    rtol, atol : float
        Tolerances of the adaptive DOP853 integrator.
    max_steps : int
        Step budget; exceeding it is reported in ``status``, never hidden.

    Returns
    -------
    ImpactResult
        Python scalars for scalar input, else arrays of the broadcast shape.
    """
    if plain_in("alpha", alpha) and plain_in("xi", xi) and plain_integrator_settings(rtol, atol, max_steps):
        out, _ = SCALAR_KERNEL[0](alpha, scaled_load_unchecked(xi), rtol, atol, max_steps, NO_RECORD, np.inf)
        return _scalar_result(out)
    alpha = check_alpha(alpha)
    xi = check_xi(xi)
    rtol, atol = check_tolerances(rtol, atol)
    return impact_unchecked(alpha, xi, rtol=rtol, atol=atol, max_steps=check_max_steps(max_steps))


def impact_unchecked(alpha, xi, *, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
    """``impact`` of a damping, a load factor and settings already checked: for the inner layers."""
    if type(alpha) in PLAIN_FLOATS and type(xi) in PLAIN_FLOATS:
        out, _ = SCALAR_KERNEL[0](alpha, scaled_load_unchecked(xi), rtol, atol, max_steps, NO_RECORD, np.inf)
        return _scalar_result(out)
    alpha, xi = np.broadcast_arrays(np.asarray(alpha, dtype=float), np.asarray(xi, dtype=float))
    shape = alpha.shape
    A = scaled_load_unchecked(xi)
    alpha, A = flat_owned(alpha), flat_owned(A)
    table = impact_many(alpha, A, rtol, atol, max_steps)
    return _as_result(table, shape)


def restitution(alpha: RealLike, xi: RealLike, **kwargs: Any) -> FloatOrArray:
    """Stronge's restitution coefficient produced by ``alpha`` at load ``xi``.

    Same arguments as ``impact``; returns ``impact(...).eps``.  NaN marks a
    failed integration: check ``impact(...).status`` for the reason.
    """
    return impact(alpha, xi, **kwargs).eps


# Largest ``max_rows`` of a trajectory (24 GB of rows): a guard against a mistyped size.
MAX_ROWS_LIMIT = 10**9


def trajectory(
    alpha: float,
    xi: float,
    *,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_step: float = np.inf,
    max_rows: int = 100_000,
) -> tuple[np.ndarray, "ImpactResult"]:
    """Accepted steps ``(t, x, v)`` of one impact, scaled, plus its ``ImpactResult``.

    ``max_step`` caps the time step (scaled time, > 0; ``inf`` for none) for smooth plots and
    quadratures; ``max_rows`` (a whole number >= 1) caps the rows recorded.

    Returns
    -------
    path : ndarray, shape (n, 3)
    result : ImpactResult
    """
    alpha = check_scalar("alpha", alpha, 0.0, np.inf, hi_open=True)
    A = float(scaled_load(check_scalar("xi", xi, 0.0, 1.0, hi_open=True)))
    rtol, atol = check_tolerances(rtol, atol)
    if not (type(max_step) in (float, np.float64) and max_step == np.inf):
        max_step = check_scalar("max_step", max_step, 0.0, np.inf, lo_open=True, hi_open=True)
    max_rows = check_count("max_rows", max_rows, 1, MAX_ROWS_LIMIT)
    rec = np.empty((max_rows, N_REC))
    out, n = impact_kernel(alpha, A, rtol, atol, MAX_STEPS, rec, float(max_step))
    return rec[:n].copy(), _as_result(out[None, :], ())
