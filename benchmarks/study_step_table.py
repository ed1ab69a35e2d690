"""Study of the batch at MuJoCo's step (issue 33 item 5): the step table's accuracy and speed.

Run: ``PYTHONPATH=src python benchmarks/study_step_table.py [N]`` (default 400 scenes).

``N`` random scenes (mass 0.02-20 kg, 3-80 steps per undamped contact at 2 ms, 0.1-3 m/s,
gravity plus a push of 0-10 times the weight, e_N targets 0.05-0.95) go through one batched
``contact_parameters(..., engine="mujoco", timestep=0.002)``.  Then, independently of the table,
each answered row's MuJoCo block is run through the step map's exact phase mean
(``stepping.delivered.over_phase``, adaptive quadrature across the jumps): the printed error is
that mean minus the target, by the map.  Also printed: how the rows were answered (table, exact
fallback, unreachable), whether the table's own error estimate bounds the error, and the batch's
speed against the continuous batch of the same scenes (the baseline, same run) and against one
scene's exact answer at the step.
"""

import os
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "2")

import numpy as np  # noqa: E402


def scenes(n, seed=7):
    """Random scenes: ``(mass, stiffness, speed, accel, target)`` arrays."""
    rng = np.random.default_rng(seed)
    m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), n))
    steps = np.exp(rng.uniform(np.log(3.0), np.log(80.0), n))
    omega = np.pi / (steps * 0.002)
    v = np.exp(rng.uniform(np.log(0.1), np.log(3.0), n))
    a = 9.81 * (1.0 + rng.uniform(0.0, 10.0, n) * (rng.uniform(size=n) < 0.5))
    e = rng.uniform(0.05, 0.95, n)
    return m, m * omega**2, v, a, e


def main(argv=None):
    from contactalpha import contact_parameters
    from contactalpha.stepping.delivered import over_phase
    from contactalpha.stepping.registry import stepper

    argv = sys.argv[1:] if argv is None else argv
    n = int(argv[0]) if argv else 400
    m, k, v, a, e = scenes(n)
    s = stepper("mujoco")

    start = time.perf_counter()
    contact_parameters(mass=m[:2], stiffness=k[:2], approach_speed=v[:2], accel=a[:2], e_N=e[:2],
                       engine="mujoco", timestep=0.002)  # fmt: skip
    print(f"first batch call (loads the table, compiles or loads the kernels): {time.perf_counter() - start:.2f} s")

    start = time.perf_counter()
    cp = contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=0.002)
    t_batch = time.perf_counter() - start
    st = cp.stepped
    src, status = st.source, st.status
    print(f"{n} scenes: {np.sum(src == 'table')} by the table, {np.sum(src == 'exact')} solved exactly, "
          f"{np.sum(status == 'unreachable')} unreachable at 2 ms, {np.sum(~cp.ok)} without an answer")  # fmt: skip

    errors, estimates, srcs = [], [], []
    for i in np.flatnonzero(cp.ok):
        block = {key: (tuple(float(x[i]) for x in val) if isinstance(val, tuple) else val)
                 for key, val in cp.block.items()}  # fmt: skip
        p = s.from_block(block, float(m[i]), None)
        mean = over_phase("mujoco", p, 0.002, float(v[i]), float(a[i])).mean
        errors.append(mean - e[i])
        estimates.append(st.mean_error[i])
        srcs.append(src[i])
    errors, estimates, srcs = np.abs(errors), np.asarray(estimates), np.asarray(srcs)
    for name in ("table", "exact"):
        sel = srcs == name
        if sel.any():
            q = np.quantile(errors[sel], [0.5, 0.99, 1.0])
            print(f"  {name:5s} rows: |mean - target| by the map: median {q[0]:.1e}, 99% {q[1]:.1e}, max {q[2]:.1e}")
    sel = srcs == "table"
    if sel.any():
        over = np.sum(errors[sel] > estimates[sel] + 1e-6)
        print(f"  table rows whose error exceeds their estimate (+1e-6): {over} of {sel.sum()}")

    start = time.perf_counter()
    contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco")
    t_cont = time.perf_counter() - start
    big = 100_000
    mb, kb, vb, ab, eb = scenes(big, seed=11)
    start = time.perf_counter()
    cpb = contact_parameters(mass=mb, stiffness=kb, approach_speed=vb, accel=ab, e_N=eb, engine="mujoco",
                             timestep=0.002)  # fmt: skip
    t_big = time.perf_counter() - start
    n_exact = int(np.sum(cpb.stepped.source == "exact"))
    start = time.perf_counter()
    contact_parameters(mass=mb, stiffness=kb, approach_speed=vb, accel=ab, e_N=eb, engine="mujoco")
    t_big_cont = time.perf_counter() - start
    start = time.perf_counter()
    contact_parameters(mass=float(m[0]), stiffness=float(k[0]), approach_speed=float(v[0]), accel=float(a[0]),
                       e_N=float(e[0]), engine="mujoco", timestep=0.002)  # fmt: skip
    t_one = time.perf_counter() - start
    print(f"speed ({os.environ['NUMBA_NUM_THREADS']} threads):")
    print(f"  batch of {n} at 2 ms: {n / t_batch:10.0f} scenes/s (its {np.sum(src == 'exact')} exact rows included); "
          f"continuous batch {n / t_cont:10.0f} scenes/s")  # fmt: skip
    print(f"  batch of {big} at 2 ms: {big / t_big:10.0f} scenes/s ({n_exact} exact rows included); "
          f"continuous batch {big / t_big_cont:10.0f} scenes/s; ratio {t_big / t_big_cont:.2f}")  # fmt: skip
    print(f"  one scene exactly at 2 ms: {1 / t_one:10.1f} scenes/s")


if __name__ == "__main__":
    main()
