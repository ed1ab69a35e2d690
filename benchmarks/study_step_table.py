"""Study of the batch at MuJoCo's step (issue 33 item 5): the step table's accuracy and speed.

Run: ``PYTHONPATH=src python benchmarks/study_step_table.py [N]`` (default 300 scenes per kind).

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


def scenes(n, seed=7, push=True):
    """Random scenes ``(mass, stiffness, speed, accel, target)``: gravity, plus (``push``) in half
    of them a push of up to 10 times the weight."""
    rng = np.random.default_rng(seed)
    m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), n))
    steps = np.exp(rng.uniform(np.log(3.0), np.log(80.0), n))
    omega = np.pi / (steps * 0.002)
    v = np.exp(rng.uniform(np.log(0.1 if push else 0.3), np.log(3.0), n))
    a = 9.81 * (1.0 + push * rng.uniform(0.0, 10.0, n) * (rng.uniform(size=n) < 0.5))
    e = rng.uniform(0.05, 0.95, n)
    return m, m * omega**2, v, a, e


def accuracy(n, push):
    """One batch through the front door, each answered row checked on the map's exact phase mean."""
    from contactalpha import contact_parameters
    from contactalpha.stepping.delivered import over_phase
    from contactalpha.stepping.registry import stepper

    m, k, v, a, e = scenes(n, push=push)
    s = stepper("mujoco")
    start = time.perf_counter()
    cp = contact_parameters(
        mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=0.002
    )
    seconds = time.perf_counter() - start
    st = cp.stepped
    src, status = st.source, st.status
    label = "gravity and pushes" if push else "gravity only"
    print(f"{n} scenes ({label}): {np.sum(src == 'table')} by the table, {np.sum(src == 'exact')} solved "
          f"exactly, {np.sum(status == 'unreachable')} unreachable at 2 ms, {np.sum(~cp.ok)} without an "
          f"answer; {seconds:.1f} s ({n / seconds:.0f} scenes/s)")  # fmt: skip
    errors, srcs = [], []
    for i in np.flatnonzero(cp.ok):
        block = {key: (tuple(float(x[i]) for x in val) if isinstance(val, tuple) else val)
                 for key, val in cp.block.items()}  # fmt: skip
        p = s.from_block(block, float(m[i]), None)
        errors.append(over_phase("mujoco", p, 0.002, float(v[i]), float(a[i])).mean - e[i])
        srcs.append(src[i])
    errors, srcs = np.abs(errors), np.asarray(srcs)
    for name in ("table", "exact"):
        sel = srcs == name
        if sel.any():
            q = np.quantile(errors[sel], [0.5, 0.99, 1.0])
            print(f"  {name:5s} rows: |mean - target| by the map: median {q[0]:.1e}, 99% {q[1]:.1e}, "
                  f"max {q[2]:.1e}; above 1e-3: {np.sum(errors[sel] > 1e-3)}")  # fmt: skip


def speed(n):
    """The table's batch inverse and the continuous batch it follows, on ``n`` scenes."""
    from contactalpha import contact_parameters
    from contactalpha.stepping.registry import stepper
    from contactalpha.stepping.table import O_STATUS, OK, step_table

    m, k, v, a, e = scenes(n, seed=11, push=False)
    tab = step_table("mujoco", stepper("mujoco").table)
    start = time.perf_counter()
    cp = contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco")
    t_cont = time.perf_counter() - start
    start = time.perf_counter()
    rows = tab.inverse(0.002 * np.sqrt(k / m), cp.xi, e)
    tab.forward(0.002 * np.sqrt(k / m), cp.xi, cp.damping)
    t_tab = time.perf_counter() - start
    ok = np.mean(rows[:, O_STATUS] == OK)
    threads = os.environ["NUMBA_NUM_THREADS"]
    print(
        f"{n} scenes, {threads} threads: continuous batch {n / t_cont:10.0f} scenes/s; "
        f"the step table's inverse and forward {n / t_tab:10.0f} scenes/s ({ok:.0%} of rows answered); "
        f"both {n / (t_cont + t_tab):10.0f} scenes/s, "
        f"{(t_cont + t_tab) / t_cont:.2f} times the continuous batch"
    )


def main(argv=None):
    from contactalpha import contact_parameters

    argv = sys.argv[1:] if argv is None else argv
    n = int(argv[0]) if argv else 300
    start = time.perf_counter()
    m, k, v, a, e = scenes(2)
    contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=a, e_N=e, engine="mujoco", timestep=0.002)
    print(
        "first batch call (loads the table; compiles or loads the kernels): "
        f"{time.perf_counter() - start:.2f} s"
    )
    speed(100_000)
    speed(100_000)
    accuracy(n, push=False)
    accuracy(n, push=True)
    start = time.perf_counter()
    contact_parameters(mass=float(m[0]), stiffness=float(k[0]), approach_speed=float(v[0]), accel=float(a[0]),
                       e_N=float(e[0]), engine="mujoco", timestep=0.002)  # fmt: skip
    print(f"one scene exactly at 2 ms: {time.perf_counter() - start:.3f} s")


if __name__ == "__main__":
    main()
