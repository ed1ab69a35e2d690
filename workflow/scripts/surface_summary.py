"""results/summary.md: grid, timings, end-state counts, largest alpha, failed points, the Fig. 5 section.

Settings (snakemake.params.figures): section_xi, eq26 (tau, sigma, beta).
Inputs: surface (results/surface.h5), chunks (its chunk files, for per-chunk timings).
Outputs: the markdown file, written atomically.
"""

from contactalpha.io import load_surface, load_surface_chunk, script_logger, write_text_atomic
from contactalpha.paper.surface.report import surface_summary

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("surface_summary", sm.log[0])
figures = sm.params.figures
text = surface_summary(
    load_surface(sm.input.surface),
    [load_surface_chunk(p) for p in sm.input.chunks],
    section_xi=figures["section_xi"],
    eq26=figures["eq26"],
)
write_text_atomic(sm.output[0], text)
log.info(f"wrote {sm.output[0]}")
