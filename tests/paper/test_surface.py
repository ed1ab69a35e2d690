import copy
import io
import logging
import re
import zlib
from pathlib import Path

import numpy as np
import pytest
import yaml

import contactalpha
from contactalpha.engine.codes import END_STATES, STATE_CODES
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL
from contactalpha.engine.solver import EPS_TOL
from contactalpha.io import load_surface, load_surface_chunk, write_dataset_atomic, write_text_atomic
from contactalpha.models import shen
from contactalpha.paper.surface.compute import (
    SOLVER_NAME,
    VARIABLES,
    check_surface_config,
    chunk_columns,
    compute_chunk,
    compute_surface,
    grid_from_config,
    log_progress,
    merge_chunks,
    section_regions,
)
from contactalpha.paper.surface.figures import plot_alpha_surface, plot_end_states, plot_section
from contactalpha.paper.surface.report import surface_summary
from contactalpha.plotting import PDF_FONT_UNUSED_TABLES, lean_pdf_fonts, new_figure, save_figure

ROOT = Path(__file__).resolve().parents[2]
# A small grid that crosses every end state and the log-spaced ridge near xi = 0.
EPS = np.array([0.01, 0.05, 0.2, 0.5, 0.9])
XI = np.array([0.0, 1e-4, 1e-3, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99])


@pytest.fixture(scope="module")
def surface():
    return compute_surface(EPS, XI)


@pytest.fixture
def default_section():
    return yaml.safe_load((ROOT / "config.yaml").read_text())["surface"]


def bits(a):
    """Float arrays as integers, so NaNs and signed zeros compare too."""
    a = np.asarray(a)
    return a.view(np.int64) if a.dtype == np.float64 else a


# --- grid from config -------------------------------------------------------------------


def test_default_grid_is_the_paper_grid_plus_log_refinement(default_section):
    eps, xi = grid_from_config(default_section)
    assert eps.size == 99 and eps[0] == 0.01 and eps[-1] == 0.99
    assert eps[36] == 0.37  # rounded to the double nearest the decimal, not 0.01 + 36 * 0.01
    assert np.all(np.diff(eps) > 0) and np.all(np.diff(xi) > 0)
    log = default_section["xi"]["log_range"]
    expected_small = 1 + log["num"] - 1  # xi = 0 and the log points below 0.01
    assert np.sum(xi < 0.01) == expected_small
    assert xi[0] == 0.0 and xi[1] == pytest.approx(1e-5) and xi[-1] == 0.99
    assert 0.2 in xi and 0.01 in xi
    assert xi.size == 100 + log["num"] - 1  # 0.01 is in both ranges, merged once


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (lambda s: s["xi"].update(values=[0.3, 0.2]), "surface.xi.values"),
        (lambda s: s["epsilon"].update(values=[0.5, 0.5]), "surface.epsilon.values"),
        (lambda s: s["epsilon"]["range"].update(step=0.03), "surface.epsilon.range"),
        (lambda s: s["xi"]["range"].update(start=0.5, stop=0.2), "surface.xi.range"),
        (lambda s: s["xi"]["log_range"].update(start=0.1, stop=0.01), "surface.xi.log_range"),
        (lambda s: s["epsilon"].update(range=None), "surface.epsilon is empty"),
        (lambda s: s["epsilon"].update(values=[0.0, 0.5]), "surface.epsilon has 0.0"),
        (lambda s: s["xi"].update(values=[0.5, 1.0]), "surface.xi has 1.0"),
        (lambda s: s["figures"].update(section_xi=0.205), "surface.figures.section_xi"),
    ],
)
def test_bad_grid_names_the_key(default_section, edit, key):
    section = copy.deepcopy(default_section)
    edit(section)
    with pytest.raises(ValueError, match="valid") as err:
        check_surface_config(section)
    assert key in str(err.value)


@pytest.mark.parametrize(
    ("surface_section", "path"),
    [
        ({"epsilon": {"range": {"start": 0.0, "stop": 0.5, "step": 0.1}}}, "['epsilon']['range']['start']"),
        ({"xi": {"values": [0.2, 1.0]}}, "['xi']['values'][1]"),
        ({"xi": {"values": [0.2, 0.2]}}, "['xi']['values']"),
        ({"solver": {"rtol": -1e-10}}, "['solver']['rtol']"),
        ({"solver": {"tol": 0.0}}, "['solver']['tol']"),
        ({"chunk": 3}, "'chunk' was unexpected"),
    ],
)
def test_schema_rejects_bad_config_naming_the_key(surface_section, path):
    from snakemake.exceptions import WorkflowError
    from snakemake.utils import validate

    with pytest.raises(WorkflowError) as err:
        validate({"surface": surface_section}, str(ROOT / "workflow/schemas/config.schema.yaml"))
    assert path in str(err.value)


def test_schema_fills_defaults_equal_to_config_yaml(default_section):
    from snakemake.utils import validate

    config = {}
    validate(config, str(ROOT / "workflow/schemas/config.schema.yaml"))
    assert config["surface"] == default_section


def test_chunks_are_strided_slices_that_cover_the_grid():
    xi = np.arange(10.0) / 10
    parts = [chunk_columns(xi, k, 3) for k in range(3)]
    np.testing.assert_array_equal(parts[1], [0.1, 0.4, 0.7])
    np.testing.assert_array_equal(np.sort(np.concatenate(parts)), xi)
    with pytest.raises(ValueError, match=r"chunk = 3 is outside the valid range \[0, 2\]"):
        chunk_columns(xi, 3, 3)


# --- the surface ------------------------------------------------------------------------


def test_surface_matches_solve_alpha_point_by_point(surface):
    e, x = np.meshgrid(EPS, XI, indexing="ij")
    sol = contactalpha.solve_alpha(e, x)
    assert np.array_equal(bits(surface.alpha.values), bits(sol.alpha))
    assert np.array_equal(surface.x_max.values, sol.x_max)
    assert np.array_equal(surface.steps.values, sol.steps)
    names = np.vectorize(lambda c: END_STATES[c])(surface.state.values)
    np.testing.assert_array_equal(names, sol.state)
    assert np.all(surface.status.values == 0)
    np.testing.assert_allclose(surface.eps_reached.values, e, atol=1e-11)


def test_surface_layout_units_and_codes(surface):
    assert surface.alpha.dims == ("epsilon", "xi")
    assert set(VARIABLES) <= set(surface.data_vars)
    for name in VARIABLES:
        assert surface[name].attrs["units"] and surface[name].attrs["long_name"]
    assert surface.state.dtype == np.int8 and surface.status.dtype == np.int8
    assert "3: creep" in surface.state.attrs["legend"] and "0: ok" in surface.status.attrs["legend"]
    lam = surface.x_end / surface.x_max
    np.testing.assert_array_equal(surface["lambda"].values, lam.values)
    # The grid crosses all three end states that the paper's domain holds.
    found = set(np.unique(surface.state.values))
    assert {STATE_CODES["separation"], STATE_CODES["nonseparation"], STATE_CODES["creep"]} <= found
    # xi = 0 separates always and matches the exact relation.
    np.testing.assert_allclose(surface.alpha.sel(xi=0.0), contactalpha.alpha_exact(EPS), rtol=1e-12)
    attrs = surface.attrs
    assert (attrs["tol"], attrs["rtol"], attrs["atol"], attrs["max_steps"]) == (
        EPS_TOL,
        RTOL,
        ATOL,
        MAX_STEPS,
    )
    assert attrs["solver"] == SOLVER_NAME and attrs["contactalpha_version"] == contactalpha.__version__
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?|unknown", attrs["git_commit"])
    assert re.fullmatch(
        r"\S+Z compute_surface on 5 x 14 points in [0-9.]+ s \(contactalpha .+\)", attrs["history"]
    )
    assert 0 < attrs["compute_seconds"] == pytest.approx(attrs["finished"] - attrs["started"], abs=1e-6)
    assert surface.x_max.attrs["units"] == "delta_star" and surface.alpha.attrs["units"] == "1"


def test_compute_surface_keeps_the_grid_and_rejects_bad_ones():
    eps = [0.123456789012345678, 0.5]
    ds = compute_surface(eps, [0.3])
    assert ds.epsilon.values[0] == eps[0]  # only config grids are rounded, not the caller's values
    with pytest.raises(ValueError, match=r"xi is not strictly increasing: 0.1 comes after 0.3"):
        compute_surface([0.5], [0.3, 0.1])
    with pytest.raises(ValueError, match=r"eps = -0.1 is outside the valid range"):
        compute_surface([-0.1], [0.3])


def test_failed_points_are_flagged_not_numbers():
    ds = compute_surface([0.05, 0.5], [0.0, 0.3], max_steps=5)
    loaded = ds.sel(xi=0.3)
    assert np.all(loaded.status.values != 0)
    assert np.all(np.isnan(loaded.alpha.values)) and np.all(np.isnan(loaded["lambda"].values))
    # xi = 0 is exact, needs no steps, and is not affected by the step budget.
    assert np.all(ds.status.sel(xi=0.0).values == 0)
    text = surface_summary(ds.assign_attrs(wall_seconds=0.0), [ds.assign_attrs(chunk=0)])
    assert "2 of 4 points failed" in text and "step limit exceeded" in text


def test_one_chunk_equals_seven_chunks_bit_for_bit(surface, tmp_path):
    paths, seconds = [], []
    for k in range(7):
        path = tmp_path / f"chunk_{k}.h5"
        chunk = compute_chunk(EPS, XI, k, 7)
        write_dataset_atomic(chunk, path)
        paths.append(path)
        seconds.append(chunk.attrs["compute_seconds"])
    merged = merge_chunks(paths[::-1], config={"surface": {"chunks": 7}})
    np.testing.assert_array_equal(merged.xi.values, XI)
    for name in surface.data_vars:
        assert merged[name].dtype == surface[name].dtype, name
        assert np.array_equal(bits(merged[name].values), bits(surface[name].values)), name
        assert merged[name].attrs == surface[name].attrs
    assert merged.attrs["chunks"] == 7
    assert merged.attrs["compute_seconds"] == pytest.approx(sum(seconds), rel=1e-12)  # CPU of all chunks
    assert len(merged.attrs["history"].splitlines()) == 8
    assert '"chunks": 7' in merged.attrs["config"]


def test_merge_rejects_incomplete_or_mixed_chunks(tmp_path):
    paths = []
    for k, tol in ((0, 1e-12), (1, 1e-12), (2, 1e-10)):
        paths.append(tmp_path / f"c{k}.h5")
        write_dataset_atomic(compute_chunk([0.5], XI[:6], k, 3, tol=tol), paths[-1])
    with pytest.raises(ValueError, match="do not make up one run of 3"):
        merge_chunks(paths[:2])
    with pytest.raises(ValueError, match="do not make up one run of 3"):
        merge_chunks([paths[0], paths[0], paths[1]])
    with pytest.raises(ValueError, match="chunks disagree on tol"):
        merge_chunks(paths)


def test_progress_reports_every_block_and_the_end(caplog):
    calls = []
    compute_surface([0.3, 0.6], XI, progress=lambda d, t, s: calls.append((d, t, s)))
    done = [c[0] for c in calls]
    assert done == sorted(done) and done[-1] == calls[-1][1] == 2 * XI.size
    logger = logging.getLogger("test_progress")
    with caplog.at_level(logging.INFO, logger="test_progress"):
        report = log_progress(logger, "chunk 1/1", every=1e9)
        report(1, 10, 0.5)  # the first block is logged
        report(5, 10, 1.0)  # throttled
        report(10, 10, 2.0)  # the end is always logged
    assert len(caplog.records) == 2
    assert "chunk 1/1: 10/10 points, 5 points/s" in caplog.records[1].getMessage()


# --- files ------------------------------------------------------------------------------


def test_round_trip_keeps_data_and_attributes(surface, tmp_path):
    path = write_dataset_atomic(surface, tmp_path / "surface.h5")
    back = contactalpha.load_surface(path)
    assert back.attrs == surface.attrs
    for name in list(surface.data_vars) + list(surface.coords):
        assert back[name].dtype == surface[name].dtype, name
        assert np.array_equal(bits(back[name].values), bits(surface[name].values)), name
        assert back[name].attrs == surface[name].attrs, name
    assert list(tmp_path.iterdir()) == [path]


def test_interrupted_write_leaves_the_old_file_and_no_temporary(surface, tmp_path):
    path = write_text_atomic(tmp_path / "surface.h5", "old")
    bad = surface.assign_attrs(unwritable={"a dict": "is no netCDF attribute"})
    with pytest.raises(TypeError):
        write_dataset_atomic(bad, path)
    assert path.read_text() == "old"
    assert list(tmp_path.iterdir()) == [path]


def test_load_surface_rejects_other_files(surface, tmp_path):
    path = write_dataset_atomic(surface[["steps"]], tmp_path / "other.h5")
    with pytest.raises(ValueError, match="is not an alpha surface"):
        load_surface(path)


def test_load_surface_rejects_a_chunk_and_load_surface_chunk_reads_it(surface, tmp_path):
    chunk = write_dataset_atomic(surface.assign_attrs(chunk=1, chunks=2), tmp_path / "chunk_1.h5")
    with pytest.raises(ValueError, match=r"chunk_1.h5 is chunk 1 of 2, not a whole surface; valid:"):
        load_surface(chunk)
    assert load_surface_chunk(chunk).attrs["chunk"] == 1
    whole = write_dataset_atomic(surface, tmp_path / "surface.h5")
    with pytest.raises(ValueError, match="is not a surface chunk"):
        load_surface_chunk(whole)


@pytest.mark.parametrize(
    "damage, message",
    [
        (lambda ds: ds.assign(alpha=ds.alpha.astype(str)), "alpha has dtype <U"),
        (lambda ds: ds.isel(xi=[1, 0, 2]), "coordinate xi is not strictly increasing"),
        (lambda ds: ds.isel(epsilon=[0, 0, 1]), "coordinate epsilon is not strictly increasing"),
        (
            lambda ds: ds.assign_coords(xi=ds.xi.astype(str)),
            "coordinate xi is not strictly increasing floats",
        ),
    ],
)
def test_load_surface_rejects_text_alpha_and_unsorted_or_repeated_coordinates(
    surface, tmp_path, damage, message
):
    path = write_dataset_atomic(damage(surface), tmp_path / "surface.h5")
    with pytest.raises(ValueError, match=message):
        load_surface(path)


# --- Fig. 5 helpers, summary and figures ------------------------------------------------


def test_paper_equations_and_regions():
    np.testing.assert_allclose(shen.eq25([0.5, 0.2]), [1.5, 6.0])
    np.testing.assert_allclose(shen.eq26(0.1, tau=0.01, sigma=0.011, beta=0.113), np.exp(-1.1) / 0.113)
    states = [STATE_CODES[n] for n in ("creep", "no_restitution", "nonseparation", "separation", "failed")]
    np.testing.assert_array_equal(section_regions(states), [1, 1, 2, 3, 0])


def test_summary_counts_and_largest_alpha(surface):
    ds = surface.assign_attrs(wall_seconds=1.0)
    text = surface_summary(
        ds, [ds.assign_attrs(chunk=0)], section_xi=0.2, eq26=dict(tau=0.01, sigma=0.011, beta=0.113)
    )
    for code, name in END_STATES.items():
        if code:
            count = int(np.sum(surface.state.values == code))
            assert f"| {name} | {count} |" in text
    top = float(surface.alpha.max())
    assert f"alpha = {top:.6g} at eps = 0.01" in text
    assert "0 of 70 points failed" in text
    assert "| epsilon | 5 | 0.01 | 0.9 |" in text
    assert "## Section xi = 0.2" in text


def test_fig4_draws_the_surface_on_a_log_scale_and_marks_failed_points(surface):
    failed = surface.copy(deep=True)
    failed["status"][0, 3] = 1
    failed["alpha"][0, 3] = np.nan
    fig = plot_alpha_surface(failed)
    left, right = fig.axes[:2]
    for ax in (left, right):
        mesh = ax.collections[0]
        np.testing.assert_array_equal(
            np.ma.filled(mesh.get_array(), np.nan).ravel(), failed.alpha.values.ravel()
        )
        assert mesh.norm.vmin == np.nanmin(failed.alpha) and mesh.norm.vmax == np.nanmax(failed.alpha)
        (cross,) = [line for line in ax.lines if line.get_label() == "failed"]
        assert (cross.get_xdata()[0], cross.get_ydata()[0]) == (XI[3], EPS[0])
    assert right.get_xscale() == "symlog" and right.get_yscale() == "log"


def test_fig4_contour_labels_lie_inside_their_panels(surface):
    fig = plot_alpha_surface(surface)
    fig.canvas.draw()
    labelled = 0
    for ax in fig.axes[:2]:
        box = ax.get_window_extent()
        for text in ax.texts:
            inner = text.get_window_extent()
            assert box.x0 <= inner.x0 and inner.x1 <= box.x1 and box.y0 <= inner.y0 and inner.y1 <= box.y1
            labelled += 1
    assert labelled >= 2


def test_end_state_map_colours_and_counts_every_state(surface):
    fig = plot_end_states(surface)
    codes = fig.axes[0].collections[0].get_array()
    np.testing.assert_array_equal(np.asarray(codes).ravel(), surface.state.values.ravel())
    legend = {t.get_text() for t in fig.legends[0].get_texts()}
    for code, name in END_STATES.items():
        assert f"{name.replace('_', ' ')} ({int(np.sum(surface.state.values == code))})" in legend


def test_fig5_draws_the_section_eq25_eq26_and_their_ratios(surface):
    fig = plot_section(surface, 0.2, tau=0.01, sigma=0.011, beta=0.113)
    top, bottom = fig.axes
    exact, eq25, eq26 = top.lines[:3]
    section = surface.sel(xi=0.2)
    np.testing.assert_array_equal(exact.get_ydata(), section.alpha.values)
    np.testing.assert_allclose(eq25.get_ydata(), 1.5 * (1 - EPS) / EPS, rtol=1e-15)
    np.testing.assert_allclose(eq26.get_ydata(), np.exp(-((EPS + 0.01) ** 2) / 0.011) / 0.113, rtol=1e-15)
    np.testing.assert_allclose(bottom.lines[0].get_ydata(), section.alpha.values / (1.5 * (1 - EPS) / EPS))
    names = [t.get_text() for t in top.texts]
    want = [{1: "I", 2: "II", 3: "III"}[r] for r in section_regions(section.state.values)]
    assert names == [n for i, n in enumerate(want) if i == 0 or n != want[i - 1]]


def test_save_figure_writes_by_suffix_and_rejects_none(tmp_path):
    fig, ax = new_figure(width=2.0)
    ax.plot([0, 1], [0, 1])
    written = save_figure(fig, [tmp_path / "f.png", tmp_path / "f.pdf"])
    assert written[0].read_bytes()[:4] == b"\x89PNG" and written[1].read_bytes()[:4] == b"%PDF"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.pdf", "f.png"]
    with pytest.raises(ValueError, match="has no suffix"):
        save_figure(new_figure()[0], tmp_path / "nosuffix")


def test_save_figure_places_the_axes_once_for_every_format(tmp_path):
    # Constrained layout is solved for the first format; later formats keep that placement.
    def figure():
        fig, (a, b) = new_figure(2, width=4.0)
        b.set_ylabel("a long label\nover two lines")
        fig.colorbar(b.imshow([[0, 1], [2, 3]]), ax=b)
        return fig

    alone = figure()
    save_figure(alone, tmp_path / "alone.png", close=False)
    placed = [ax.get_position().bounds for ax in alone.axes]
    fig = figure()
    save_figure(fig, [tmp_path / "f.png", tmp_path / "f.pdf", tmp_path / "f.svg"], close=False)
    assert [ax.get_position().bounds for ax in fig.axes] == placed
    assert placed[0] != (0.125, 0.11, 0.3522727272727273, 0.77)  # not matplotlib's default grid
    assert fig.get_layout_engine() is None


def test_save_figure_draws_later_formats_once_with_the_same_bytes(tmp_path, monkeypatch):
    # Matplotlib's placeholder engine ("none") would cost every later format a dry draw first.
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "0")  # PDFs without today's date, to compare bytes

    def figure():
        fig, (a, b) = new_figure(2, width=4.0)
        a.plot([0, 1], [0, 2], label="ε = 0.5")
        a.legend()
        fig.colorbar(b.imshow([[0, 1], [2, 3]]), ax=b)
        draws = []
        real_draw = fig.draw
        fig.draw = lambda renderer: draws.append(type(renderer).__name__) or real_draw(renderer)
        return fig, draws

    fig, draws = figure()
    save_figure(fig, [tmp_path / "f.png", tmp_path / "f.pdf"], close=False)
    assert draws == ["RendererAgg", "MixedModeRenderer"]  # no dry draw for the layout
    old, _ = figure()  # the placement kept the old way, behind the placeholder
    old.savefig(tmp_path / "old.png")
    old.set_layout_engine("none")
    with lean_pdf_fonts():
        old.savefig(tmp_path / "old.pdf")
    assert (tmp_path / "f.pdf").read_bytes() == (tmp_path / "old.pdf").read_bytes()
    assert (tmp_path / "f.png").read_bytes() == (tmp_path / "old.png").read_bytes()


def _pdf_objects(data):
    """{number: (dictionary bytes, decompressed stream or b"")} of the objects of a Matplotlib PDF."""
    out = {}
    for m in re.finditer(rb"(?m)^(\d+) 0 obj\b(.*?)\bendobj", data, re.S):
        head, is_stream, body = m.group(2).partition(b"stream\n")
        if is_stream:
            body = body[: body.rindex(b"endstream")]
            body = zlib.decompressobj().decompress(body) if b"/FlateDecode" in head else body
        out[int(m.group(1))] = (head, body)
    return out


def test_pdf_fonts_leave_out_only_the_layout_tables_and_the_pages_stay_the_same(tmp_path):
    from fontTools import subset
    from fontTools.ttLib import TTFont

    defaults = list(subset.Options._drop_tables_default)

    def figure():  # upright and oblique (mathtext) DejaVu, a ligature candidate ("fi"), Greek
        fig, ax = new_figure(width=3.0)
        ax.plot([0, 1], [0, 1], label="first fit δ (µm), ε = 0.5")
        ax.set_title("$x^2$, ξ = 0.1")
        ax.legend()
        return fig

    lean = save_figure(figure(), tmp_path / "lean.pdf")[0].read_bytes()
    assert subset.Options._drop_tables_default == defaults  # restored
    figure().savefig(tmp_path / "full.pdf")  # Matplotlib's own subsets
    full = (tmp_path / "full.pdf").read_bytes()
    fonts = {int(n) for n in re.findall(rb"/FontFile2 (\d+) 0 R", lean)}
    assert len(fonts) >= 2
    a, b = _pdf_objects(lean), _pdf_objects(full)
    assert a.keys() == b.keys()
    # Every object but the font programs and the creation date is the same bytes: the page
    # content, glyph widths, CID-to-glyph maps and ToUnicode maps.
    info = {n for n in a if b"/CreationDate" in a[n][0]}
    assert len(info) == 1
    assert {n for n in a if a[n] != b[n]} - info == fonts
    for n in fonts:
        mine, theirs = TTFont(io.BytesIO(a[n][1])), TTFont(io.BytesIO(b[n][1]))
        assert set(theirs.keys()) - set(mine.keys()) == set(PDF_FONT_UNUSED_TABLES)
        assert set(mine.keys()) < set(theirs.keys()) and mine.getGlyphOrder() == theirs.getGlyphOrder()
        same = [t for t in mine.keys() if t not in ("GlyphOrder", "head")]
        assert all(mine.getTableData(t) == theirs.getTableData(t) for t in same)
