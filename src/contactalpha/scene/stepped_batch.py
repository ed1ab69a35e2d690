"""A batch at an engine's own step: the phase-mean parameters of many scenes at formula speed.

``contact_parameters(..., engine=NAME, timestep=h)`` with array inputs solves the continuous law
for the batch first (``scene.batched``), then, for an engine whose stepper has a step table
(``stepping.registry.Stepper.table``) and an e_N target, reads the damping whose phase mean is
the target from the table (``stepping.table.StepTable.inverse``) and what the continuous law's
damping delivers at the step (``forward``).  Rows the table cannot answer within its accuracy,
or that lie outside its grid, and every row of an engine without a table or of an eps target,
are solved exactly by ``stepping.inverse.damping_for``, one scene at a time (slow: progress on
stderr).  A row with no answer (unreachable at this step, or no continuous answer) has NaN in
every number of the engine's block and ``ok = False`` with the reason.
"""

import math
from dataclasses import replace

import numpy as np

from contactalpha.adapters.registry import adapter
from contactalpha.laws.domain import target_name as restitution_name
from contactalpha.progress import Progress
from contactalpha.stepping.registry import stepper
from contactalpha.stepping.table import (
    O_DAMPING,
    O_ERROR,
    O_MAX,
    O_MEAN,
    O_MIN,
    O_NEAREST,
    O_STATUS,
    O_STEPS_MAX,
    O_STEPS_MIN,
    OK,
    ROW_STATUS,
    UNREACHABLE,
    step_table,
)

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
    solve_rows,
)
from contactalpha.stepping.batch_inverse import ROW_STATUS as BATCH_STATUS
from contactalpha.stepping.delivered import step_limit
from contactalpha.stepping.inverse import BRACKET_START
from contactalpha.stepping.kernels import AFFINE

from .batched import masked_rows
from .law_scene import EngineScene
from .stepped import SteppedAnswer, resolve_timestep, solve_on_map

# Columns of the per-row answer: the table's O_* plus what the continuous damping delivers.
_COLUMNS = ("damping", "mean", "minimum", "maximum", "std", "steps_min", "steps_max", "mean_error", "nearest",
            "continuous_mean", "continuous_minimum", "continuous_maximum")  # fmt: skip
# The columns the step table fills, from its O_* slots.
_FROM_TABLE = {"damping": O_DAMPING, "mean": O_MEAN, "minimum": O_MIN, "maximum": O_MAX,
               "steps_min": O_STEPS_MIN, "steps_max": O_STEPS_MAX, "mean_error": O_ERROR,
               "nearest": O_NEAREST}  # fmt: skip


# The columns the batch inverse fills, from its B_* columns.
_FROM_BATCH = {"damping": B_DAMPING, "mean": B_MEAN, "minimum": B_MIN, "maximum": B_MAX, "std": B_STD,
               "steps_min": B_STEPS_MIN, "steps_max": B_STEPS_MAX, "nearest": B_NEAREST,
               "continuous_mean": B_GUESS_MEAN, "continuous_minimum": B_GUESS_MIN,
               "continuous_maximum": B_GUESS_MAX}  # fmt: skip


def _block_row(block, i):
    """Row ``i`` of an engine block of arrays (tuples entry by entry)."""

    def pick(x):
        if isinstance(x, tuple):
            return tuple(pick(v) for v in x)
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
    if s.code in AFFINE and restitution == "kinematic":
        exact = _solved_in_batch(s, cp.engines[engine], h, m, v, a, r, e, ok_in, cols, status, source, zeta)
    elif s.table is not None and restitution == "kinematic":
        exact = _from_table(s, engine, cp, h, m, k, a, e, ok_in, cols, status, source, zeta)
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
                values, st, zi = _exact_row(s, _block_row(block, i), float(m[i]), float(v[i]), float(a[i]),
                                            ri, h, float(e[i]), restitution)  # fmt: skip
            except ValueError as err:  # e.g. a drop too slow to fly a step before touchdown
                values, st, zi = (math.nan,) * len(_COLUMNS), f"no answer at this step: {err}", math.nan
            cols[i], status[i], source[i], zeta[i] = values, st, "exact", zi
    ok = status == "ok"
    a_ = adapter(engine)
    settings = replace(a_.settings, **{s.step_setting: h})
    scene = EngineScene(*(None if x is None else x.reshape(shape) for x in (m, k, v, r)))
    params = a_.parameters(np.where(ok, zeta, 0.0).reshape(shape), scene, settings)
    from_table = ok & (source == "table")
    cols[from_table, 0] = np.broadcast_to(s.block_damping(params), shape).ravel()[from_table]
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
    out = {name: cols[:, c].reshape(shape) for c, name in enumerate(_COLUMNS)}
    answer = SteppedAnswer(
        engine=engine, timestep=h, restitution=restitution, target=e.reshape(shape),
        law_damping=np.where(ok, zeta, np.nan).reshape(shape), status=status.reshape(shape),
        steps_min=out.pop("steps_min"), steps_max=out.pop("steps_max"),
        timestep_reachable=np.full(shape, np.nan), source=source.reshape(shape), **out,
    )  # fmt: skip
    return cp.replaced(engines=engines, stepped=answer, ok=ok.reshape(shape), reason=reason.reshape(shape))


def _flat(x):
    """A block's value with every array raveled (tuples entry by entry)."""
    if isinstance(x, tuple):
        return tuple(_flat(v) for v in x)
    return np.asarray(x, dtype=float).ravel() if isinstance(x, np.ndarray) else x


def _solved_in_batch(s, block, h, m, v, a, r, e, ok_in, cols, status, source, zeta):
    """Solve the rows of a piecewise-affine map exactly in one parallel call (``stepping.batch_inverse``).

    Fills the rows with a continuous answer; returns the mask of rows left to the one-at-a-time
    inverse (none).
    """
    rows = np.flatnonzero(ok_in & (v >= 0.5 * a * h))
    params = s.from_block({key: _flat(x) for key, x in block.items()}, m, r)
    params = np.ascontiguousarray(np.broadcast_to(params, (m.size, params.shape[-1])))[rows]
    guess = params[:, s.damping_slots[0]].copy()
    t_c = s.contact_time(params.T)
    out = solve_rows(s.code, params, np.array(s.damping_slots), h, v[rows], a[rows], e[rows], guess,
                     BRACKET_START / t_c, step_limit(s, params.T, h))  # fmt: skip
    for name, c in _FROM_BATCH.items():
        cols[rows, _COLUMNS.index(name)] = out[:, c]
    cols[rows, _COLUMNS.index("mean_error")] = np.abs(out[:, B_MEAN] - e[rows])
    st = out[:, B_STATUS].astype(int)
    status[rows] = [BATCH_STATUS[c] for c in st]
    source[rows] = "exact"
    good = st == B_OK
    params[:, list(s.damping_slots)] = out[:, [B_DAMPING]]
    zeta[rows[good]] = s.law_damping(params[good].T, v[rows[good]])
    slow = np.flatnonzero(ok_in & (v < 0.5 * a * h))
    status[slow] = (
        f"no answer at this step: approach_speed is below accel * timestep / 2 = {0.5 * h:.6g} * accel: a drop "
        "this slow flies less than a step before touchdown, so its touchdown phase is not defined"
    )
    source[slow] = "exact"
    return np.zeros_like(ok_in)


def _from_table(s, engine, cp, h, m, k, a, e, ok_in, cols, status, source, zeta):
    """Fill the rows the table answers; return the mask of rows left to the exact inverse."""
    tab = step_table(engine, s.table)
    x = h * np.sqrt(k / m)
    xi = np.where(ok_in, np.asarray(cp.xi, dtype=float).ravel(), np.nan)
    rows = tab.inverse(x, xi, e)
    before = tab.forward(x, xi, np.asarray(cp.damping, dtype=float).ravel())
    st = rows[:, O_STATUS].astype(int)
    done = ok_in & ((st == OK) | (st == UNREACHABLE))
    for name, o in _FROM_TABLE.items():
        cols[done, _COLUMNS.index(name)] = rows[done, o]
    for c, name in enumerate(("continuous_mean", "continuous_minimum", "continuous_maximum")):
        cols[done, _COLUMNS.index(name)] = before[done, c]
    status[done] = [ROW_STATUS[v] for v in st[done]]
    source[done] = "table"
    good = done & (st == OK)
    zeta[good] = rows[good, O_DAMPING]  # the law's damping; the engine's own is read from its block
    # Past the table's grid the phase mean's cells are NaN where a drop flies less than a step:
    # the exact rows check that scene and say so.
    return ok_in & ~done
