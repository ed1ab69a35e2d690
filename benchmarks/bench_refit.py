"""Benchmark: the Eq. 40 refit stage (rule fit_refit), new path against the old one (issue 14, item 6).

Run: ``python benchmarks/bench_refit.py`` (``--surface FILE``, default ``results/surface.h5``,
else the default grid is solved first; ``--quick`` fits every 2nd row and column of it;
``--out FILE`` for JSON).  Set ``OPENBLAS_NUM_THREADS=1``: the fits' SVDs are about 12x slower
with 2 OpenBLAS threads on a 2-core box.
Prints, measured in this run on the same surface, the CPU seconds of:
- old: each reading's Eq. 40 fit by continuation on all points and the per-section Eq. 39 fits,
  with scipy's 2-point finite-difference Jacobians (the path before issue 14, except that the
  sections' third start already runs only when the first two disagree: 15.3 s with all three);
- new: the main refit by continuation and the per-section fits with exact Jacobians, the other
  readings from the main refit's second term within ``fit.READING_MAX_NFEV`` evaluations
  (``fit.fit_eq40_alternative``);
- the ratio old / new per part and in all, and the whole ``refit_report`` (new path, with the
  restitution errors through the engine, whose kernels are loaded first and timed apart), in
  one process and with ``workers=2`` (wall time, and CPU of this process and of the workers);
and how far the new main refit is from the old one, in its standard errors.
"""

import argparse
import json
import os
import platform
import resource
import time
from pathlib import Path

import numpy as np


def cpu(fn):
    """(result, CPU seconds) of ``fn()``."""
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def load_or_solve(path):
    """The surface at ``path``, or the default grid's solved now (config.yaml) if there is none."""
    from contactalpha.io import load_surface

    if path.is_file():
        return load_surface(path), str(path)
    import yaml

    from contactalpha.paper.surface.compute import compute_surface, grid_from_config
    from contactalpha.provenance import PACKAGE_DIR

    section = yaml.safe_load((PACKAGE_DIR.parents[1] / "config.yaml").read_text())["surface"]
    eps, xi = grid_from_config(section)
    return compute_surface(eps, xi, **section["solver"]), "default grid, solved in this run"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--surface", type=Path, default=Path("results/surface.h5"))
    p.add_argument("--quick", action="store_true")
    p.add_argument("--out", type=Path)
    args = p.parse_args(argv)

    from contactalpha.engine.driver import impact
    from contactalpha.models import shen
    from contactalpha.paper.fit import compute as fit
    from contactalpha.paper.fit import report as fit_report

    ds, source = load_or_solve(args.surface)
    if args.quick:
        ds = ds.isel(epsilon=slice(None, None, 2), xi=slice(None, None, 2))
    blas = os.environ.get("OPENBLAS_NUM_THREADS", "unset")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, OPENBLAS_NUM_THREADS={blas}")
    print(f"surface: {source}, {ds.sizes['epsilon']} x {ds.sizes['xi']}")
    _, warm = cpu(lambda: impact(np.array([1.0]), np.array([0.2])))
    print(f"engine kernels loaded (compile or cache): {warm:.2f} s CPU")

    main_reading, others = shen.BEST_READING, [r for r in shen.READINGS if r != shen.BEST_READING]
    rows = {}
    old_main, rows["main refit (old)"] = cpu(
        lambda: fit.fit_eq40_surface(ds, main_reading, jacobian="2-point")
    )
    new_main, rows["main refit (new)"] = cpu(lambda: fit.fit_eq40_surface(ds, main_reading))
    old_rest = [cpu(lambda r=r: fit.fit_eq40_surface(ds, r, jacobian="2-point")) for r in others]
    new_rest = [cpu(lambda r=r: fit.fit_eq40_alternative(ds, r, new_main)) for r in others]
    rows["other readings (old)"] = sum(t for _, t in old_rest)
    rows["other readings (new)"] = sum(t for _, t in new_rest)
    _, rows["Eq. 39 sections (old)"] = cpu(lambda: fit.fit_eq39_slices(ds, jacobian="2-point"))
    _, rows["Eq. 39 sections (new)"] = cpu(lambda: fit.fit_eq39_slices(ds))
    _, report_cpu = cpu(lambda: fit_report.refit_report(ds))
    wall, children = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    _, pooled_cpu = cpu(lambda: fit_report.refit_report(ds, workers=2))
    wall = time.perf_counter() - wall
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - children

    for name, t in rows.items():
        print(f"{name:24s} {t:8.2f} s CPU")
    for r, (f, t), (g, u) in zip(others, old_rest, new_rest, strict=True):
        print(
            f"  {r:9s} old {t:6.2f} s, RMS {f.rms:.4g}, converged {f.converged}; "
            f"new {u:6.2f} s, RMS {g.rms:.4g}, converged {g.converged}"
        )
    parts = ("main refit", "other readings", "Eq. 39 sections")
    old = sum(rows[f"{k} (old)"] for k in parts)
    new = sum(rows[f"{k} (new)"] for k in parts)
    for k in parts:
        print(f"ratio old / new, {k}: {rows[f'{k} (old)'] / rows[f'{k} (new)']:.1f}")
    print(f"ratio old / new, all fits: {old / new:.1f} ({old:.1f} s -> {new:.1f} s CPU)")
    print(f"refit_report (new path, restitution errors included): {report_cpu:.2f} s CPU")
    print(
        f"refit_report, 2 worker processes: {wall:.2f} s wall, {pooled_cpu:.2f} s CPU here "
        f"+ {children:.2f} s in the workers (a busy box gives no speed-up)"
    )
    off = np.abs(new_main.x - old_main.x) / old_main.se
    print(f"main refit, new - old: max {np.nanmax(off):.2g} SE ({new_main.names[int(np.nanargmax(off))]})")
    if args.out:
        result = {
            "surface": source,
            "grid": [int(ds.sizes["epsilon"]), int(ds.sizes["xi"])],
            "cpu_s": rows,
            "ratio_all_fits": old / new,
            "refit_report_cpu_s": report_cpu,
            "refit_report_2_workers": {"wall_s": wall, "cpu_s": pooled_cpu, "worker_cpu_s": children},
            "main_refit_max_diff_in_se": float(np.nanmax(off)),
        }
        args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
