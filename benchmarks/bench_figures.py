"""Benchmark: ``save_figure`` against Matplotlib's own ways, on the ball report's figures.

Run: ``python benchmarks/bench_figures.py`` (``--rounds N``, default 3; ``--ball FILE``, default
``results/ball/first_collision.nc``, written by ``snakemake -c2``).
Draws the bouncing ball's first-collision figures (Figs. 13-21, the ball report's job), in
alternating rounds, and compares two things:

- fonts: each figure as a PDF through ``save_figure`` (its embedded fonts leave out
  ``plotting.PDF_FONT_UNUSED_TABLES``) against ``savefig`` alone (Matplotlib's subsets);
- pairs: each figure as the workflow's (PNG, PDF) pair through ``save_figure`` (the layout solved
  once, no dry draws) against Matplotlib's way of keeping a layout: ``savefig`` of the PNG, the
  engine set to "none", ``savefig`` of the PDF (same lean fonts), which draws the figure 4 times.

Prints the CPU seconds of each round, the best of each, their ratio, and the bytes written.
The files are the same bytes (the pages, for the fonts; ``tests/paper/test_surface.py``).
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
from contactalpha.plotting import lean_pdf_fonts, save_figure


def matplotlib_fonts(fig, paths):
    """The baseline of "fonts": ``savefig`` alone."""
    for path in paths:
        fig.savefig(path)
    plt.close(fig)


def matplotlib_pairs(fig, paths):
    """The baseline of "pairs": the layout kept behind Matplotlib's "none" placeholder."""
    png, pdf = paths
    fig.savefig(png)
    fig.set_layout_engine("none")
    with lean_pdf_fonts():
        fig.savefig(pdf)
    plt.close(fig)


# comparison -> (file suffixes, baseline way of saving)
COMPARISONS = {"fonts": ((".pdf",), matplotlib_fonts), "pairs": ((".png", ".pdf"), matplotlib_pairs)}


def round_cpu(ds, folder, comparison, ours):
    """CPU seconds and bytes of one round: every first-collision figure drawn and saved."""
    suffixes, baseline = COMPARISONS[comparison]
    save = save_figure if ours else baseline
    t, size = time.process_time(), 0
    for kind in FIRST_KINDS:
        for i in range(ds.sizes["force"]):
            fig = plot_first_collision(ds, i, kind, reference=ds.attrs["reference"])
            paths = [Path(folder, f"{kind}{i}_{'ours' if ours else 'base'}{x}") for x in suffixes]
            save(fig, paths)
            size += sum(path.stat().st_size for path in paths)
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
    machine = platform.processor() or platform.machine()
    print(f"machine: {machine}, {os.cpu_count()} cores; {n} figures per round")
    names = {
        "fonts": ("Matplotlib's font subsets", "lean fonts"),
        "pairs": ("Matplotlib's layout", "save_figure"),
    }
    with tempfile.TemporaryDirectory() as folder:
        round_cpu(ds, folder, "pairs", True)  # first use: font caches, imports
        times = {(c, ours): [] for c in COMPARISONS for ours in (False, True)}
        for r in range(args.rounds):
            for comparison in COMPARISONS:
                for ours in (False, True):
                    seconds, size = round_cpu(ds, folder, comparison, ours)
                    times[comparison, ours].append(seconds)
                    name = names[comparison][ours]
                    print(f"round {r + 1}, {comparison}: {name} {seconds:.2f} s CPU, {size} bytes")
    for comparison, (base, ours) in names.items():
        best = {k: min(times[comparison, k]) for k in (False, True)}
        saved = (best[False] - best[True]) / n
        print(
            f"{comparison}: best {base} {best[False]:.2f} s, {ours} {best[True]:.2f} s CPU for {n} figures; "
            f"ratio {best[False] / best[True]:.2f}; saved per figure: {saved:.3f} s"
        )


if __name__ == "__main__":
    main()
