"""Right-hand side, one DOP853 step, error norm and step-size control.

The scaled impact equation (docs/science.md, "Scaling"; paper Eq. 24 after scaling) is

    x'' = A - (5/4) x^{3/2} (1 + alpha x'),   x(0) = 0,  x'(0) = 1.

The state vector is ``y = (t, x, v, p, q, w)`` with ``v = x'``, the
sensitivities ``p = dx/dalpha``, ``q = dv/dalpha`` and ``w = sqrt(x)``.  Any
of ``t``, ``x``, ``v`` or ``w`` can serve as the independent variable ``s``
(``mode`` 0, 1, 2 or 5): then ``dy/ds = f(y) / f_mode(y)``.  Changing the
independent variable to the event function is how events are placed to full
step accuracy (Henon's trick, M. Henon, Physica D 5, 1982).  ``w`` is only
tracked in mode 5, used near ``x = 0``: there ``x^{3/2} = w^3`` is smooth in
``w``, whereas it is not smooth in ``x`` or ``t``, which spoils the error
estimate of the step that ends the impact.

Notation for the Butcher tableau follows Hairer, Norsett & Wanner (1993);
the step and its error estimate follow SciPy's ``DOP853``.
"""

import numpy as np
from numba import njit

from .tableau import E3 as RK_E3
from .tableau import E5 as RK_E5
from .tableau import ERROR_ESTIMATOR_ORDER, N_STAGES
from .tableau import A as RK_A
from .tableau import B as RK_B

# Number of state components: t, x, v, dx/dalpha, dv/dalpha, sqrt(x).
N_STATE = 6
# Mode whose independent variable is time; the mode whose independent variable is w = sqrt(x).
MODE_TIME = 0
MODE_SQRT_X = 5
# Components that enter the error norm: t, x and v (the sensitivities only
# steer Newton's method, so they must not change the step sequence).
N_CONTROLLED = 3
# Step-size controller constants, as in SciPy's explicit RK solvers.
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ERROR_EXPONENT = -1.0 / (ERROR_ESTIMATOR_ORDER + 1)
# Hertz stiffness of the scaled equation: (5/4) x^{3/2}.
HERTZ = 1.25


@njit(cache=True, error_model="numpy")
def contact_acceleration(x, v, A, alpha):
    """Scaled acceleration ``x''`` of Eq. 24; no contact force for ``x < 0``."""
    xp = max(x, 0.0)
    return A - HERTZ * xp * np.sqrt(xp) * (1.0 + alpha * v)


@njit(cache=True, error_model="numpy")
def rhs(y, A, alpha, mode, out):
    """Write ``dy/ds`` into ``out``, with ``s = y[mode]`` the independent variable.

    Parameters
    ----------
    y : ndarray, shape (6,)
        State ``(t, x, v, p, q, w)``.
    A : float
        Scaled external load, ``A = xi (1 - xi)^(-3/5) / 2``.
    alpha : float
        Hysteresis damping factor.
    mode : int
        0 for time, 1 for ``x``, 2 for ``v``, 5 for ``w = sqrt(x)`` as the
        independent variable.  Callers pass it as a run-time ``int64``
        (``np.int64(MODE_TIME)``, never a bare constant): numba compiles a separate
        copy of a jitted callee for each literal constant it is given, which tripled
        the compile of this function, ``dop853_step`` and ``events.locate``.
    out : ndarray, shape (6,)
        Output buffer.
    """
    x = y[1]
    v = y[2]
    if mode == MODE_SQRT_X:
        rx = max(y[5], 0.0)
        xp = rx * rx
    else:
        xp = max(x, 0.0)
        rx = np.sqrt(xp)
    damp = 1.0 + alpha * v
    out[0] = 1.0
    out[1] = v
    out[2] = A - HERTZ * xp * rx * damp
    out[3] = y[4]
    out[4] = -HERTZ * (1.5 * rx * y[3] * damp + xp * rx * (v + alpha * y[4]))
    out[5] = 0.0
    if mode == MODE_SQRT_X:
        # dw/dt = v / (2 w); multiply rather than divide so that w = 0 is regular.
        g = 2.0 * rx / v
        for i in range(N_STATE):
            out[i] *= g
        out[5] = 1.0
    elif mode != 0:
        d = out[mode]
        for i in range(N_STATE):
            out[i] /= d


@njit(cache=True, error_model="numpy")
def dop853_step(y, h, A, alpha, mode, K, y_new, ytmp):
    """Take one DOP853 step of size ``h``; fill stages ``K`` and ``y_new``.

    ``K[0]`` must hold ``dy/ds`` at ``y`` on entry (first-same-as-last);
    on return ``K[N_STAGES]`` holds ``dy/ds`` at ``y_new``.
    """
    for s in range(1, N_STAGES):
        for i in range(N_STATE):
            acc = 0.0
            for j in range(s):
                acc += RK_A[s, j] * K[j, i]
            ytmp[i] = y[i] + h * acc
        rhs(ytmp, A, alpha, mode, K[s])
    for i in range(N_STATE):
        acc = 0.0
        for j in range(N_STAGES):
            acc += RK_B[j] * K[j, i]
        y_new[i] = y[i] + h * acc
    rhs(y_new, A, alpha, mode, K[N_STAGES])


@njit(cache=True, error_model="numpy")
def error_norm(K, h, y, y_new, rtol, atol):
    """Scaled RMS error of the step, blending the 5th- and 3rd-order estimates.

    Returns ``inf`` when the step produced a non-finite value, so the caller
    rejects it rather than accepting garbage.
    """
    e5 = 0.0
    e3 = 0.0
    for i in range(N_CONTROLLED):
        sc = atol + rtol * max(abs(y[i]), abs(y_new[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(N_STAGES + 1):
            a5 += RK_E5[j] * K[j, i]
            a3 += RK_E3[j] * K[j, i]
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if not (np.isfinite(e5) and np.isfinite(e3)):
        return np.inf
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / np.sqrt((e5 + 0.01 * e3) * N_CONTROLLED)


@njit(cache=True, error_model="numpy")
def step_factor(err, rejected):
    """Factor for the next step size from the error norm of this one.

    The one accept/reject rule of the engine: ``kernel.impact_kernel`` (in time) and
    ``events.locate`` (in the event variable) both accept a step when ``error_norm <= 1`` and
    size the next one with this factor.  Their loops stay separate on purpose: the kernel
    counts every attempted step against ``max_steps``, halves steps whose crossing is not
    monotone and caps ``h`` at ``max_step``, while the locator counts accepted steps, clips
    ``h`` to the distance left to the event and has its own underflow floor.  A single loop
    would have to change one of those counts, and with it the ``steps`` every result reports.
    """
    if not np.isfinite(err):
        return MIN_FACTOR
    if err == 0.0:
        return 1.0 if rejected else MAX_FACTOR
    f = SAFETY * err**ERROR_EXPONENT
    if err > 1.0:
        return max(MIN_FACTOR, f)
    f = min(MAX_FACTOR, f)
    return min(1.0, f) if rejected else f
