"""Build an engine's step table: the phase-mean e_N of its map over (step, damping, load).

In the scaling of the engine's law (approach speed 1, contact angular frequency omega = 1) a
drop through the map depends on three numbers only: the step ``x = omega h`` (pi over the steps
per undamped half period), the law's dimensionless damping ``c`` (zeta for MuJoCo, alpha for
Drake) and the load, given as the law's load factor ``xi`` (``A = law.scaled_load(xi)``).  The
table holds, on a uniform grid of each, the phase mean of e_N over a uniform touchdown phase and
the range one drop sees (``phase.phase_mean``), and the steps in contact.

- ``x = 0`` is the continuous law (the map converges on it at first order in ``x``): its e_N,
  with the range collapsed onto it.
- A drop must fly a step before touchdown (``v >= a h / 2``, ``delivered.check_scene``):
  cells with ``A x`` above ``MAX_LOAD_STEP`` are NaN.
- Along the damping a column ends (NaN after it) at the first node where every phase is
  captured (e_N = 0 for every drop: more damping need not capture too, with the force's floor),
  where a drop fails, or past the damping at which the step turns unstable
  (``StepTableSpec.stable_damping``).  ``table.StepTable.inverse`` uses only the first crossing
  of the target from zero damping upwards, and leaves a target that no node brackets to the
  exact inverse.

Cells run in parallel (numba ``prange``); each is deterministic, so the bits do not depend on the
threads.  ``python -m contactalpha.stepping.table_build [ENGINE ...]`` rebuilds the shipped
files (``data/step_table_<engine>.npz``), each with its grid, tolerances, the code version and
the arrays' SHA-256.
"""

import argparse
import math
import sys
import time
from dataclasses import asdict

import numpy as np
from numba import njit, prange

from contactalpha.laws import get_law
from contactalpha.provenance import git_commit, source_hash

from .codes import CAPTURED, P_MAX, P_MEAN, P_MIN, P_STATUS, P_STEPS_MAX, P_STEPS_MIN, QUAD_LIMIT
from .delivered import REST_CONTACT_TIMES
from .phase import GL_W, GL_X, GRID, MAX_INTERVALS, phase_mean
from .registry import STEPPERS, stepper
from .table import (
    F_MAX,
    F_MEAN,
    F_MIN,
    F_STEPS_MAX,
    F_STEPS_MIN,
    MAX_LOAD_STEP,
    N_FIELDS,
    TABLE_FORMAT,
    save_step_table,
    table_path,
)


@njit(cache=True, parallel=True)
def _build_cells(code, params, dampings, xs, limits, loads, tol, out):
    """Fill ``out[i, k, j, F_*]`` for step ``xs[i]``, load ``loads[k]`` and damping row ``params[j]``.

    Along the damping a column stops (NaN after) at the first node where every phase is captured,
    where a drop fails, or past ``limits[i]``, the damping at which the step turns unstable.
    """
    nx, nl, nc = xs.size, loads.size, params.shape[0]
    out[:] = math.nan
    for n in prange(nx * nl):
        i = n // nl
        k = n % nl
        x, a = xs[i], loads[k]
        if a * x > MAX_LOAD_STEP:
            continue
        max_steps = int(max(1000.0, math.ceil(REST_CONTACT_TIMES * math.pi / x)))
        for j in range(nc):
            if dampings[j] > limits[i]:
                break
            row = phase_mean(code, params[j], x, 1.0, a, max_steps, tol, GRID, MAX_INTERVALS, GL_X, GL_W)
            st = int(row[P_STATUS])
            if not (st == 0 or st == CAPTURED or st == QUAD_LIMIT):
                break
            for f, slot in ((F_MEAN, P_MEAN), (F_MIN, P_MIN), (F_MAX, P_MAX),
                            (F_STEPS_MIN, P_STEPS_MIN), (F_STEPS_MAX, P_STEPS_MAX)):  # fmt: skip
                out[i, k, j, f] = row[slot]
            if row[P_MAX] == 0.0:
                # Every phase captured.  More damping need not capture too (with the force's floor
                # a stiffly damped drop can bounce again), and the inverse never reads past the
                # first crossing of its target: the column ends here.
                break


def build(engine, progress=None):
    """``(arrays, meta)`` of ``engine``'s step table on its registered grid (``StepTableSpec``)."""
    s = stepper(engine)
    spec = s.table
    if spec is None:
        raise ValueError(f"engine = {engine!r} has no step table; the engines with one are {table_engines()}")
    g = spec.grid
    law = get_law(spec.law)
    xs = g.steps()
    xis = g.loads()
    loads = np.asarray(law.scaled_load(xis), dtype=float)
    cs = g.dampings()
    params = np.array([spec.unit_params(c) for c in cs])
    out = np.empty((xs.size, xis.size, cs.size, N_FIELDS))
    t0 = time.perf_counter()
    for i in range(1, xs.size):  # one step at a time, so that a long build reports as it goes
        limit = np.array([math.inf if spec.stable_damping is None else spec.stable_damping(xs[i])])
        _build_cells(s.code, params, cs, xs[i : i + 1], limit, loads, g.quad_tol, out[i : i + 1])
        if progress is not None:
            progress(
                f"{engine}: step {i} of {xs.size - 1} (x = {xs[i]:.4g}), {time.perf_counter() - t0:.0f} s"
            )
    # x = 0: the continuous law, its range collapsed onto it.
    for k, xi in enumerate(xis):
        e = np.array([float(law.restitution(c, float(xi), "kinematic")) for c in cs])
        out[0, k, :, F_MEAN] = out[0, k, :, F_MIN] = out[0, k, :, F_MAX] = e
        out[0, k, :, F_STEPS_MIN] = out[0, k, :, F_STEPS_MAX] = -1.0  # continuous: no steps
    seconds = time.perf_counter() - t0
    if progress is not None:
        progress(f"{engine}: {out.shape[0] * out.shape[1] * out.shape[2]} cells in {seconds:.0f} s")
    arrays = {"table": out}
    meta = {
        "format": TABLE_FORMAT, "engine": engine, "law": law.name, "impedance": law.impedance,
        "grid": asdict(g), "damping_name": law.damping, "seconds": round(seconds, 1),
        "max_load_step": MAX_LOAD_STEP, "rest_contact_times": REST_CONTACT_TIMES, "phase_grid": GRID,
        "code_version": source_hash("contactalpha.stepping.table_build"), "git_commit": git_commit(),
        "command": f"python -m contactalpha.stepping.table_build {engine}",
    }  # fmt: skip
    return arrays, meta


def table_engines():
    """Engines whose stepper registers a step table."""
    return tuple(s.name for s in STEPPERS if s.table is not None)


def main(argv=None):
    """``python -m contactalpha.stepping.table_build [ENGINE ...]``: rebuild the shipped step tables."""
    ap = argparse.ArgumentParser(
        prog="python -m contactalpha.stepping.table_build", description=__doc__.split("\n")[0]
    )
    ap.add_argument("engines", nargs="*", help=f"engines (default all: {', '.join(table_engines())})")
    args = ap.parse_args(argv)
    for engine in args.engines or table_engines():
        arrays, meta = build(engine, progress=lambda line: print(line, file=sys.stderr, flush=True))
        path = save_step_table(arrays, meta, table_path(engine))
        print(f"wrote {path}", file=sys.stderr)


if __name__ == "__main__":
    main()
