"""The jitted driver for one impact: phases, events, end states, Stronge's epsilon.

Stronge's energetic coefficient (paper Eq. 17) is evaluated from the energy
identity of the scaled equation (docs/science.md, "The restitution identity"), exact for the ODE:

    eps^2 = (v_e^2 / 2 + A (x_m - x_e)) / (1/2 + A x_m).

Next to the onset of no restitution ``x_m - x_e`` is a tiny difference of two
compressions close to ``x_eq`` (~ eps^2 x_eq).  The kernel therefore carries
the restitution phase's displacement from the maximum compression, ``drop =
x_m - x_e``, measured from ``x_eq`` where the linearised end gives both sides
(``u_m - u_e``), so that eps^2 keeps its relative accuracy instead of the
rounding of ``x_eq + u`` (1e-16 x_eq absolute).

Its derivative with respect to alpha comes from the sensitivities ``p, q``
integrated along the trajectory, so a Newton step costs no extra impact.
Newton's kinematic coefficient ``e_N = -v_e`` (separation speed over approach
speed, 0 when the impact ends without separation) and its alpha-derivative
are reported beside it.
"""

import numpy as np
from numba import njit

from .codes import (
    CREEP,
    EVENT_FAILED,
    FAILED,
    N_OUT,
    NO_RESTITUTION,
    NON_FINITE,
    NONSEPARATION,
    OK,
    OUT_DE_N,
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
    REC_T,
    REC_V,
    REC_X,
    SEPARATION,
    STEP_LIMIT,
    STEP_UNDERFLOW,
)
from .events import (
    MIN_REL_STEP,
    equilibrium,
    in_linear_zone,
    linear_constants,
    linear_turn,
    locate,
    trapped_above,
    trapped_below,
)
from .rk import (
    MODE_SQRT_X,
    MODE_TIME,
    N_STAGES,
    N_STATE,
    contact_acceleration,
    dop853_step,
    error_norm,
    rhs,
    step_factor,
)

# First trial step in scaled time.  Small, because x^{3/2} is not smooth at
# t = 0 and the embedded error estimate is unreliable across that point.
FIRST_STEP = 1e-4


@njit(cache=True, error_model="numpy")
def stronge(A, x_m, drop, v_e, dxm, dxe, dve):
    """Return ``(eps^2, d eps^2 / d alpha)`` from the end state and its sensitivities.

    ``drop = x_m - x_e`` is the restitution phase's displacement, computed by the caller
    without cancellation.
    """
    wc = 0.5 + A * x_m
    wr = 0.5 * v_e * v_e + A * drop
    e2 = wr / wc
    de2 = ((v_e * dve + A * (dxm - dxe)) * wc - wr * A * dxm) / (wc * wc)
    return e2, de2


@njit(cache=True, error_model="numpy")
def _copy(src, dst):
    for i in range(N_STATE):
        dst[i] = src[i]


@njit(cache=True, error_model="numpy")
def impact_kernel(alpha, A, rtol, atol, max_steps, record, max_step):
    """Integrate one impact of the scaled Eq. 24 from ``x = 0, v = 1``.

    Parameters
    ----------
    alpha, A : float
        Damping factor and scaled load (both >= 0; validated by the caller).
    rtol, atol : float
        Tolerances of the step-size controller on ``t``, ``x`` and ``v``.
    max_steps : int
        Limit on accepted plus rejected steps, events included.
    record : ndarray, shape (n, 3)
        Buffer for ``(t, x, v)`` at every accepted step; ``n = 0`` records nothing.
    max_step : float
        Cap on the time step, for dense trajectories (figures, quadratures); ``np.inf`` for
        none.  No default: an omitted argument has its own type in numba, and every caller
        that left it out compiled a second copy of this kernel (2 s of CPU).

    Returns
    -------
    out : ndarray, shape (N_OUT,)
        ``eps2, deps2, state, status, x_m, x_e, v_e, t_m, t_e, steps, nfev, e_N, de_N`` in
        the slots ``codes.OUT_*``; the number of recorded rows is returned separately.
    n_rec : int
    """
    K = np.empty((N_STAGES + 1, N_STATE))
    y = np.zeros(N_STATE)
    y_new = np.empty(N_STATE)
    ytmp = np.empty(N_STATE)
    y_start = np.empty(N_STATE)
    y[2] = 1.0
    n_rec = 0
    if record.shape[0] > 0:
        record[0, REC_T] = 0.0
        record[0, REC_X] = 0.0
        record[0, REC_V] = 1.0
        n_rec = 1
    xeq = equilibrium(A) if A > 0.0 else np.inf
    state = FAILED
    status = OK
    x_m = np.nan
    u_m = np.nan  # x_m - x_eq, kept apart from x_m (see the module docstring)
    drop = np.nan  # x_m - x_e
    dxm = 0.0
    t_m = np.nan
    x_e = np.nan
    v_e = np.nan
    t_e = np.nan
    dxe = 0.0
    dve = 0.0
    compressing = True
    steps = 0
    nfev = 1
    h = FIRST_STEP
    rejected: np.bool_ = np.bool_(False)
    rhs(y, A, alpha, np.int64(MODE_TIME), K[0])
    while state == FAILED:
        if steps >= max_steps:
            status = STEP_LIMIT
            break
        h = min(h, max_step)
        dop853_step(y, h, A, alpha, np.int64(MODE_TIME), K, y_new, ytmp)
        nfev += N_STAGES
        steps += 1
        err = error_norm(K, h, y, y_new, rtol, atol)
        if err > 1.0:
            h *= step_factor(err, np.bool_(True))
            rejected = np.bool_(True)
            if h < MIN_REL_STEP * (1.0 + y[0]):
                status = STEP_UNDERFLOW if np.isfinite(err) else NON_FINITE
                break
            continue
        # Which event, if any, did this step cross?  An event is only placed
        # from a step whose start already moves towards it; otherwise the
        # step is shortened so that the crossing becomes monotone.
        k: int | np.int64 = -1
        if compressing:
            if y_new[2] <= 0.0:
                k = 2
        elif y_new[1] <= 0.0:
            k = 1
        elif y_new[2] > 0.0:
            k = 2
        if k >= 0:
            if K[0, k] * y[k] >= 0.0:
                h *= 0.5
                rejected = np.bool_(True)
                continue
            if k == 1:
                # Separation: integrate in w = sqrt(x), where the Hertz force is smooth.
                k = MODE_SQRT_X
                y[5] = np.sqrt(y[1])
            _copy(y, y_start)
            st, ls, lf = locate(y, k, A, alpha, rtol, atol, max_steps - steps, K, y_new, ytmp)
            steps += ls
            nfev += lf
            if st == OK and k == 2 and not compressing and y[1] < 0.0:
                # A grazing exit: within one step x passed 0 (the load alone then turns v) and
                # v turned below x = 0.  The bodies separated first, with a small speed.
                _copy(y_start, y)
                k = np.int64(MODE_SQRT_X)
                y[5] = np.sqrt(y[1])
                st, ls, lf = locate(y, k, A, alpha, rtol, atol, max_steps - steps, K, y_new, ytmp)
                steps += ls
                nfev += lf
            if st != OK:
                status = EVENT_FAILED if st == STEP_UNDERFLOW else st
                break
            if record.shape[0] > n_rec:
                record[n_rec, REC_T] = y[0]
                record[n_rec, REC_X] = y[1]
                record[n_rec, REC_V] = y[2]
                n_rec += 1
            if compressing:
                compressing = False
                x_m = y[1]
                u_m = x_m - xeq
                dxm = y[3]
                t_m = y[0]
                y[2] = 0.0
                rhs(y, A, alpha, np.int64(MODE_TIME), K[0])
                continue
            t_e = y[0]
            if k == MODE_SQRT_X:
                state = SEPARATION
                y[1] = 0.0
                x_e = 0.0
                drop = x_m
                v_e = y[2]
                acc = contact_acceleration(0.0, v_e, A, alpha)
                dxe = 0.0
                dve = y[4] - acc * y[3] / v_e
            else:
                state = NONSEPARATION
                x_e = y[1]
                drop = x_m - x_e
                v_e = 0.0
                dxe = y[3]
                dve = 0.0
            break
        _copy(y_new, y)
        for i in range(N_STATE):
            K[0, i] = K[N_STAGES, i]
        if record.shape[0] > n_rec:
            record[n_rec, REC_T] = y[0]
            record[n_rec, REC_X] = y[1]
            record[n_rec, REC_V] = y[2]
            n_rec += 1
        # The two end states reached only as t -> inf: their limits are set after the loop.
        if in_linear_zone(y[1], y[2], A, alpha):
            kl, cl = linear_constants(A, alpha)
            turns, u_turn = linear_turn(y[1] - xeq, y[2], kl, cl)
            if compressing:
                if not turns:
                    state = NO_RESTITUTION
                    break
                x_m = xeq + u_turn
                u_m = u_turn
                dxm = y[3]
                t_m = np.nan
                turns, u_turn = linear_turn(u_turn, 0.0, kl, cl)
            if turns:
                state = NONSEPARATION
                x_e = xeq + u_turn
                drop = u_m - u_turn
                v_e = 0.0
                t_e = np.inf
                dxe = y[3]
            else:
                state = CREEP
            break
        if compressing:
            if trapped_below(y[1], y[2], A, alpha):
                state = NO_RESTITUTION
                break
        elif trapped_above(y[1], y[2], A, alpha):
            state = CREEP
            break
        h *= step_factor(err, rejected)
        rejected = np.bool_(False)
    if state == NO_RESTITUTION:
        x_m = xeq
        t_m = np.inf
    if state == CREEP:
        drop = u_m
    if state == NO_RESTITUTION or state == CREEP:
        x_e = xeq
        v_e = 0.0
        t_e = np.inf
    out = np.full(N_OUT, np.nan)
    if state != FAILED:
        if state == NO_RESTITUTION:
            out[OUT_EPS2] = 0.0
            out[OUT_DEPS2] = 0.0
        else:
            e2, de2 = stronge(A, x_m, drop, v_e, dxm, dxe, dve)
            out[OUT_EPS2] = e2
            out[OUT_DEPS2] = de2
    out[OUT_STATE] = state
    out[OUT_STATUS] = status
    out[OUT_X_MAX] = x_m
    out[OUT_X_END] = x_e
    out[OUT_V_END] = v_e
    out[OUT_T_MAX] = t_m
    out[OUT_T_END] = t_e
    out[OUT_STEPS] = steps
    out[OUT_NFEV] = nfev
    if state == SEPARATION:
        out[OUT_E_N] = -v_e  # v_e < 0: the bodies move apart
        out[OUT_DE_N] = -dve
    elif state != FAILED:
        out[OUT_E_N] = 0.0
        out[OUT_DE_N] = 0.0
    return out, n_rec
