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
from contactalpha.stepping.delivered import over_phase
from contactalpha.stepping.inverse import damping_for
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

from .law_scene import EngineScene
from .stepped import SteppedAnswer, resolve_timestep

# Columns of the per-row answer: the table's O_* plus what the continuous damping delivers.
_COLUMNS = ("damping", "mean", "minimum", "maximum", "std", "steps_min", "steps_max", "mean_error", "nearest",
            "continuous_mean", "continuous_minimum", "continuous_maximum")  # fmt: skip


def _block_row(block, i):
    """Row ``i`` of an engine block of arrays (tuples entry by entry)."""

    def pick(x):
        if isinstance(x, tuple):
            return tuple(pick(v) for v in x)
        return float(np.asarray(x).ravel()[i]) if isinstance(x, np.ndarray) else x

    return {k: pick(v) for k, v in block.items()}


def _exact_row(s, engine, block, m, v, a, r, h, target, restitution):
    """One row solved on the map: the ``_COLUMNS`` values, its status and the law's damping."""
    p0 = s.from_block(block, m, r)
    before = over_phase(engine, p0, h, v, a).of(restitution)
    inv = damping_for(engine, p0, h, v, a, target, restitution, remedies=False)
    ok = inv.status == "ok"
    mean, lo, hi = inv.stats.of(restitution) if ok else (math.nan,) * 3
    std = (inv.stats.std if restitution == "kinematic" else inv.stats.eps_std) if ok else math.nan
    values = (float(inv.damping), mean, lo, hi, std, inv.stats.steps_min, inv.stats.steps_max,
              abs(mean - target), inv.nearest, *before)  # fmt: skip
    zeta = float(s.law_damping(inv.p, v)) if ok else math.nan
    return values, inv.status, zeta


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
    if s.table is not None and restitution == "kinematic":
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
                values, st, zi = _exact_row(s, engine, _block_row(block, i), float(m[i]), float(v[i]),
                                            float(a[i]), ri, h, float(e[i]), restitution)  # fmt: skip
            except ValueError as err:  # e.g. a drop too slow to fly a step before touchdown
                values, st, zi = (math.nan,) * len(_COLUMNS), f"no answer at this step: {err}", math.nan
            cols[i], status[i], source[i], zeta[i] = values, st, "exact", zi
    ok = status == "ok"
    a_ = adapter(engine)
    settings = replace(a_.settings, **{s.step_setting: h})
    scene = EngineScene(m, k, v, r)
    params = a_.parameters(np.where(ok, zeta, 0.0), scene, settings)
    from_table = ok & (source == "table")
    cols[from_table, 0] = np.broadcast_to(s.block_damping(params), (n,))[from_table]
    engines = dict(cp.engines)
    engines[engine] = {key: _nan_rows(x, ok, shape) for key, x in params.items()}
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


def _from_table(s, engine, cp, h, m, k, a, e, ok_in, cols, status, source, zeta):
    """Fill the rows the table answers; return the mask of rows left to the exact inverse."""
    tab = step_table(engine, s.table)
    x = h * np.sqrt(k / m)
    xi = np.where(ok_in, np.asarray(cp.xi, dtype=float).ravel(), np.nan)
    rows = tab.inverse(x, xi, e)
    before = tab.forward(x, xi, np.asarray(cp.damping, dtype=float).ravel())
    st = rows[:, O_STATUS].astype(int)
    done = ok_in & ((st == OK) | (st == UNREACHABLE))
    for c, o in enumerate((O_DAMPING, O_MEAN, O_MIN, O_MAX)):
        cols[done, c] = rows[done, o]
    for c, o in ((5, O_STEPS_MIN), (6, O_STEPS_MAX), (7, O_ERROR), (8, O_NEAREST)):
        cols[done, c] = rows[done, o]
    cols[done, 9:12] = before[done]
    status[done] = [ROW_STATUS[v] for v in st[done]]
    source[done] = "table"
    good = done & (st == OK)
    zeta[good] = rows[good, O_DAMPING]  # the law's damping; the engine's own is read from its block
    # Past the table's grid the phase mean's cells are NaN where a drop flies less than a step:
    # the exact rows check that scene and say so.
    return ok_in & ~done


def _nan_rows(x, ok, shape):
    """Engine value ``x`` with NaN in the rows without an answer, in the batch's shape."""
    if isinstance(x, tuple):
        return tuple(_nan_rows(v, ok, shape) for v in x)
    if isinstance(x, np.ndarray | float | int) and not isinstance(x, bool):
        return np.where(ok, np.broadcast_to(np.asarray(x, dtype=float), ok.shape), np.nan).reshape(shape)
    return x
