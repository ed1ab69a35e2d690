"""Benchmark of the answers at an engine's step (issue 33): per scene, and the cost of --verify.

Run: ``PYTHONPATH=src python benchmarks/bench_stepping.py`` (``--quick``: fewer scenes;
``--batch-only N``: only the batch, N scenes per affine engine, on 1 and 2 threads; ``--page``
with it fills the batch block of docs/stepping.md).
Prints, measured side by side in this run (one thread; compile time first, separately):
- the phase mean of one scene (``stepping.delivered.over_phase``): scenes per second, and drops
  evaluated per scene; the same mean on MuJoCo's affine pieces (``stepping.affine_phase``);
- the answer of the front door at MuJoCo's 2 ms step (``contact_parameters(..., engine="mujoco",
  timestep=0.002)``: the inverse on the phase mean) against the continuous answer of the same
  call without a step (the baseline): seconds per scene and the ratio;
- a batch at each engine's default step through the front door (MuJoCo and PyBullet solved
  exactly in one parallel call, Drake one scene at a time) against the continuous batch of the same
  scenes (the baseline); ``NUMBA_NUM_THREADS=2`` for two cores;
- the check (``verify``): each installed engine's own drop at 128 touchdown phases, per scene.
"""

import argparse
import os
import platform
import re
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
PAGE = Path(__file__).resolve().parents[1] / "docs" / "stepping.md"
START, END = "<!-- stepping-batch:start -->", "<!-- stepping-batch:end -->"

import numpy as np  # noqa: E402


def scenes(n, seed=0):
    """``n`` random scenes: mass 0.02-20 kg, 10-60 steps per contact at 2 ms, 0.2-3 m/s, e_N 0.1-0.95."""
    rng = np.random.default_rng(seed)
    m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), n))
    steps = rng.uniform(10.0, 60.0, n)
    omega = np.pi / (steps * 0.002)
    v = np.exp(rng.uniform(np.log(0.2), np.log(3.0), n))
    e = rng.uniform(0.1, 0.95, n)
    return [(float(m[i]), float(m[i] * omega[i] ** 2), float(v[i]), float(e[i])) for i in range(n)]


def main(argv=None):
    from contactalpha import contact_parameters
    from contactalpha.stepping.affine_phase import QUAD_TOL, phase_mean_affine
    from contactalpha.stepping.codes import P_EVALS
    from contactalpha.stepping.delivered import over_phase, step_limit
    from contactalpha.stepping.registry import stepper

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--batch-only", type=int, metavar="N", help="only the batch at the step, N scenes")
    ap.add_argument("--page", action="store_true", help="with --batch-only: fill docs/stepping.md's block")
    args = ap.parse_args(argv)
    if args.batch_only:
        batch_page(args.batch_only, args.page)
        return
    n = 4 if args.quick else 24
    todo = scenes(n)
    s = stepper("mujoco")

    start = time.perf_counter()
    contact_parameters(mass=0.5, stiffness=2e4, approach_speed=0.5, accel=9.81, e_N=0.5, engine="mujoco",
                       timestep=0.002)  # fmt: skip
    print(f"first call (compiles or loads the kernels): {time.perf_counter() - start:.2f} s")

    start = time.perf_counter()
    evals = 0
    for m, k, v, _ in todo:
        st = over_phase("mujoco", s.pack(stiffness=k / m, damping=0.3 * np.sqrt(k / m), impedance=0.9), 0.002,
                        v, 9.81)  # fmt: skip
        evals += st.evaluations
    t_mean = (time.perf_counter() - start) / n
    print(f"phase mean:        {1 / t_mean:10.0f} scenes/s  ({evals / n:.0f} drops per scene; the baseline)")
    reps = 200
    start = time.perf_counter()
    pieces = 0
    for _ in range(reps):
        for m, k, v, _ in todo:
            p = s.pack(stiffness=k / m, damping=0.3 * np.sqrt(k / m), impedance=0.9)
            pieces += phase_mean_affine(s.code, p, 0.002, v, 9.81, step_limit(s, p, 0.002), QUAD_TOL)[P_EVALS]
    t_affine = (time.perf_counter() - start) / (n * reps)
    print(f"affine phase mean: {1 / t_affine:10.0f} scenes/s  ({pieces / n / reps:.1f} pieces per scene; "
          f"{t_mean / t_affine:.0f} x faster than the baseline)")  # fmt: skip

    def per_scene(**kw):
        start = time.perf_counter()
        for m, k, v, e in todo:
            contact_parameters(
                mass=m, stiffness=k, approach_speed=v, accel=9.81, e_N=e, engine="mujoco", **kw
            )
        return (time.perf_counter() - start) / n

    base = per_scene()
    stepped = per_scene(timestep=0.002)
    print(f"continuous answer: {base * 1e3:10.3f} ms/scene (baseline)")
    print(f"answer at 2 ms:    {stepped * 1e3:10.3f} ms/scene  ({1 / stepped:.0f} scenes/s; "
          f"{stepped / base:.0f} x the baseline)")  # fmt: skip
    batch(100_000 if not args.quick else 10_000)
    import importlib.util

    # (engine, module, step, radius): each engine's verify at 128 phases, on a few of the scenes.
    for engine, module, h, radius in [("mujoco", "mujoco", 0.002, None), ("drake", "pydrake", 0.001, None),
                                      ("pybullet", "pybullet", 5e-4, 0.05)]:  # fmt: skip
        if importlib.util.find_spec(module) is None:
            print(f"verify ({engine}): not installed")
            continue
        few = todo[: max(2, n // 8)]
        answer = verify = 0.0
        for m, k, v, e in few:
            kw = dict(mass=m, stiffness=k, approach_speed=v, accel=9.81, e_N=e, engine=engine, timestep=h,
                      radius=radius)  # fmt: skip
            start = time.perf_counter()
            cp = contact_parameters(**kw)
            answer += time.perf_counter() - start
            if cp.stepped.status == "ok":
                start = time.perf_counter()
                contact_parameters(**kw, verify=128)
                verify += time.perf_counter() - start
        print(f"verify ({engine}, {h:g} s, 128 phases): {max(verify - answer, 0.0) / len(few) * 1e3:.0f} "
              f"ms/scene beside an answer of {answer / len(few) * 1e3:.0f} ms/scene")  # fmt: skip


def batch(n):
    """A batch at each engine's default step through the front door, against the continuous batch (baseline).

    MuJoCo and PyBullet: every row solved exactly in one parallel call (``stepping.batch_inverse``);
    Drake (not piecewise affine): one scene at a time, on a few rows.  The first call of each
    compiles or loads the kernels and is timed apart.
    """
    from contactalpha import contact_parameters

    rng = np.random.default_rng(1)
    for engine, h, radius, rows in [("mujoco", 0.002, None, n), ("pybullet", 1.0 / 240.0, 0.05, n),
                                    ("drake", 0.001, None, 4)]:  # fmt: skip
        m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), rows))
        k = m * (np.pi / (rng.uniform(10.0, 60.0, rows) * h)) ** 2
        v = rng.uniform(0.3, 3.0, rows)
        e = rng.uniform(0.1, 0.95, rows)
        kw = dict(mass=m, stiffness=k, approach_speed=v, accel=9.81, e_N=e, engine=engine)
        start = time.perf_counter()
        two = {x: y[:2] if isinstance(y, np.ndarray) else y for x, y in kw.items()}
        contact_parameters(**two, timestep=h, radius=radius)
        first = time.perf_counter() - start
        start = time.perf_counter()
        contact_parameters(**kw)
        t_cont = time.perf_counter() - start
        start = time.perf_counter()
        cp = contact_parameters(**kw, timestep=h, radius=radius)
        t_step = time.perf_counter() - start
        ok = cp.stepped.status == "ok"
        miss = float(np.max(np.abs(cp.stepped.mean[ok] - e[ok]))) if ok.any() else float("nan")
        print(f"batch of {rows} at {engine}'s {h:g} s: {rows / t_step:.0f} scenes/s, continuous batch "
              f"{rows / t_cont:.0f} scenes/s (baseline), {t_step / t_cont:.1f} x the baseline; "
              f"{ok.sum()} reach the target (largest |mean - target| by the map {miss:.1e}), "
              f"{rows - ok.sum()} out of reach; "
              f"first call {first:.2f} s ({os.environ['NUMBA_NUM_THREADS']} thread(s))")  # fmt: skip


def _draw(engine, h, rows, rng):
    m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), rows))
    k = m * (np.pi / (rng.uniform(10.0, 60.0, rows) * h)) ** 2
    return dict(mass=m, stiffness=k, approach_speed=rng.uniform(0.3, 3.0, rows), accel=9.81,
                e_N=rng.uniform(0.1, 0.95, rows), engine=engine)  # fmt: skip


def batch_page(n, page):
    """The batch at MuJoCo's and PyBullet's default steps against the continuous batch, 1 and 2 threads.

    Each timing is the best of three runs of the whole front door on the same ``n`` scenes, the
    continuous batch (the baseline) and the batch at the step alternating; ``page`` writes the table
    between the markers of docs/stepping.md.
    """
    import numba

    from contactalpha import contact_parameters

    rows = []
    load_before = os.getloadavg()[0]
    for engine, h, radius in [("mujoco", 0.002, None), ("pybullet", 1.0 / 240.0, 0.05)]:
        kw = _draw(engine, h, n, np.random.default_rng(1))
        two = {x: y[:2] if isinstance(y, np.ndarray) else y for x, y in kw.items()}
        contact_parameters(**two, timestep=h, radius=radius)  # compiles or loads the kernels
        contact_parameters(**two)
        for threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
            numba.set_num_threads(threads)
            t_cont = t_step = float("inf")
            for _ in range(3):
                start = time.perf_counter()
                contact_parameters(**kw)
                t_cont = min(t_cont, time.perf_counter() - start)
                start = time.perf_counter()
                cp = contact_parameters(**kw, timestep=h, radius=radius)
                t_step = min(t_step, time.perf_counter() - start)
            ok = cp.stepped.status == "ok"
            miss = float(np.max(np.abs(cp.stepped.mean[ok] - kw["e_N"][ok]))) if ok.any() else float("nan")
            rows.append((engine, h, threads, n / t_step, n / t_cont, t_step / t_cont, int(ok.sum()), miss))
            print(f"{engine} {h:g} s, {threads} thread(s): {n / t_step:.3g} scenes/s, continuous "
                  f"{n / t_cont:.3g} scenes/s, ratio {t_step / t_cont:.1f}; {ok.sum()} of {n} reach the "
                  f"target (largest |mean - target| by the map {miss:.1e})", flush=True)  # fmt: skip
    load_after = os.getloadavg()[0]
    lines = [
        f"`NUMBA_NUM_THREADS=2 python benchmarks/bench_stepping.py --batch-only {n:,} --page` on "
        f"{platform.machine()}, {os.cpu_count()} cores, load average {load_before:.1f} before and "
        f"{load_after:.1f} after (other sessions' jobs on the same cores: the ratio to the continuous batch, "
        f"measured alternately in the same run, is the number to compare), {n:,} random scenes per engine "
        "(mass 0.02–20 kg, 10–60 steps per undamped contact at the engine's default step, 0.3–3 m/s "
        "under gravity, e_N 0.1–0.95), best of three runs each:",
        "",
        "| engine (step) | threads | scenes/s, whole batch through the front door | continuous batch "
        "(baseline) | ratio (time) | reach the target | largest \\|mean − target\\| by the map |",
        "|---|---|---|---|---|---|---|",
    ]
    names = {"mujoco": "MuJoCo", "pybullet": "PyBullet"}
    for engine, _, threads, rate, base, ratio, ok, miss in rows:
        step = "2 ms" if engine == "mujoco" else "1/240 s"
        lines.append(f"| {names[engine]} ({step}) | {threads} | {rate:.3g} | {base:.3g} | {ratio:.1f} | "
                     f"{ok:,} of {n:,} | {miss:.1e} |")  # fmt: skip
    block = "\n".join(lines)
    print(block)
    if page:
        text = PAGE.read_text()
        pattern = re.compile(re.escape(START) + ".*?" + re.escape(END), flags=re.S)
        if not pattern.search(text):
            raise ValueError(f"{PAGE} has no {START} ... {END} block")
        PAGE.write_text(pattern.sub(lambda _: f"{START}\n{block}\n{END}", text))


if __name__ == "__main__":
    main()
