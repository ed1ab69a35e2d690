"""Benchmark: the PDF figures' font subsetting, lean (``plotting.lean_pdf_fonts``) against Matplotlib's own.

Run: ``python benchmarks/bench_figures.py`` (``--rounds N``, default 3; ``--ball FILE``, default
``results/ball/first_collision.nc``, written by ``snakemake -c2``).
Draws the bouncing ball's first-collision figures (Figs. 13-21, the ball report's job) and saves
each as a PDF, in alternating rounds: once through ``save_figure`` (its embedded fonts leave out
``plotting.PDF_FONT_UNUSED_TABLES``) and once with ``savefig`` alone (Matplotlib's subsets, the
baseline). Prints the CPU seconds of each round, the best of each, their ratio, and the bytes
of the PDFs. The pages are the same (``tests/paper/test_surface.py``).
"""

import argparse
import os
import platform
import tempfile
import time
from pathlib import Path

import matplotlib.pyplot as plt

from contactalpha.io import load_dataset
from contactalpha.paper.ball.figures import FIRST_KINDS, plot_first_collision
from contactalpha.plotting import save_figure


def round_cpu(ds, folder, lean):
    """CPU seconds and bytes of one round: every first-collision figure drawn and saved as PDF."""
    t, size = time.process_time(), 0
    for kind in FIRST_KINDS:
        for i in range(ds.sizes["force"]):
            fig = plot_first_collision(ds, i, kind, reference=ds.attrs["reference"])
            path = Path(folder, f"{kind}{i}_{'lean' if lean else 'full'}.pdf")
            if lean:
                save_figure(fig, path)
            else:
                fig.savefig(path)
                plt.close(fig)
            size += path.stat().st_size
    return time.process_time() - t, size


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--ball", default="results/ball/first_collision.nc")
    args = parser.parse_args()
    if args.rounds < 1:
        raise SystemExit(f"--rounds = {args.rounds} is outside the valid range >= 1")
    ds = load_dataset(args.ball)
    n = len(FIRST_KINDS) * ds.sizes["force"]
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs; {n} PDFs per round")
    with tempfile.TemporaryDirectory() as folder:
        round_cpu(ds, folder, lean=True)  # first use: font caches, imports
        times = {True: [], False: []}
        for r in range(args.rounds):
            for lean in (False, True):
                seconds, size = round_cpu(ds, folder, lean)
                times[lean].append(seconds)
                name = "lean" if lean else "Matplotlib"
                print(f"round {r + 1}: {name} fonts {seconds:.2f} s CPU, {size} bytes")
    best = {k: min(v) for k, v in times.items()}
    print(f"best: Matplotlib's subsets {best[False]:.2f} s, lean {best[True]:.2f} s CPU for {n} PDFs")
    saved = (best[False] - best[True]) / n
    print(f"ratio Matplotlib / lean: {best[False] / best[True]:.2f}; saved per PDF: {saved:.3f} s")


if __name__ == "__main__":
    main()
