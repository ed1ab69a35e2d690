"""Fast evaluators of the laws: the closed form of the piecewise-linear laws, the engine's table for n = 3/2.

``law.fast`` holds one of these values (or None when the law has none yet).  Each offers
``restitution(law, p, A)`` (the forward map) and ``damping(law, target, kinematic, A, xi)`` (the
inverse) on validated flat arrays, or raises naming what the law offers instead.
"""

from dataclasses import dataclass

import numpy as np

from contactalpha.engine.threads import run_rows

from .closed_form import closed_form_rows
from .integrate import ATOL, MAX_STEPS, RTOL
from .solve import PARALLEL_MIN, solve_damping


@dataclass(frozen=True)
class ClosedForm:
    """Closed-form phases (``closed_form.py``): the forward map, and the inverse by Illinois on it."""

    name: str = "closed form"

    @property
    def exact_inverse(self):
        """The evaluator whose inverse is exact (root finding on the closed form): itself."""
        return self

    def restitution(self, law, p, A, xi, kinematic):
        """Restitution of flat ``p``, ``A``."""
        out = np.empty(p.size)
        threads = None if p.size >= PARALLEL_MIN else 1
        run_rows(closed_form_rows, p.size, p, A, law.impedance, kinematic, out, threads=threads)
        return out

    def damping(self, law, target, kinematic, A, xi):
        """(p, status code) meeting flat ``target`` at flat ``A``."""
        x_eq = law.equilibrium(A)
        return solve_damping(law.code, target, kinematic, A, law.impedance, x_eq, RTOL, ATOL, MAX_STEPS, True)


@dataclass(frozen=True)
class EngineTable:
    """The Hunt-Crossley engine's shipped tables of alpha(eps, xi) (``engine/table.py``): inverse only."""

    name: str = "engine table"
    # No closed form to find roots on.
    exact_inverse = None

    def restitution(self, law, p, A, xi, kinematic):
        """Not offered: the engine tabulates the inverse."""
        raise ValueError(f"law {law.name!r} has no fast forward map; law.impact(p, xi) computes it")

    def damping(self, law, target, kinematic, A, xi):
        """(alpha, status code) from ``alpha_tabulated`` (0.01 <= target <= 1, xi <= 0.99)."""
        from contactalpha.engine.table import alpha_tabulated

        alpha = alpha_tabulated(target, xi, restitution="kinematic" if kinematic else "energetic")
        alpha = np.atleast_1d(np.asarray(alpha, dtype=float))
        return alpha, np.where(np.isfinite(alpha), 0, 6)


CLOSED_FORM = ClosedForm()
ENGINE_TABLE = EngineTable()


def _flat(law, a, b, a_name, a_check):
    from .maps import check_load_factor

    return _flat_unchecked(law, a_check(a), check_load_factor(law, b))


def _flat_unchecked(law, a, b):
    aa, xx = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    shape = aa.shape
    af = np.ascontiguousarray(aa, dtype=float).ravel()
    xf = np.ascontiguousarray(xx, dtype=float).ravel()
    A = np.atleast_1d(law.scaled_load_unchecked(xf)).astype(float)
    return af, xf, A, shape


def _shaped(a, shape):
    a = np.asarray(a).reshape(shape)
    return a[()] if a.ndim == 0 else a


def _fast_of(law):
    if law.fast is None:
        raise ValueError(
            f"law {law.name!r} has no fast evaluator yet; law.impact and law.damping_for compute it exactly "
            "(laws with one: see ContactLaw.fast)"
        )
    return law.fast


def fast_restitution(law, p, xi, restitution="energetic"):
    """Forward map by the law's fast evaluator: ``eps`` or ``e_N`` at damping ``p``, load factor ``xi``."""
    from contactalpha.validation import check_range

    from .domain import check_restitution

    kinematic = check_restitution(restitution) == "kinematic"
    fast = _fast_of(law)
    pf, xf, A, shape = _flat(
        law, p, xi, law.damping, lambda v: check_range(law.damping, v, 0.0, np.inf, hi_open=True)
    )
    return _shaped(fast.restitution(law, pf, A, xf, kinematic), shape)


def fast_damping(law, target, xi, restitution="energetic", exact=False):
    """Inverse by the law's fast evaluator: damping ``p`` for ``target`` at load factor ``xi`` (NaN: none).

    ``exact`` asks for root finding on the fast forward map (the closed form: the solver's
    tolerance) instead of a table (1e-7 in restitution); laws without one raise.
    """
    from contactalpha.validation import check_flag

    from .maps import check_target

    fast = _fast_of(law)
    if check_flag("exact", exact):
        if fast.exact_inverse is None:
            raise ValueError(
                f"law {law.name!r} has no closed form to invert exactly; law.damping_for computes it"
            )
        fast = fast.exact_inverse
    tf, xf, A, shape = _flat(law, target, xi, "target", lambda v: check_target(law, v, restitution))
    return _damping(law, fast, tf, xf, A, shape, restitution)


def fast_damping_unchecked(law, target, xi, restitution):
    """``fast_damping`` (not ``exact``) of a target and a load factor already checked: inner layers'."""
    tf, xf, A, shape = _flat_unchecked(law, target, xi)
    return _damping(law, _fast_of(law), tf, xf, A, shape, restitution)


def _damping(law, fast, tf, xf, A, shape, restitution):
    p, status = fast.damping(law, tf, restitution == "kinematic", A, xf)
    return _shaped(np.where(status == 0, p, np.nan), shape)
