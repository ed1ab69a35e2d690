import numpy as np
import pytest

from contactalpha.baselines.reference import impact_scipy
from contactalpha.engine.codes import END_STATES
from contactalpha.engine.exact import restitution_exact
from contactalpha.paper.fig9.compute import (
    deviation_table,
    fig9_statements,
    max_deviation,
    nonseparation_mask,
    post_vs_pre,
)
from contactalpha.paper.statements import FAILS, HOLDS, NOT_CHECKED, PARTLY, statements_markdown, verdict

EPS = np.array([0.05, 0.3, 0.6, 0.95])


@pytest.fixture(scope="module")
def ds():
    return post_vs_pre(["hunt_crossley", "hu_guo", "exact"], [0.0, 0.227, 0.91], EPS)


def test_exact_model_delivers_what_it_is_asked_for(ds):
    post = ds.eps_post.sel(model="exact")
    np.testing.assert_allclose(post, np.broadcast_to(EPS, post.shape), atol=1e-6)


def test_post_restitution_is_an_impact_with_the_models_alpha(ds):
    # Hu & Guo's closed form, written out here, and the SciPy oracle's impact (not the engine's)
    a = 3 * (1 - 0.3) / (2 * 0.3)
    assert float(ds.alpha.sel(model="hu_guo", xi=0.227, eps_pre=0.3)) == pytest.approx(a, rel=1e-15)
    ref = impact_scipy(a, 0.227, rtol=1e-12, atol=1e-14)
    assert float(ds.eps_post.sel(model="hu_guo", xi=0.227, eps_pre=0.3)) == pytest.approx(ref.eps, abs=1e-10)
    assert END_STATES[int(ds.state.sel(model="hu_guo", xi=0.227, eps_pre=0.3))] == ref.state


def test_hunt_crossley_over_restitutes_at_low_eps(ds):
    dev, where = max_deviation(ds)
    assert float(dev.sel(model="hunt_crossley", xi=0.0)) > 0.3
    assert float(where.sel(model="hunt_crossley", xi=0.0)) == 0.05
    assert "| Hunt–Crossley |" in deviation_table(ds)


def test_non_separating_ends_are_marked(ds):
    mask = nonseparation_mask(ds)
    state = ds.state.sel(model="exact", xi=0.91).values
    assert mask.sel(model="exact", xi=0.91).values.tolist() == [s != 1 for s in state]
    assert not mask.sel(xi=0.0).any()  # without a load every impact separates


def test_statements_carry_verdicts(ds):
    st = fig9_statements(ds, new="hu_guo", reference="exact")
    assert all(s.verdict in ("holds", "partly", "does not hold") for s in st)
    fixed = [s for s in st if "fixed when" in s.claim][0]
    assert fixed.verdict == "holds"
    # At xi = 0 the post-impact eps of a model is the exact unloaded relation at its alpha (no
    # integrator): the claim's evidence and verdict must be those numbers'.
    low = EPS[EPS <= 0.3]
    hc = np.max(abs(restitution_exact(1.5 * (1 - low)) - low))
    hg = np.max(abs(restitution_exact(1.5 * (1 - low) / low) - low))
    (row,) = [s for s in st if s.claim.startswith("Fig. 9(a, b)")]
    assert f"Hunt–Crossley ξ=0: {hc:.3f}" in row.evidence and f"Hu–Guo ξ=0: {hg:.3f}" in row.evidence
    assert row.verdict == verdict([hc > 0.05, hg > 0.05]) == PARTLY  # 0.451 and 0.029


def test_no_evidence_is_not_checked_never_holds():
    assert verdict([]) == NOT_CHECKED
    assert verdict([True, True]) == HOLDS and verdict([True, False]) == PARTLY and verdict([False]) == FAILS


def test_claims_whose_panels_or_models_are_absent_are_not_checked(ds):
    # Only the xi = 0.91 panel and no reference model: every claim about xi <= 0.016 or about
    # end states against the exact alpha lacks its data.
    st = fig9_statements(
        ds.sel(xi=[0.91], model=["hunt_crossley", "hu_guo"]), new="hu_guo", reference="exact"
    )
    by_claim = {s.claim[:20]: s for s in st}
    assert by_claim["Fig. 9(a, b): classi"].verdict == NOT_CHECKED
    assert "ξ = 0 or 0.016" in by_claim["Fig. 9(a, b): classi"].evidence
    assert by_claim["The incorrect dissip"].verdict == NOT_CHECKED
    assert by_claim["Classical models kee"].verdict == NOT_CHECKED  # one panel cannot show alpha is fixed
    assert by_claim["Fig. 9(e, f): fixed "].verdict in (HOLDS, PARTLY, FAILS)
    text = statements_markdown(st, "Fig. 9")
    assert f"{sum(s.verdict == NOT_CHECKED for s in st)} not checked" in text
    # |post − pre| in a criterion must not split the table's cells: every row has 5 columns.
    rows = [line for line in text.splitlines() if line.startswith("| ") and line[2].isdigit()]
    assert rows and all(line.replace("\\|", "").count("|") == 6 for line in rows)


def test_fig9_legend_stays_off_the_panels_and_crosses_leave_the_exact_line_visible():
    from contactalpha.paper.fig9.figures import MARKER_SPACING, fig9

    eps = np.round(np.arange(0.02, 1.0, 0.02), 2)
    data = post_vs_pre(["hunt_crossley", "exact"], [0.0, 0.91], eps)
    fig = fig9(data)
    fig.canvas.draw()
    (legend,) = fig.legends
    box = legend.get_window_extent()
    assert not any(box.overlaps(ax.get_window_extent()) for ax in fig.axes if ax.get_visible())
    assert "impact ends without separation" in [t.get_text() for t in legend.get_texts()]
    assert not fig.texts and fig._suptitle is None  # no in-figure "Fig. 9" title
    ax = fig.axes[1]  # xi = 0.91: the exact impacts end without separation below eps_b
    (exact,) = [ln for ln in ax.get_lines() if ln.get_label() == "exact"]
    crosses = [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
    assert crosses and all(c.get_zorder() < exact.get_zorder() for c in crosses)
    stuck = int(nonseparation_mask(data).sel(model="exact", xi=0.91).sum())
    for c in crosses:
        assert np.all(np.diff(c.get_xdata()) >= MARKER_SPACING - 1e-12)
    (mine,) = [c for c in crosses if c.get_color() == exact.get_color()]
    assert 0 < len(mine.get_xdata()) < stuck
