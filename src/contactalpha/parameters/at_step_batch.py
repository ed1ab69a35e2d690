"""A batch at an engine's own step: the phase-mean parameters of many scenes at formula speed.

``contact_parameters(..., engine=NAME, timestep=h)`` with array inputs solves the continuous law
for the batch first (``parameters.batch``).  For an engine whose step is piecewise affine
(``stepping.registry.Stepper.affine``: MuJoCo, PyBullet) and an e_N target, every row is then
solved exactly in one parallel call (``stepping.batch_inverse``): the damping whose phase mean is
the target within ``stepping.inverse.MEAN_TOL`` by the map, starting from the continuous law's
damping, whose own mean at the step is reported too.  Every row of another engine (Drake) or of
an eps target is solved by ``stepping.inverse.damping_for``, one scene at a time (slow: progress
on stderr).  A row with no answer (unreachable at this step, or no continuous answer) has NaN in
every number of the engine's block and ``ok = False`` with the reason.
"""

import math
import warnings
from dataclasses import replace
from typing import Any

import numpy as np

from contactalpha.adapters.registry import adapter
from contactalpha.adapters.stepped import ContactStepsWarning
from contactalpha.laws.domain import target_name as restitution_name
from contactalpha.progress import Progress
from contactalpha.stepping.batch_inverse import (
    B_DAMPING,
    B_GUESS_MAX,
    B_GUESS_MEAN,
    B_GUESS_MIN,
    B_MAX,
    B_MEAN,
    B_MIN,
    B_NEAREST,
    B_OK,
    B_STATUS,
    B_STD,
    B_STEPS_MAX,
    B_STEPS_MIN,
    solve_batch,
)
from contactalpha.stepping.batch_inverse import ROW_STATUS as BATCH_STATUS
from contactalpha.stepping.delivered import MAX_CONTACT_STEPS, check_contact_steps, check_scene, contact_steps
from contactalpha.stepping.registry import stepper

from .at_step import SteppedAnswer, resolve_timestep, solve_on_map, warn_gain
from .batch import masked_rows
from .block_scene import BlockScene

# A world whose contact spans fewer steps than this is flagged: one landing there spreads by tens
# of percent of the target about the phase mean.
FEW_STEPS = 5
# Rows a flag's message names, at most.
ROWS_NAMED = 10
# Columns of the per-row answer.
_COLUMNS = ("damping", "mean", "minimum", "maximum", "std", "steps_min", "steps_max", "mean_error", "nearest",
            "continuous_mean", "continuous_minimum", "continuous_maximum")  # fmt: skip
# The columns the batch inverse fills, from its B_* columns.
_FROM_BATCH = {"damping": B_DAMPING, "mean": B_MEAN, "minimum": B_MIN, "maximum": B_MAX, "std": B_STD,
               "steps_min": B_STEPS_MIN, "steps_max": B_STEPS_MAX, "nearest": B_NEAREST,
               "continuous_mean": B_GUESS_MEAN, "continuous_minimum": B_GUESS_MIN,
               "continuous_maximum": B_GUESS_MAX}  # fmt: skip


def _block_row(block, i, shape):
    """Row ``i`` of an engine block of arrays of the batch's ``shape`` (a row per world: its tuple)."""

    def pick(x):
        if isinstance(x, tuple):
            return tuple(pick(v) for v in x)
        if isinstance(x, np.ndarray) and x.ndim > len(shape):
            return tuple(float(v) for v in x.reshape(-1, x.shape[-1])[i])
        return float(np.asarray(x).ravel()[i]) if isinstance(x, np.ndarray) else x

    return {k: pick(v) for k, v in block.items()}


def _exact_row(s, block, m, v, a, r, h, target, restitution):
    """One row solved on the map: the ``_COLUMNS`` values, its status and the law's damping."""
    sol = solve_on_map(s, block, m, r, h, v, a, target, restitution, remedies=False)
    inv = sol.inverse
    values = (float(inv.damping), sol.mean, sol.minimum, sol.maximum, sol.std, inv.stats.steps_min,
              inv.stats.steps_max, abs(sol.mean - target), inv.nearest, *sol.continuous)  # fmt: skip
    return values, inv.status, sol.zeta


def at_step_batch(cp, engine, timestep, mass, stiffness, approach_speed, accel, radius, target, restitution):
    """``cp`` (a batch's ``ContactParameters``) with the engine's block for the phase mean at the step.

    ``mass``, ``stiffness``, ``approach_speed``, ``accel``, ``target`` (and ``radius`` or None) are
    arrays of the batch's shape, already checked by the continuous batch.
    """
    s = stepper(engine)
    if s.from_block is None or s.law_damping is None:
        raise ValueError(f"engine = {engine!r} has a step map but no front door at its step yet")
    h = resolve_timestep(engine, timestep)
    shape = np.shape(cp.ok)
    m, k, v, a, e = (np.broadcast_to(np.asarray(x, dtype=float), shape).ravel()
                     for x in (mass, stiffness, approach_speed, accel, target))  # fmt: skip
    r = None if radius is None else np.broadcast_to(np.asarray(radius, dtype=float), shape).ravel()
    n = m.size
    ok_in = np.asarray(cp.ok).ravel()
    cols = np.full((n, len(_COLUMNS)), np.nan)
    status = np.full(n, "no continuous answer", dtype=object)
    source = np.full(n, "none", dtype=object)
    zeta = np.full(n, np.nan)
    exact = ok_in.copy()
    if s.affine and restitution == "kinematic":
        block = cp.engines[engine]
        exact = _solved_in_batch(s, block, shape, h, m, v, a, r, e, ok_in, cols, status, source, zeta)
    # The law's a <= 0 rows have no touchdown phase: each exact row checks its own scene.
    rows = np.flatnonzero(exact)
    block = cp.engines[engine]
    with Progress(f"{engine} at its step: {rows.size} scene(s) solved on the map") as progress:
        every = max(1, rows.size // 20)
        for count, i in enumerate(rows):
            if count % every == 0:
                progress(f"scene {count + 1} of {rows.size}")
            ri = None if r is None else float(r[i])
            try:
                row = _block_row(block, i, shape)
                values, st, zi = _exact_row(s, row, float(m[i]), float(v[i]), float(a[i]),
                                            ri, h, float(e[i]), restitution)  # fmt: skip
            except ValueError as err:  # e.g. a drop too slow to fly a step before touchdown
                values, st, zi = (math.nan,) * len(_COLUMNS), f"no answer at this step: {err}", math.nan
            cols[i], status[i], source[i], zeta[i] = values, st, "exact", zi
    ok = status == "ok"
    a_ = adapter(engine)
    settings = replace(a_.settings, **{s.step_setting: h})
    scene = BlockScene(*(None if x is None else x.reshape(shape) for x in (m, k, v, r)))
    params = a_.parameters(np.where(ok, zeta, 0.0).reshape(shape), scene, settings)
    engines = dict(cp.engines)
    engines[engine] = {key: masked_rows(x, ok.reshape(shape)) for key, x in params.items()}
    reason = np.asarray(cp.reason, dtype=object).ravel().copy()
    nearest = cols[:, _COLUMNS.index("nearest")]
    for i in np.flatnonzero(~ok & ok_in):
        reason[i] = f"at {engine}'s step {h:.6g} s: {status[i]}"
        if status[i] == "unreachable" and np.isfinite(nearest[i]):
            name = restitution_name(restitution)
            reason[i] += (
                f"; the nearest mean {name} met is {nearest[i]:.4g} "
                "(one scene's call names the largest step that reaches the target)"
            )
    out: dict[str, Any] = {name: cols[:, c].reshape(shape) for c, name in enumerate(_COLUMNS)}
    few = _few_steps(engine, h, ok, cols[:, _COLUMNS.index("steps_min")])
    answer = SteppedAnswer(
        engine=engine, timestep=h, restitution=restitution, target=e.reshape(shape),
        law_damping=np.where(ok, zeta, np.nan).reshape(shape), status=status.reshape(shape),
        steps_min=out.pop("steps_min"), steps_max=out.pop("steps_max"),
        timestep_reachable=np.full(shape, np.nan), source=source.reshape(shape), few_steps=few, **out,
    )  # fmt: skip
    answer = warn_gain(answer)
    return cp.replaced(engines=engines, stepped=answer, ok=ok.reshape(shape), reason=reason.reshape(shape))


def _few_steps(engine, h, ok, steps_min):
    """Flat indices of the answered rows under ``FEW_STEPS`` steps in contact; a warning gives the count."""
    few = np.flatnonzero(ok & (steps_min < FEW_STEPS))
    if few.size:
        shown = ", ".join(str(int(i)) for i in few[:ROWS_NAMED]) + (", ..." if few.size > ROWS_NAMED else "")
        warnings.warn(
            f"{engine} at its step {h:.6g} s: {few.size} of {ok.size} world(s) have fewer than {FEW_STEPS} "
            f"steps in contact (rows {shown}; all in stepped.few_steps): the mean is delivered over "
            "touchdown phases, but one landing there spreads widely about it; a smaller step narrows it",
            ContactStepsWarning,
            stacklevel=4,
        )
    return few


def _flat(x, shape):
    """A block's value with every array raveled over the batch's ``shape`` (a row per world kept whole)."""
    if isinstance(x, tuple):
        return tuple(_flat(v, shape) for v in x)
    if isinstance(x, np.ndarray) and x.ndim > len(shape):
        return np.asarray(x, dtype=float).reshape(-1, x.shape[-1])
    return np.asarray(x, dtype=float).ravel() if isinstance(x, np.ndarray) else x


def _solved_in_batch(s, block, shape, h, m, v, a, r, e, ok_in, cols, status, source, zeta):
    """Solve the rows of a piecewise-affine map exactly in one parallel call (``stepping.batch_inverse``).

    Fills the rows with a continuous answer; returns the mask of rows left to the one-at-a-time
    inverse (none).
    """
    params_all = s.from_block({key: _flat(x, shape) for key, x in block.items()}, m, r)
    params_all = np.ascontiguousarray(np.broadcast_to(params_all, (m.size, params_all.shape[-1])))
    with np.errstate(invalid="ignore"):  # a row without a continuous answer: NaN parameters
        bounded = ~(contact_steps(s, params_all.T, h) > MAX_CONTACT_STEPS)  # ``check_contact_steps``
    flies = (v >= 0.5 * a * h) & bounded  # a drop flies a step before touchdown (``check_scene``)
    rows = np.flatnonzero(ok_in & flies)
    params = params_all[rows]
    out = solve_batch(s, params, h, v[rows], a[rows], e[rows])
    for name, c in _FROM_BATCH.items():
        cols[rows, _COLUMNS.index(name)] = out[:, c]
    cols[rows, _COLUMNS.index("mean_error")] = np.abs(out[:, B_MEAN] - e[rows])
    st = out[:, B_STATUS].astype(int)
    status[rows] = [BATCH_STATUS[c] for c in st]
    source[rows] = "exact"
    good = st == B_OK
    params[:, list(s.damping_slots)] = out[:, [B_DAMPING]]
    zeta[rows[good]] = s.law_damping(params[good].T, v[rows[good]])
    for i in np.flatnonzero(ok_in & ~flies):  # check_scene says why, as for one scene
        try:
            check_scene(params_all[i], h, v[i], a[i])
            check_contact_steps(s, params_all[i], h)
        except ValueError as err:
            status[i], source[i] = f"no answer at this step: {err}", "exact"
    return np.zeros_like(ok_in)
