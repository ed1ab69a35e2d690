"""alpha for a target restitution: the paper's Fig. 3 process, as a safeguarded Newton method.

For a target ``eps`` at load ``xi`` the root of ``eps(alpha) = eps_target`` is
found with Newton steps on ``ln eps`` against ``ln alpha`` (exact for the
``alpha ~ 1/eps`` law of light damping), using the sensitivity ``deps/dalpha``
integrated along each impact, so every iteration costs one impact.  A bracket
``[lo, hi]`` with ``eps(lo) > target > eps(hi)`` is kept from the start
(``eps(0) = 1``) and any step that leaves it is replaced by bisection, so the
method cannot diverge; ``eps(alpha)`` is monotone decreasing (docs/science.md,
"Shape of the surface").

- ``xi = 0`` uses the exact relation (``exact.alpha_exact``), no ODE.
- The starting guess is the exact table (``table.py``, ~1e-7 relative) where
  it covers the point, so one Newton step usually lands within tolerance;
  elsewhere, and when building the table itself, it is the exact unloaded
  alpha.
- Below ``eps = SMALL_EPS`` the target sits next to the onset, where eps^2 ~ onset - alpha is
  the overshoot ``x_m - x_eq`` of a compression that creeps into ``x_eq``: the integrator's
  error in it is ~ rtol x_eq whatever way eps^2 is evaluated.  The impacts of such a point
  are integrated with ``rtol`` (and ``atol``) scaled by ``(eps / SMALL_EPS)^2``, down to
  ``RTOL_FLOOR``, so that eps keeps its relative accuracy.  Measured against SciPy's DOP853
  at its floor rtol 2.2e-14 (xi = 1e-4 ... 0.99), the eps reached agrees to 1.1e-9 at
  eps = 1e-3, 4.6e-8 at 1e-4, 3.2e-6 at 1e-5 and 6.3e-4 at 1e-6 (before: 1.4e-8, 1.4e-6,
  1.4e-4, 1.2e-2); SciPy's own runs at rtol 1e-13 and 2.2e-14 differ by as much, so these
  bound the error from above (``test_small_eps_keeps_its_relative_accuracy``).  The solver
  stops within ``max(tol, 3e-16 / eps)`` of the target, the identity's resolution there, or
  where alpha itself is resolved to a few ulp: a tol below what eps(alpha) resolves at double
  alpha (e.g. 2e-12 in e_N = 0.01 at xi = 0.99) is then met only to that resolution.
- ``eps = 0`` at ``xi > 0`` returns the onset: the smallest alpha at which the
  compression never reverses (end state ``no_restitution``), to relative
  ``ONSET_RTOL``; Newton then works on ``eps^2``, which is linear there.

Every point is solved from a starting guess that depends on its own
``(eps, xi)`` only, so a grid gives bit-identical results however it is split.
"""

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from contactalpha.defaults import EPS_TOL
from contactalpha.validation import (
    PLAIN_FLOATS,
    RESTITUTIONS,
    FloatOrArray,
    RealLike,
    check_eps,
    check_flag,
    check_max_steps,
    check_range,
    check_restitution,
    check_tolerances,
    check_xi,
    plain_in,
    plain_integrator_settings,
)

from .codes import (
    END_STATES,
    FAILED,
    N_OUT,
    N_REC,
    N_SOLVE_OUT,
    NO_BRACKET,
    NO_RESTITUTION,
    NOT_CONVERGED,
    OK,
    OUT_DE_N,
    OUT_DEPS2,
    OUT_E_N,
    OUT_EPS2,
    OUT_NFEV,
    OUT_STATE,
    OUT_STATUS,
    OUT_STEPS,
    OUT_X_END,
    OUT_X_MAX,
    SEPARATION,
    SOL_ALPHA,
    SOL_E_N,
    SOL_EPS,
    SOL_IMPACTS,
    SOL_NFEV,
    SOL_STATE,
    SOL_STATUS,
    SOL_STEPS,
    SOL_X_END,
    SOL_X_MAX,
    STATUS,
)
from .driver import ATOL, MAX_STEPS, PARALLEL_MIN, RTOL
from .exact import alpha_exact_scalar, max_compression_exact
from .kernel import impact_kernel
from .scaling import scaled_load, scaled_load_unchecked
from .table import EPS_MIN, XI_MAX, alpha_from_table, kinematic_alpha_from_table
from .threads import flat_owned, run_rows

# Default absolute tolerance on the restitution coefficient reached (its home: ``defaults``), and
# the loosest accepted.
TOL_MAX = 1e-3
# Relative width of the final bracket around the onset alpha (eps = 0).
ONSET_RTOL = 1e-11
# Iteration limit; each iteration is one impact.
MAX_ITER = 60
# Growth factor while no upper bracket is known yet.
EXPAND = 8.0
# Guard on alpha: no root of the domain eps >= 1e-6 lies beyond it (the largest, ~1e12, sit just
# below the onset at xi ~ 1e-7).  A proposal beyond it is tried at ALPHA_MAX once; only if eps
# is still above the target there is "no root bracketed" reported.
ALPHA_MAX = 1e15
# Beyond this |d ln eps / d ln alpha| the point is close to the onset, where eps^2 is nearly
# linear in alpha (eps ~ sqrt(onset - alpha)): Newton then works on eps^2, not on ln eps.
STEEP = 4.0
# alpha counts as found when a Newton step or the bracket shrinks below this (relative, a few
# ulp): a double alpha cannot resolve eps to EPS_TOL next to the onset.
ALPHA_RESOLVED = 4e-16
# Below this target, next to the onset, the energy identity's own resolution ends the iteration
# when it is coarser than tol: eps^2 = A (x_m - x_e) / (1/2 + A x_m) is known to
# A (rtol x_m + atol) / (1/2 + A x_m) at best, while eps^2 itself is ~ onset - alpha.
SMALL_EPS = 0.01
# Tightest integrator tolerance the small-eps points use: a few ulp per step, the floor that
# validation.check_tolerances allows.
RTOL_FLOOR = 1e-15
# Next to the onset the alpha-sensitivity from the linearised end (events.linear_turn) is only
# approximate: where the secant of the last two eps^2 differs from it by more than this
# (relative), Newton takes the secant's slope.
SECANT_SWITCH = 0.2


@njit(cache=True, error_model="numpy")
def _bisect(lo, hi):
    """Midpoint of the bracket, geometric when it spans more than a factor of 4."""
    if not np.isfinite(hi):
        return EXPAND * max(lo, 1.0)
    if lo > 0.0 and hi > 4.0 * lo:
        return np.sqrt(lo * hi)
    return 0.5 * (lo + hi)


@njit(cache=True, error_model="numpy")
def _target_of(res, kinematic):
    """``(e^2, d e^2 / d alpha, ended without restitution)`` of the definition being solved for.

    Energetic: Stronge's eps, which vanishes only at the onset (no restitution).
    Kinematic: Newton's e_N, which vanishes for every impact that does not separate.
    """
    if kinematic:
        e_n = res[OUT_E_N]
        return e_n * e_n, 2.0 * e_n * res[OUT_DE_N], res[OUT_STATE] != SEPARATION
    return res[OUT_EPS2], res[OUT_DEPS2], res[OUT_STATE] == NO_RESTITUTION


@njit(cache=True, error_model="numpy")
def solve_kernel(eps_t, A, alpha0, tol, rtol, atol, max_steps, kinematic=False):
    """Find alpha with ``eps(alpha, A) = eps_t`` (``e_N(alpha, A) = eps_t`` when ``kinematic``).

    The kinematic target must be > 0: e_N = 0 holds on a whole range of alpha.

    Returns
    -------
    out : ndarray, shape (N_SOLVE_OUT,)
        ``alpha, eps_reached, state, status, impacts, steps, x_m, x_e, nfev, e_N_reached``
        in the slots ``codes.SOL_*``.
    """
    out = np.full(N_SOLVE_OUT, np.nan)
    lo = 0.0
    hi = np.inf
    # eps^2 and its alpha-derivative at lo (the Newton fallback next to the onset).
    lo_e2 = 1.0
    lo_de2 = np.nan
    # The previous iterate with eps > 0, for the secant.
    prev_alpha = np.nan
    prev_e2 = np.nan
    alpha = alpha0
    best = np.full(N_OUT, np.nan)
    impacts = 0
    steps = 0
    nfev = 0
    status = NOT_CONVERGED
    onset = eps_t == 0.0
    if 0.0 < eps_t < SMALL_EPS:
        # eps^2's error is ~ rtol x_eq next to the onset: shrink the tolerances with eps_t^2.
        shrink = max((eps_t / SMALL_EPS) ** 2, min(1.0, RTOL_FLOOR / rtol))
        rtol *= shrink
        atol *= shrink
    for _ in range(MAX_ITER):
        res, _ = impact_kernel(alpha, A, rtol, atol, max_steps, np.empty((0, N_REC)), np.inf)
        impacts += 1
        steps += int(res[OUT_STEPS])
        nfev += int(res[OUT_NFEV])
        if res[OUT_STATUS] != OK:
            status = int(res[OUT_STATUS])
            best = res
            break
        e2, de2_here, dead = _target_of(res, kinematic)
        eps = np.sqrt(max(e2, 0.0))
        if onset:
            if res[OUT_STATE] == NO_RESTITUTION:
                hi = alpha
                best = res
            else:
                lo = alpha
            if np.isfinite(hi) and hi - lo <= ONSET_RTOL * hi:
                status = OK
                alpha = hi
                break
            rising = res[OUT_STATE] != NO_RESTITUTION and res[OUT_DEPS2] < 0.0
            new = alpha - e2 / res[OUT_DEPS2] if rising else np.inf
            # Aim a hair past the Newton estimate, so the bracket closes from above too.
            new *= 1.0 + 0.5 * ONSET_RTOL
        else:
            best = res
            # Only an impact that ends in the target's own end state meets it: an impact without
            # restitution (or, kinematic, without separation) reaches 0, within tol of a tiny target.
            if abs(eps - eps_t) <= tol and not dead:
                status = OK
                break
            has_slope = eps > 0.0 and de2_here < 0.0 and alpha > 0.0 and not dead
            if eps > eps_t:
                lo = alpha
                lo_e2 = e2
                lo_de2 = de2_here if has_slope else np.nan
            else:
                hi = alpha
            new = np.inf
            near_onset = dead
            if has_slope:
                slope = alpha * de2_here / (2.0 * e2)
                near_onset = slope < -STEEP
                if near_onset:
                    # Newton on eps^2, which is linear in alpha at the onset.
                    de2 = de2_here
                    if prev_alpha != alpha and np.isfinite(prev_alpha):
                        secant = (e2 - prev_e2) / (alpha - prev_alpha)
                        if secant < 0.0 and abs(secant - de2) > SECANT_SWITCH * abs(secant):
                            de2 = secant
                    new = alpha - (e2 - eps_t * eps_t) / de2
                    if eps_t < SMALL_EPS:
                        x_m = res[OUT_X_MAX]
                        wc = 0.5 + A * x_m
                        # e_N^2 = v_e^2 is known to 2 e_N (rtol e_N + atol) at best.
                        res_e2 = (
                            2.0 * eps * (rtol * eps + atol) if kinematic else A * (rtol * x_m + atol) / wc
                        )
                        if abs(e2 - eps_t * eps_t) <= res_e2:
                            status = OK  # eps^2 meets the target to its own resolution
                            break
                else:
                    # Newton on ln eps versus ln alpha.
                    new = alpha * np.exp(-(np.log(eps) - np.log(eps_t)) / slope)
                if abs(new - alpha) <= ALPHA_RESOLVED * alpha:
                    status = OK  # the root is this alpha to a few ulp
                    break
                prev_alpha = alpha
                prev_e2 = e2
            if near_onset and not (lo < new < hi) and lo_de2 < 0.0:
                new = lo - (lo_e2 - eps_t * eps_t) / lo_de2
        if not (lo < new < hi) or not np.isfinite(new):
            new = _bisect(lo, hi)
        if new > ALPHA_MAX:
            if lo >= ALPHA_MAX:
                status = NO_BRACKET  # eps(ALPHA_MAX) is still above the target
                break
            new = ALPHA_MAX
        if new == alpha or (np.isfinite(hi) and hi - lo <= ALPHA_RESOLVED * hi):
            # The bracket cannot shrink further: alpha is the root to double precision (unless the
            # last impact ended in another end state than the target's).
            if not onset and not _target_of(best, kinematic)[2]:
                status = OK
            break
        alpha = new
    out[SOL_ALPHA] = alpha
    out[SOL_EPS] = np.sqrt(max(best[OUT_EPS2], 0.0)) if best[OUT_STATUS] == OK else np.nan
    out[SOL_E_N] = best[OUT_E_N] if best[OUT_STATUS] == OK else np.nan
    out[SOL_STATE] = best[OUT_STATE]
    out[SOL_STATUS] = status
    out[SOL_IMPACTS] = impacts
    out[SOL_STEPS] = steps
    out[SOL_X_MAX] = best[OUT_X_MAX]
    out[SOL_X_END] = best[OUT_X_END]
    out[SOL_NFEV] = nfev
    return out


@njit(cache=True, error_model="numpy")
def initial_guess(eps, A):
    """Starting alpha: the exact unloaded value, bounded for the eps = 0 onset search."""
    if eps <= 0.0:
        return 1.0 / max(A, 1e-6)
    return max(alpha_exact_scalar(eps), 1e-8)


@njit(cache=True, error_model="numpy")
def solve_point(eps_t, A, xi, tol, rtol, atol, max_steps, use_exact, use_table, tb, kinematic, tk):
    """Solve one point: exact relation at ``A = 0`` (unless ``use_exact`` is False), else Newton.

    ``eps_t`` is Stronge's eps, or Newton's e_N when ``kinematic`` (then it must be > 0
    unless ``A = 0``: e_N = 0 holds on a whole range of alpha, reported as no bracket).
    ``tb`` holds the energetic table's arrays (``table.ARRAY_NAMES``), ``tk`` the
    kinematic table's (``table.KINEMATIC_ARRAY_NAMES``), used for the starting guess
    when ``use_table`` is True and the point is inside the table's domain.
    """
    if eps_t >= 1.0:
        out = np.full(N_SOLVE_OUT, np.nan)
        res, _ = impact_kernel(0.0, A, rtol, atol, max_steps, np.empty((0, N_REC)), np.inf)
        out[SOL_ALPHA] = 0.0
        out[SOL_EPS] = np.sqrt(max(res[OUT_EPS2], 0.0))
        out[SOL_E_N] = res[OUT_E_N]
        out[SOL_STATE] = res[OUT_STATE]
        out[SOL_STATUS] = res[OUT_STATUS]
        out[SOL_IMPACTS] = 1
        out[SOL_STEPS] = res[OUT_STEPS]
        out[SOL_X_MAX] = res[OUT_X_MAX]
        out[SOL_X_END] = res[OUT_X_END]
        out[SOL_NFEV] = res[OUT_NFEV]
        return out
    if (A == 0.0 and use_exact) or (kinematic and eps_t <= 0.0):
        out = np.full(N_SOLVE_OUT, np.nan)
        out[SOL_STATE] = FAILED  # unless a root exists
        out[SOL_STATUS] = NO_BRACKET
        out[SOL_IMPACTS] = 0.0
        out[SOL_STEPS] = 0.0
        out[SOL_NFEV] = 0.0
        if eps_t > 0.0:
            # Without a load e_N = eps (the energy identity with A = 0).
            alpha = alpha_exact_scalar(eps_t)
            out[SOL_ALPHA] = alpha
            out[SOL_EPS] = eps_t
            out[SOL_E_N] = eps_t
            out[SOL_STATE] = SEPARATION
            out[SOL_STATUS] = OK
            out[SOL_X_MAX] = max_compression_exact(alpha)
            out[SOL_X_END] = 0.0
        return out
    in_table = use_table and eps_t >= EPS_MIN and xi <= XI_MAX
    if in_table and kinematic:
        guess = kinematic_alpha_from_table(eps_t, xi, tk[0], tk[1], tk[2], tk[3])
    elif in_table:
        guess = alpha_from_table(eps_t, xi, tb[0], tb[1], tb[2], tb[3], tb[4], tb[5], tb[6], tb[7], tb[8])
    else:
        guess = initial_guess(eps_t, A)
    return solve_kernel(eps_t, A, guess, tol, rtol, atol, max_steps, kinematic)


@njit(cache=True, nogil=True, error_model="numpy")
def solve_rows(eps, A, xi, tol, rtol, atol, max_steps, use_exact, use_table, tb, kinematic, tk, out, i0, i1):
    """Rows ``i0 .. i1 - 1`` of ``solve_many``'s table, written into ``out``."""
    for i in range(i0, i1):
        row = solve_point(
            eps[i], A[i], xi[i], tol, rtol, atol, max_steps, use_exact, use_table, tb, kinematic, tk
        )
        for j in range(N_SOLVE_OUT):  # not ``out[i] = row``: see ``driver.impact_rows``
            out[i, j] = row[j]


def solve_many(eps, A, xi, tol, rtol, atol, max_steps, use_exact, use_table, tb, kinematic, tk, threads=None):
    """``solve_point`` over flat arrays; returns shape (n, N_SOLVE_OUT).

    Inputs shorter than ``PARALLEL_MIN`` run in this thread; longer ones in
    ``threads.thread_count()`` threads (or ``threads``).  Same bits either way.
    """
    out = np.empty((eps.size, N_SOLVE_OUT))
    if eps.size < PARALLEL_MIN:
        threads = 1
    args = (eps, A, xi, tol, rtol, atol, max_steps, use_exact, use_table, tb, kinematic, tk, out)
    run_rows(solve_rows, eps.size, *args, threads=threads)
    return out


_NO_TABLE = (
    (np.empty(0),) * 4 + (np.empty((0, 0)),) + (np.empty(0),) * 2 + (np.empty((0, 0)), np.empty(0)),
    (np.empty(0), np.empty(0), np.empty((0, 0)), np.empty(0)),
)


def _guess_arrays(use_table, kinematic):
    """``(found, energetic arrays, kinematic arrays)`` for the starting guess.

    Only the table of the definition being solved for is read; the other is replaced by empty
    stand-ins.  A table that is missing or cannot be read raises (naming the file): the
    formula guess is asked for with ``guess="formula"``, never taken silently.
    """
    tb, tk = _NO_TABLE
    if not use_table:
        return False, tb, tk
    from .table import kinematic_table_arrays, table_arrays

    try:
        if kinematic:
            return True, tb, kinematic_table_arrays()
        return True, table_arrays(), tk
    except (FileNotFoundError, ValueError) as err:
        raise type(err)(
            f"solve_alpha: guess='table' needs the shipped table: {err}; "
            "reinstall the package, or pass guess='formula'"
        ) from None


@dataclass(frozen=True)
class AlphaSolution:
    """Result of ``solve_alpha`` (arrays shaped like the broadcast inputs).

    Attributes
    ----------
    alpha : damping factor; NaN where ``status`` is not "ok".
    eps_reached : Stronge's energetic epsilon that ``alpha`` actually produces.
    state : end state of the impact at ``alpha``.
    status : "ok" or why the root-finder stopped.
    impacts : impacts integrated for this point (0 on the exact xi = 0 path).
    steps, nfev : integrator steps and right-hand-side evaluations, all impacts.
    x_max, x_end : maximum compression and end compression at ``alpha`` (scaled).
    e_n_reached : Newton's kinematic e_N that ``alpha`` produces (0 without separation).
    """

    alpha: FloatOrArray
    eps_reached: FloatOrArray
    state: str | np.ndarray
    status: str | np.ndarray
    impacts: int | np.ndarray
    steps: int | np.ndarray
    nfev: int | np.ndarray
    x_max: FloatOrArray
    x_end: FloatOrArray
    e_n_reached: FloatOrArray

    @property
    def ok(self):
        """True where a root was found to tolerance."""
        return np.asarray(self.status) == "ok"


def no_kinematic_inverse(name="e_N"):
    """The error for a kinematic target of 0, which many alpha produce."""
    return ValueError(
        f"{name} = 0.0 has no kinematic inverse: every alpha from the separation boundary's "
        "alpha_b(xi) upwards ends without separation, so e_N = 0 for all of them; as e_N -> 0+ "
        "alpha tends to alpha_b(xi) (see separation_boundary). Valid: e_N in (0, 1]"
    )


def _check_targets(eps, xi, kinematic, exact_at_zero):
    """Validated, broadcast targets; the kinematic target 0 and eps = 0 at xi = 0 raise."""
    if kinematic:
        eps = check_range("e_N", eps, 0.0, 1.0)
        if np.any(eps == 0.0):
            raise no_kinematic_inverse()
    else:
        eps = check_eps(eps)
    xi = check_xi(xi)
    eps, xi = np.broadcast_arrays(eps, xi)
    if exact_at_zero and np.any((eps == 0.0) & (xi == 0.0)):
        raise ValueError(
            "eps = 0.0 at xi = 0.0 cannot be reached: without a load alpha -> infinity; "
            "valid: eps in (0, 1] when xi = 0, eps in [0, 1] when 0 < xi < 1"
        )
    return eps, xi


def _check_guess(guess):
    if guess not in ("table", "formula"):
        raise ValueError(f"guess = {guess!r} is not one of 'table', 'formula'")


def solve_table(
    eps,
    xi,
    *,
    tol=EPS_TOL,
    rtol=RTOL,
    atol=ATOL,
    max_steps=MAX_STEPS,
    exact_at_zero=True,
    guess="table",
    restitution="energetic",
):
    """Validated flat solve: returns the raw ``(n, N_SOLVE_OUT)`` table and the broadcast shape."""
    kinematic = check_restitution(restitution) == "kinematic"
    exact_at_zero = check_flag("exact_at_zero", exact_at_zero)
    eps, xi = _check_targets(eps, xi, kinematic, exact_at_zero)
    rtol, atol = check_tolerances(rtol, atol)
    max_steps = check_max_steps(max_steps)
    tol = float(check_range("tol", tol, 0.0, TOL_MAX, lo_open=True))
    _check_guess(guess)
    use_table, tb, tk = _guess_arrays(guess == "table", kinematic)
    A = scaled_load(xi)
    table = solve_many(
        flat_owned(eps),
        flat_owned(A),
        flat_owned(xi),
        tol,
        rtol,
        atol,
        max_steps,
        bool(exact_at_zero),
        use_table,
        tb,
        kinematic,
        tk,
    )
    return table, eps.shape


def _scalar_solution(row):
    """``AlphaSolution`` of one solver row as Python scalars (the scalar fast path, same numbers)."""
    status = int(row[SOL_STATUS])
    state = row[SOL_STATE]
    return AlphaSolution(
        alpha=float(row[SOL_ALPHA]) if status == OK else math.nan,
        eps_reached=float(row[SOL_EPS]),
        state=END_STATES[int(state) if state == state else FAILED],
        status=STATUS[status],
        impacts=int(row[SOL_IMPACTS]),
        steps=int(row[SOL_STEPS]),
        nfev=int(row[SOL_NFEV]),
        x_max=float(row[SOL_X_MAX]),
        x_end=float(row[SOL_X_END]),
        e_n_reached=float(row[SOL_E_N]),
    )


def solve_alpha(
    eps: RealLike,
    xi: RealLike,
    *,
    tol: float = EPS_TOL,
    rtol: float = RTOL,
    atol: float = ATOL,
    max_steps: int = MAX_STEPS,
    exact_at_zero: bool = True,
    guess: str = "table",
    restitution: str = "energetic",
) -> "AlphaSolution":
    """Damping factor alpha that makes the loaded impact restitute with ``eps``.

    Parameters
    ----------
    eps : float or array_like
        Target restitution coefficient, in the definition ``restitution`` names.
        Energetic (Stronge's eps): 0 <= eps <= 1; ``eps = 0`` (only for ``xi > 0``)
        returns the onset alpha where restitution stops.  Kinematic (Newton's e_N,
        separation speed / approach speed): 0 < e_N <= 1; e_N = 0 has no inverse
        (every alpha from the separation boundary up gives it) and raises.
    xi : float or array_like
        Influence factor of the load, 0 <= xi < 1; broadcast against ``eps``.
    tol : float
        Absolute tolerance on the restitution reached.
    rtol, atol, max_steps
        Integrator settings, as in ``impact``.
    exact_at_zero : bool
        Use the exact relation at ``xi = 0`` (default); False integrates there too.
    guess : {"table", "formula"}
        Starting guess: the shipped exact table of the chosen definition (fewest
        impacts), or the exact unloaded alpha (independent of any data file; used to
        build the tables).
    restitution : {"energetic", "kinematic"}
        Which coefficient ``eps`` is.

    Returns
    -------
    AlphaSolution
        Both coefficients reached (``eps_reached``, ``e_n_reached``); points that failed
        carry NaN alpha and say why in ``status``.  Python scalars for scalar input.
    """
    if (
        guess == "table"
        and plain_in("eps", eps)
        and eps > 0.0
        and plain_in("xi", xi)
        and plain_integrator_settings(rtol, atol, max_steps)
        and type(tol) in PLAIN_FLOATS
        and 0.0 < tol <= TOL_MAX
        and type(exact_at_zero) is bool
        and restitution in RESTITUTIONS
    ):
        kinematic = restitution == "kinematic"
        use_table, tb, tk = _guess_arrays(True, kinematic)
        A = scaled_load_unchecked(xi)
        row = solve_point(eps, A, xi, tol, rtol, atol, max_steps, exact_at_zero, use_table, tb, kinematic, tk)
        return _scalar_solution(row)
    table, shape = solve_table(
        eps,
        xi,
        tol=tol,
        rtol=rtol,
        atol=atol,
        max_steps=max_steps,
        exact_at_zero=exact_at_zero,
        guess=guess,
        restitution=restitution,
    )
    status = table[:, SOL_STATUS].astype(int)
    alpha = np.where(status == OK, table[:, SOL_ALPHA], np.nan)
    state = np.nan_to_num(table[:, SOL_STATE], nan=float(FAILED)).astype(int)

    def shaped(a):
        a = np.asarray(a).reshape(shape)
        return a[()] if a.ndim == 0 else a

    return AlphaSolution(
        alpha=shaped(alpha),
        eps_reached=shaped(table[:, SOL_EPS]),
        state=shaped(np.array([END_STATES[c] for c in state], dtype=object)),
        status=shaped(np.array([STATUS[c] for c in status], dtype=object)),
        impacts=shaped(table[:, SOL_IMPACTS].astype(np.int64)),
        steps=shaped(table[:, SOL_STEPS].astype(np.int64)),
        nfev=shaped(table[:, SOL_NFEV].astype(np.int64)),
        x_max=shaped(table[:, SOL_X_MAX]),
        x_end=shaped(table[:, SOL_X_END]),
        e_n_reached=shaped(table[:, SOL_E_N]),
    )
