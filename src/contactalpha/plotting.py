"""Shared figure helpers: one look for every figure, and atomic PNG + PDF output.

Every figure script of the workflow does ``fig = ...; save_figure(fig, [png, pdf])``.
"""

from contextlib import contextmanager
from pathlib import Path

import matplotlib

matplotlib.use("agg")  # batch jobs: no display, whatever the environment says

import matplotlib.pyplot as plt  # noqa: E402

from .io import write_atomic  # noqa: E402

# House style, applied on top of the repository's matplotlibrc.
STYLE = {
    "figure.dpi": 100,
    "savefig.dpi": 200,
    "savefig.bbox": "standard",  # constrained layout already fits; "tight" costs one more draw
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "legend.frameon": False,
    "axes.grid": False,
    "image.cmap": "viridis",
    "pdf.fonttype": 42,  # TrueType in PDFs: text stays editable and searchable
}
# OpenType layout tables (substitutions, positioning, glyph classes) that ``save_figure`` leaves
# out of the font subsets it embeds in PDF (and PS) files.  A PDF places every glyph itself (glyph
# ids and widths in the page's content stream), so no viewer reads them, and the pages are the
# same; but fontTools parses all of DejaVu's to subset them: 0.1 of the 0.18 s per embedded
# font, and a figure's PDF embeds two or three fonts.
PDF_FONT_UNUSED_TABLES = ("GSUB", "GPOS", "GDEF")
# Width of a two-column journal figure, inches.
FULL_WIDTH = 7.0
# Width of a one-column figure, inches.
COLUMN_WIDTH = 3.5


def use_style():
    """Apply ``STYLE`` to matplotlib's global settings."""
    plt.rcParams.update(STYLE)


def new_figure(ncols=1, nrows=1, *, width=FULL_WIDTH, aspect=0.42, **kwargs):
    """A styled ``(fig, axes)`` pair; ``aspect`` is height over width of the whole figure."""
    use_style()
    kwargs.setdefault("layout", "constrained")
    return plt.subplots(nrows, ncols, figsize=(width, width * aspect), **kwargs)


@contextmanager
def lean_pdf_fonts():
    """Within this block, fonts embedded in PDFs leave out ``PDF_FONT_UNUSED_TABLES``.

    Matplotlib subsets each font with fontTools' default options, which it does not expose;
    this extends fontTools' default list of dropped tables (``subset.Options``) and restores it
    on exit.  ``tests/paper/test_surface.py`` checks both, and that the pages are the same.
    """
    from fontTools import subset

    saved = subset.Options._drop_tables_default
    subset.Options._drop_tables_default = [*saved, *PDF_FONT_UNUSED_TABLES]
    try:
        yield
    finally:
        subset.Options._drop_tables_default = saved


def save_figure(fig, paths, *, close=True):
    """Write ``fig`` to each path (format from the suffix: .png, .pdf, .svg) atomically.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    paths : path-like or sequence of path-like
    close : bool
        Close the figure afterwards, freeing its memory.
    """
    if isinstance(paths, str | Path):
        paths = [paths]
    with lean_pdf_fonts():
        for path in paths:
            fmt = Path(path).suffix.lstrip(".").lower()
            if not fmt:
                valid = "a name ending in .png, .pdf, .svg"
                raise ValueError(f"path = {str(path)!r} has no suffix; valid: {valid}")
            write_atomic(path, lambda tmp, fmt=fmt: fig.savefig(tmp, format=fmt))
            if fig.get_layout_engine() is not None:
                # The first format placed the axes (constrained layout, in figure fractions, so
                # the same at any dpi); the others keep that placement instead of solving it
                # again, about a sixth of the time of a (png, pdf) pair.
                fig.set_layout_engine("none")
    if close:
        plt.close(fig)
    return [Path(p) for p in paths]
