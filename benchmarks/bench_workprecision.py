"""Speed against accuracy (issue 7): work-precision chart, failure maps, scaling, docs/performance.md.

Run (one command; ~15-25 min on 2 cores):

    python benchmarks/bench_workprecision.py            # settings: config.yaml, section bench
    python benchmarks/bench_workprecision.py --quick    # settings: workflow/test-config.yaml (a smoke run)

Writes into ``--out`` (default ``results/bench``): reference.csv, workprecision.csv,
failure_map.csv, failure_counts.csv, scaling.json, summary.md and the figures
workprecision/failure_map/scaling (.png, .pdf); with ``--page`` it also puts
summary.md between the bench markers of docs/performance.md.  The same stages run as the
Snakemake target ``bench`` (``snakemake -c2 bench``).  Every time ratio is
measured against the engine in this same run.
"""

import argparse
import time
from pathlib import Path

import yaml

from contactalpha.config import settings_from
from contactalpha.paper.bench import report as br

ROOT = Path(__file__).resolve().parent.parent


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="tiny settings from workflow/test-config.yaml")
    p.add_argument("--out", type=Path, default=ROOT / "results" / "bench", help="output folder")
    p.add_argument("--page", action="store_true", help="fill the bench block of docs/performance.md")
    p.add_argument(
        "--only",
        choices=["workprecision", "failures", "scaling", "report"],
        default=None,
        help="run one stage (the others' files must exist for 'report')",
    )
    args = p.parse_args(argv)
    config = ROOT / ("workflow/test-config.yaml" if args.quick else "config.yaml")
    settings = settings_from(br.BenchSettings, yaml.safe_load(config.read_text())["bench"])
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()

    def log(msg):
        print(f"[{time.perf_counter() - start:7.1f} s] {msg}", flush=True)

    log(f"settings from {config.relative_to(ROOT)}; machine: {br.machine_info()}")
    if args.only in (None, "workprecision"):
        br.run_workprecision(settings, out / "reference.csv", out / "workprecision.csv", log=log)
    if args.only in (None, "failures"):
        br.run_failures(settings, out / "failure_map.csv", out / "failure_counts.csv", log=log)
    if args.only in (None, "scaling"):
        br.run_scaling(settings, out / "scaling.json", log=log)
    if args.only in (None, "report"):
        br.run_figures(out)
        text = br.run_summary(
            settings,
            out / "reference.csv",
            out / "workprecision.csv",
            out / "failure_counts.csv",
            out / "scaling.json",
            out / "summary.md",
            page=ROOT / "docs" / "performance.md" if args.page else None,
            failure_csv=out / "failure_map.csv",
        )
        print(text)
    log("done")


if __name__ == "__main__":
    main()
