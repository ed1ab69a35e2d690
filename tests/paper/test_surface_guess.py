"""The surface says which starting guess made it; the solver warns when it cannot use the table."""

import pytest

import contactalpha
from contactalpha.paper.surface.compute import compute_surface, guess_record


def test_surface_records_its_starting_guess_and_table(tmp_path):
    record = guess_record()
    assert record["guess"] == "table"
    name, word, digest = record["guess_table"].split()
    assert (name, word, len(digest)) == ("alpha_table.npz", "sha256", 64)
    missing = guess_record(tmp_path / "none.npz")
    assert missing["guess"] == "formula" and "not found" in missing["guess_table"]
    ds = compute_surface([0.5], [0.1])
    assert (ds.attrs["guess"], ds.attrs["guess_table"]) == (record["guess"], record["guess_table"])


def test_solver_warns_when_it_falls_back_to_the_formula_guess(monkeypatch):
    import contactalpha.engine.table as table

    def unusable(path=None):
        raise FileNotFoundError("exact-alpha table gone")

    monkeypatch.setattr(table, "table_arrays", unusable)
    with pytest.warns(UserWarning, match="no usable table .*gone.*formula starting guess"):
        s = contactalpha.solve_alpha(0.5, 0.2)
    assert s.status == "ok"
