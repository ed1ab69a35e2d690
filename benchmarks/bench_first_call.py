"""Benchmark of the first call of every path, cold (an empty numba cache) and warm (after ``warmup``).

Run: ``python benchmarks/bench_first_call.py`` (``--page`` also fills the first-call block of
docs/performance.md; ``--repeat N``, default 1; ``--paths NAME ...`` a subset; ``--no-jax``).

Each measurement is a fresh Python process running one path's first call:

- ``scalar``: ``contact_parameters`` for one scene (Hunt-Crossley, the default law);
- ``law``: the same for another law (Kelvin-Voigt);
- ``batch``: 1,000 scenes of the default law;
- ``scalar-step``: one scene at MuJoCo's 2 ms step (the inverse on the step map's phase mean);
- ``batch-step-<engine>``: a batch at each stepping engine's default step (100 scenes for the
  piecewise-affine maps, solved exactly in one call; 4 for Drake, one scene at a time);
- ``tune``: ``contactalpha tune`` of a test model (``tests/data/models/leg.xml``) with
  ``--no-engine-loop`` (its reduced model: the law, the map's phase mean at the model's step);
- ``jax``: ``xla.contact_parameters`` for 1,000 scenes (when JAX is installed).

Cold: an empty ``NUMBA_CACHE_DIR`` of its own; warm: a ``NUMBA_CACHE_DIR`` that ``contactalpha
warmup`` filled once in this run (its time is reported apart).  Each cell gives the process's CPU
time (user + system, ``resource.getrusage`` of the child: import, compiles and the call, every
thread) and the call's wall time; the ratio is cold over warm CPU, both measured in this run.
On a loaded machine the CPU time is the better guess of a quiet machine's wall time.
"""

import argparse
import importlib.util
import math
import os
import platform
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
PAGE = ROOT / "docs" / "performance.md"
START, END = "<!-- first-call:start -->", "<!-- first-call:end -->"
MODEL = ROOT / "tests" / "data" / "models" / "leg.xml"

# The scenes every path's program draws (the benchmark of the batch at the step, bench_stepping's ranges).
SCENES = """
import numpy as np
def scenes(n, h):
    rng = np.random.default_rng(1)
    m = np.exp(rng.uniform(np.log(0.02), np.log(20.0), n))
    k = m * (np.pi / (rng.uniform(10.0, 60.0, n) * h)) ** 2
    return dict(mass=m, stiffness=k, approach_speed=rng.uniform(0.3, 3.0, n), accel=9.81,
                e_N=rng.uniform(0.1, 0.95, n))
"""
ONE = "dict(mass=0.5, stiffness=2e4, approach_speed=0.5, accel=9.81, e_N=0.5)"
# Path -> (what it is, its program's call; the program imports contactalpha as ca first).
PATHS = {
    "scalar": ("one scene, Hunt-Crossley", "ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1e8, "
               "approach_speed=0.5, accel=9.81)"),
    "law": ("one scene, Kelvin-Voigt", "ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1e5, "
            "approach_speed=0.5, accel=9.81, law='kelvin_voigt')"),
    "batch": ("1,000 scenes, Hunt-Crossley", "ca.contact_parameters(**scenes(1000, 0.002))"),
    "scalar-step": ("one scene at MuJoCo's 2 ms", f"ca.contact_parameters(**{ONE}, engine='mujoco', "
                    "timestep=0.002)"),
    "batch-step-mujoco": ("100 scenes at MuJoCo's 2 ms", "ca.contact_parameters(**scenes(100, 0.002), "
                          "engine='mujoco', timestep=0.002)"),
    "batch-step-pybullet": ("100 scenes at PyBullet's 1/240 s", "ca.contact_parameters(**scenes(100, "
                            "1 / 240), engine='pybullet', timestep=1 / 240, radius=0.05)"),
    "batch-step-drake": ("4 scenes at Drake's 1 ms", "ca.contact_parameters(**scenes(4, 0.001), "
                         "engine='drake', timestep=0.001)"),
    "tune": ("`tune` leg.xml, reduced model", "tune()"),
    "jax": ("`xla.contact_parameters`, 1,000 scenes", "jax_call()"),
}  # fmt: skip
PROGRAM = (
    """
import time
t0 = time.perf_counter()
import warnings
warnings.simplefilter("ignore")
import contactalpha as ca
"""
    + SCENES
    + """
def tune():
    import shutil, tempfile
    from contactalpha.cli import main
    d = tempfile.mkdtemp()
    shutil.copy({model!r}, d)
    assert main(["tune", d + "/leg.xml", "--pair", "floor", "foot", "--e-n", "0.6", "--speed", "1.0",
                 "--no-engine-loop", "-o", d + "/out.xml"]) == 0
def jax_call():
    import jax
    jax.config.update("jax_enable_x64", True)
    from contactalpha import xla
    s = scenes(1000, 0.002)
    xla.contact_parameters(s["mass"], s["stiffness"], s["approach_speed"], s["accel"], s["e_N"])
t1 = time.perf_counter()
{call}
print("WALL", time.perf_counter() - t1)
"""
)


def cpu_name():
    """The CPU's model name."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown cpu"


def _env(cache):
    return {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": str(SRC)}


def run_child(args, cache):
    """``(CPU s, stdout)`` of ``python ARGS`` in a fresh process: user + system of the child."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, *args], env=_env(cache), capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise RuntimeError(f"{args[:2]} failed: {out.stderr[-2000:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, out.stdout, out.stderr


def first_call(path, cache):
    """``(CPU s, call wall s, compile lines on stderr)`` of ``path``'s first call in a fresh process."""
    code = PROGRAM.format(model=str(MODEL), call=PATHS[path][1])
    cpu, out, err = run_child(["-c", code], cache)
    wall = float(re.search(r"WALL (\S+)", out).group(1))
    return cpu, wall, err.count("contactalpha:   compiling ")


def warm_cache(cache):
    """Fill ``cache`` by ``contactalpha warmup``; its CPU s."""
    return run_child(["-m", "contactalpha", "warmup"], cache)[0]


def _median(runs):
    return tuple(statistics.median(x) for x in zip(*runs, strict=True)) if runs else (math.nan,) * 3


def measure(paths, repeat):
    """Rows ``(path, cold, warm)`` of median (CPU, wall, compiles); the warm-up's CPU s."""
    rows = []
    with tempfile.TemporaryDirectory() as warm:
        warmup_s = warm_cache(warm)
        print(f"warmup: {warmup_s:.1f} s CPU", flush=True)
        for path in paths:
            cold_runs, warm_runs = [], []
            for _ in range(repeat):
                with tempfile.TemporaryDirectory() as cold:
                    cold_runs.append(first_call(path, cold))
                warm_runs.append(first_call(path, warm))
            cold, hot = _median(cold_runs), _median(warm_runs)
            rows.append((path, cold, hot))
            print(f"{path:22s} cold {cold[0]:6.2f} s CPU {cold[1]:6.2f} s wall ({cold[2]:.0f} compiles)  "
                  f"warm {hot[0]:5.2f} s CPU {hot[1]:5.2f} s wall  cold/warm {cold[0] / hot[0]:.1f}x",
                  flush=True)  # fmt: skip
    return rows, warmup_s


def table(rows, warmup_s, load_before, load_after):
    """The markdown block for docs/performance.md."""
    lines = [
        f"Measured on {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"{platform.system()}; load average {load_before:.1f} before and {load_after:.1f} after (the machine "
        "was shared with other sessions' jobs while it ran: on a quiet machine the wall times are lower, "
        "about the CPU times). Each path's first call in a fresh process; CPU = user + system seconds of "
        "the whole process (import, compiles, the call); wall = the call's. Cold: an empty numba cache; "
        f"warm: after `contactalpha warmup` ({warmup_s:.1f} s of CPU, once). Compiles: the kernels the "
        "first call announced on stderr.",
        "",
        "| path | what | cold CPU (s) | cold wall (s) | compiles | warm CPU (s) | warm wall (s) "
        "| cold / warm (CPU) |",
        "|---|---|---|---|---|---|---|---|",
    ]  # fmt: skip
    for path, cold, hot in rows:
        lines.append(
            f"| `{path}` | {PATHS[path][0]} | {cold[0]:.2f} | {cold[1]:.2f} | {cold[2]:.0f} | {hot[0]:.2f} | "
            f"{hot[1]:.2f} | {cold[0] / hot[0]:.1f}x |"
        )
    return "\n".join(lines)


def fill_page(block, page=PAGE, start=START, end=END):
    """Put ``block`` between the ``start`` and ``end`` markers of ``page``."""
    text = page.read_text()
    pattern = re.compile(re.escape(start) + ".*?" + re.escape(end), flags=re.S)
    if not pattern.search(text):
        raise ValueError(f"{page} has no {start} ... {end} block")
    page.write_text(pattern.sub(lambda _: f"{start}\n{block}\n{end}", text))


def main(argv=None):
    """Run the benchmark and print its table (``--page``: also into docs/performance.md)."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=1, help="fresh processes per measurement (default 1)")
    p.add_argument("--paths", nargs="+", choices=tuple(PATHS), help="a subset of the paths")
    p.add_argument("--no-jax", action="store_true", help="skip the JAX path")
    p.add_argument("--page", action="store_true", help="fill the first-call block of docs/performance.md")
    args = p.parse_args(argv)
    paths = list(args.paths or PATHS)
    if "jax" in paths and (args.no_jax or importlib.util.find_spec("jax") is None):
        paths.remove("jax")
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores, {platform.platform()}")
    load_before = os.getloadavg()[0]
    start = time.perf_counter()
    rows, warmup_s = measure(paths, args.repeat)
    load_after = os.getloadavg()[0]
    print(
        f"load average before {load_before:.2f}, after {load_after:.2f}; {time.perf_counter() - start:.0f} s"
    )
    block = table(rows, warmup_s, load_before, load_after)
    if args.page:
        fill_page(block)
    print(block)


if __name__ == "__main__":
    main()
