"""Where a law's reference numbers come from: the family's integrator, or the Hunt-Crossley engine.

A backend maps validated flat float arrays to rows: ``impact(law, p, A, xi)`` gives columns
(eps, e_N, state code, status code, x_m, x_e, v_e) and ``damping(law, target, kinematic, A, xi)``
gives (p, status code).  Hunt-Crossley n = 3/2 keeps its own engine (``engine/driver.py``,
``engine/solver.py``), unchanged, so its numbers stay bit-identical.
"""

from dataclasses import dataclass

import numpy as np

from contactalpha.engine.codes import STATE_CODES, STATUS
from contactalpha.engine.firstcall import FirstCall

from .integrate import (
    ATOL,
    MAX_STEPS,
    R_EN,
    R_EPS2,
    R_STATE,
    R_STATUS,
    R_TE,
    R_VE,
    R_XE,
    R_XM,
    RTOL,
    impact_rows,
)
from .solve import solve_damping

_STATUS_CODES = {word: code for code, word in STATUS.items()}
# Impacts of a first call on a cold numba cache run as the kernel's Python twin (``firstcall``):
# a few rows cost milliseconds, its compile seconds; larger arrays compile at once.
TWIN_ROWS_MAX = 64
_impact_rows = FirstCall(impact_rows, interpret_if=lambda code, p, *rest: p.size <= TWIN_ROWS_MAX)


@dataclass(frozen=True)
class FamilyBackend:
    """The family's DOP853 integrator with exact free flight (``integrate.py``, ``solve.py``)."""

    name: str = "family integrator"

    def impact(self, law, p, A, xi, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
        """Rows (eps, e_N, state, status, x_m, x_e, v_e, t_e) of impacts at flat ``p``, ``A``, ``xi``."""
        rows = _impact_rows(law.code, p, A, law.impedance, law.equilibrium(A), rtol, atol, max_steps)
        eps = np.sqrt(np.maximum(rows[:, R_EPS2], 0.0))
        eps = np.where(np.isnan(rows[:, R_EPS2]), np.nan, eps)
        cols = (
            eps,
            rows[:, R_EN],
            rows[:, R_STATE],
            rows[:, R_STATUS],
            rows[:, R_XM],
            rows[:, R_XE],
            rows[:, R_VE],
            rows[:, R_TE],
        )
        return np.column_stack(cols)

    def damping(self, law, target, kinematic, A, xi, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
        """(p, status code) that meet flat ``target`` restitutions at flat ``A``, ``xi``."""
        return solve_damping(
            law.code, target, kinematic, A, law.impedance, law.equilibrium(A), rtol, atol, max_steps
        )


@dataclass(frozen=True)
class EngineBackend:
    """The package's Hunt-Crossley n = 3/2 engine, called through its public functions."""

    name: str = "Hunt–Crossley engine"

    def impact(self, law, p, A, xi, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
        """Rows (eps, e_N, state, status, x_m, x_e, v_e, t_e) of impacts at flat ``p``, ``A``, ``xi``."""
        from contactalpha.engine.driver import impact_unchecked

        r = impact_unchecked(p, xi, rtol=rtol, atol=atol, max_steps=max_steps)
        state = np.array([STATE_CODES[s] for s in np.atleast_1d(r.state)], dtype=float)
        status = np.array([_STATUS_CODES[s] for s in np.atleast_1d(r.status)], dtype=float)
        cols = (r.eps, r.e_n, state, status, r.x_max, r.x_end, r.v_end, r.t_end)
        return np.column_stack([np.atleast_1d(np.asarray(c, dtype=float)) for c in cols])

    def damping(self, law, target, kinematic, A, xi, rtol=RTOL, atol=ATOL, max_steps=MAX_STEPS):
        """(p, status code) that meet flat ``target`` restitutions at flat ``A``, ``xi``."""
        from contactalpha.engine.solver import solve_alpha

        sol = solve_alpha(
            target,
            xi,
            rtol=rtol,
            atol=atol,
            max_steps=max_steps,
            restitution="kinematic" if kinematic else "energetic",
        )
        status = np.array([_STATUS_CODES[s] for s in np.atleast_1d(sol.status)], dtype=np.int64)
        return np.atleast_1d(np.asarray(sol.alpha, dtype=float)), status


FAMILY = FamilyBackend()
ENGINE = EngineBackend()
