"""Validated, broadcasting forward map and exact inverse of any registered law."""

from dataclasses import dataclass

import numpy as np

from contactalpha.engine.codes import END_STATES, NOT_CONVERGED, OK, STATUS
from contactalpha.validation import check_max_steps, check_range, check_tolerances

from .domain import check_restitution
from .integrate import ATOL, RTOL


@dataclass(frozen=True)
class LawImpact:
    """One impact of a law (arrays for array input).

    Attributes
    ----------
    eps : Stronge's energetic restitution, from the energy identity; NaN if the run failed.
    e_n : Newton's kinematic restitution, separation speed / approach speed; 0 without separation.
    state : end state: separation, nonseparation (capture), creep, no_restitution, failed.
    status : "ok" or why the integrator stopped.
    x_max, x_end, v_end : scaled maximum compression and end state.
    t_end : scaled duration of the contact (inf when it creeps to rest).
    """

    eps: object
    e_n: object
    state: object
    status: object
    x_max: object
    x_end: object
    v_end: object
    t_end: object

    @property
    def ok(self):
        """True where the integrator finished."""
        return np.asarray(self.status) == "ok"


@dataclass(frozen=True)
class DampingSolution:
    """The damping that meets a target restitution, and what it delivers.

    Attributes
    ----------
    damping : the law's dimensionless damping ``p``; NaN where the solve failed.
    eps, e_n : both restitutions the damping delivers (reference integrator).
    state : end state at that damping.
    status : "ok" or why the solve failed.
    """

    damping: object
    eps: object
    e_n: object
    state: object
    status: object

    @property
    def ok(self):
        """True where the solve met its target."""
        return np.asarray(self.status) == "ok"


def _shaped(a, shape):
    a = np.asarray(a).reshape(shape)
    return a[()] if a.ndim == 0 else a


def _words(codes, names):
    return np.array([names[int(c)] if c == c else "failed" for c in codes], dtype=object)


def check_load_factor(law, xi):
    """Load factor ``xi`` inside the law's domain [0, 1)."""
    return check_range("xi", xi, 0.0, 1.0, hi_open=True)


# The integrator settings a law's maps take, and their defaults.
SETTINGS = ("rtol", "atol", "max_steps")


def check_settings(law, settings):
    """The integrator ``settings`` (rtol, atol, max_steps) checked by name, as the default law checks them.

    Every backend takes them checked: a negative tolerance or a text would otherwise reach the
    compiled integrator (a wrong number with status ok, or a typing error).
    """
    unknown = sorted(set(settings) - set(SETTINGS))
    if unknown:
        raise ValueError(f"unknown settings {unknown} of law {law.name!r}; valid: {', '.join(SETTINGS)}")
    checked = dict(settings)
    if "rtol" in checked or "atol" in checked:
        checked["rtol"], checked["atol"] = check_tolerances(
            checked.get("rtol", RTOL), checked.get("atol", ATOL)
        )
    if "max_steps" in checked:
        checked["max_steps"] = check_max_steps(checked["max_steps"])
    return checked


def impact(law, p, xi, **settings):
    """Both restitutions and the end state at damping ``p`` and load factor ``xi`` (broadcast)."""
    settings = check_settings(law, settings)
    pp = check_range(law.damping, p, 0.0, np.inf, hi_open=True)
    return impact_unchecked(law, pp, check_load_factor(law, xi), settings)


def impact_unchecked(law, p, xi, settings=None):
    """``impact`` of a damping, a load factor and settings already checked: for the inner layers."""
    settings = {} if settings is None else settings
    pp, xx = np.broadcast_arrays(np.asarray(p, dtype=float), np.asarray(xi, dtype=float))
    shape = pp.shape
    pf = np.ascontiguousarray(pp, dtype=float).ravel()
    xf = np.ascontiguousarray(xx, dtype=float).ravel()
    A = np.atleast_1d(law.scaled_load_unchecked(xf)).astype(float)
    rows = law.backend.impact(law, pf, A, xf, **settings)
    return LawImpact(
        eps=_shaped(rows[:, 0], shape),
        e_n=_shaped(rows[:, 1], shape),
        state=_shaped(_words(rows[:, 2], END_STATES), shape),
        status=_shaped(_words(rows[:, 3], STATUS), shape),
        x_max=_shaped(rows[:, 4], shape),
        x_end=_shaped(rows[:, 5], shape),
        v_end=_shaped(rows[:, 6], shape),
        t_end=_shaped(rows[:, 7], shape),
    )


def check_target(law, target, restitution):
    """Target restitution in (0, 1]: e = 0 has no unique damping (every p past a boundary gives it)."""
    kind = check_restitution(restitution)
    name = "eps" if kind == "energetic" else "e_N"
    return check_range(name, target, 0.0, 1.0, lo_open=True)


# The largest miss of a solved damping's restitution, through the integrator, per unit of its rtol
# (1e-8 at the default rtol): past it the root finder accepted a bracket across a jump of the
# integrator's e(p), or one shrunk to nothing at loads far past the tables' (xi -> 1).
DELIVERED_PER_RTOL = 1e4


def _check_delivered(law, p, status, rows, target, kinematic, A, xi, tol, settings):
    """Where the delivered restitution misses ``target`` by more than ``tol``, redo the row (in place).

    The closed form's root (piecewise-linear laws) if the integrator confirms it, else NaN with status
    NOT_CONVERGED.
    """
    col = 1 if kinematic else 0
    bad = np.flatnonzero((status == OK) & ~(np.abs(rows[:, col] - target) <= tol))
    exact = getattr(law.fast, "exact_inverse", None)
    if bad.size and exact is not None:
        root, st = exact.damping(law, target[bad], kinematic, A[bad], xi[bad])
        again = law.backend.impact(law, np.nan_to_num(root), A[bad], xi[bad], **settings)
        fixed = (st == OK) & (np.abs(again[:, col] - target[bad]) <= tol)
        p[bad[fixed]], rows[bad[fixed]] = root[fixed], again[fixed]
        bad = bad[~fixed]
    p[bad], status[bad] = np.nan, NOT_CONVERGED


def damping_for(law, target, xi, restitution="energetic", **settings):
    """Exact inverse: the damping ``p`` whose impact restitutes ``target`` at load factor ``xi``.

    Returns
    -------
    DampingSolution
        ``damping`` and what it delivers (both restitutions, end state), broadcast shape.
    """
    settings = check_settings(law, settings)
    tt = check_target(law, target, restitution)
    return damping_for_unchecked(law, tt, check_load_factor(law, xi), restitution, settings)


def damping_for_unchecked(law, target, xi, restitution, settings=None):
    """``damping_for`` of a target, a load factor and settings already checked: for the inner layers."""
    settings = {} if settings is None else settings
    tt, xx = np.broadcast_arrays(np.asarray(target, dtype=float), np.asarray(xi, dtype=float))
    shape = tt.shape
    tf = np.ascontiguousarray(tt, dtype=float).ravel()
    xf = np.ascontiguousarray(xx, dtype=float).ravel()
    A = np.atleast_1d(law.scaled_load_unchecked(xf)).astype(float)
    kinematic = restitution == "kinematic"
    p, status = law.backend.damping(law, tf, kinematic, A, xf, **settings)
    p = np.where(status == OK, p, np.nan)
    rows = law.backend.impact(law, np.nan_to_num(p), A, xf, **settings)
    tol = DELIVERED_PER_RTOL * settings.get("rtol", RTOL)
    _check_delivered(law, p, status, rows, tf, kinematic, A, xf, tol, settings)
    return DampingSolution(
        damping=_shaped(p, shape),
        eps=_shaped(np.where(status == OK, rows[:, 0], np.nan), shape),
        e_n=_shaped(np.where(status == OK, rows[:, 1], np.nan), shape),
        state=_shaped(np.where(status == OK, _words(rows[:, 2], END_STATES), "failed"), shape),
        status=_shaped(_words(status, STATUS), shape),
    )
