"""Shared figure helpers: one look for every figure, and atomic PNG + PDF output.

Every figure script of the workflow does ``fig = ...; save_figure(fig, [png, pdf])``.
"""

from contextlib import contextmanager
from pathlib import Path

import matplotlib

matplotlib.use("agg")  # batch jobs: no display, whatever the environment says

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402

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
    plt.rcParams.update(STYLE)  # type: ignore[arg-type]  # stubs type the keys as a Literal of names


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
    formats = [Path(path).suffix.lstrip(".").lower() for path in paths]
    for path, fmt in zip(paths, formats, strict=True):
        if not fmt:
            raise ValueError(f"path = {str(path)!r} has no suffix; valid: a name ending in .png, .pdf, .svg")
    if formats and formats[0] == "png":
        _place_axes_for_png(fig)
    with lean_pdf_fonts():
        for path, fmt in zip(paths, formats, strict=True):
            write_atomic(path, lambda tmp, fmt=fmt: fig.savefig(tmp, format=fmt))
            # The first format placed the axes (constrained layout, in figure fractions, so the
            # same at any dpi); the others keep that placement.
            _drop_layout_engine(fig)
    if close:
        plt.close(fig)
    return [Path(p) for p in paths]


def _place_axes_for_png(fig):
    """Solve ``fig``'s layout as ``savefig`` of a PNG would, and keep it (no engine left).

    For a figure with a layout engine, ``savefig`` draws the whole figure once without output
    only to run the engine, and then again for real.  Running the engine directly, with the Agg
    renderer at the saving dpi that the dry draw would use, places the axes the same (the same
    PNG and PDF bytes, tests/paper/test_surface.py) without that draw: about 0.25 of the 1.5 s of
    a ball figure's PNG here.  Other canvases keep ``savefig``'s own way.
    """
    engine = fig.get_layout_engine()
    if engine is None or not fig.axes or not isinstance(fig.canvas, FigureCanvasAgg):
        return
    dpi = plt.rcParams["savefig.dpi"]
    saved, fig.dpi = fig.dpi, (getattr(fig, "_original_dpi", fig.dpi) if dpi == "figure" else dpi)
    try:
        engine.execute(fig)
    finally:
        fig.dpi = saved
    _drop_layout_engine(fig)


def _drop_layout_engine(fig):
    """Remove ``fig``'s layout engine, keeping the axes where they are.

    No engine at all, not ``"none"``: Matplotlib's placeholder for "none" still costs every
    later ``savefig`` a whole dry draw before the real one (it runs one for any engine), about
    0.3 of the 1.4 s of a ball figure's PDF here, for the same bytes.
    """
    if fig.get_layout_engine() is None:
        return
    with plt.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        fig.set_layout_engine(None)
