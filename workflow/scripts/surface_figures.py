"""Figs. 4 and 5, the end-state map and results/summary.md: the outputs a rule names.

Each named figure output (fig4, fig5, end_states) is a (png, pdf) pair; one job draws several,
so that they share one Python start-up and one set of imports.
Settings (snakemake.params.figures, for fig5 and summary): section_xi, eq26 (tau, sigma, beta)
(paper.surface.compute.SurfaceFigureSettings).
Inputs: surface (results/surface.h5); chunks (the chunk files, for the summary's timings).
Outputs: the figures and, if named, summary (markdown: grid, timings, end states, failures),
written atomically.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from functools import cache

from contactalpha.config import settings_from
from contactalpha.io import load_surface, load_surface_chunk, script_logger, write_text_atomic
from contactalpha.paper.surface.compute import SurfaceFigureSettings
from contactalpha.paper.surface.figures import plot_alpha_surface, plot_end_states, plot_section
from contactalpha.paper.surface.report import surface_summary
from contactalpha.plotting import save_figure

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("surface_figures", sm.log[0])


@cache
def surface():
    return load_surface(sm.input.surface)


def figures():
    return settings_from(SurfaceFigureSettings, sm.params.figures)


def section():
    return plot_section(surface(), figures().section_xi, **figures().eq26)


DRAW = {
    "fig4": lambda: plot_alpha_surface(surface()),
    "fig5": section,
    "end_states": lambda: plot_end_states(surface()),
}
for name in sm.output.keys():
    if name == "summary":
        chunks = [load_surface_chunk(p) for p in sm.input.chunks]
        text = surface_summary(surface(), chunks, section_xi=figures().section_xi, eq26=figures().eq26)
        write_text_atomic(sm.output.summary, text)
        log.info(f"wrote {sm.output.summary}")
        continue
    paths = list(sm.output[name])
    save_figure(DRAW[name](), paths)
    log.info(f"wrote {' and '.join(paths)}")
