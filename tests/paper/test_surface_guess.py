"""The surface says which starting guess made it; the solver warns when it cannot use the table."""

import hashlib

import pytest

import contactalpha
from contactalpha.engine.table import DEFAULT_FILE, load_table
from contactalpha.engine.table_build import save_table
from contactalpha.paper.surface.compute import compute_surface, guess_record


def test_surface_records_its_starting_guess_and_table(tmp_path):
    record = guess_record()
    assert record["guess"] == "table"
    name, word, digest = record["guess_table"].split()
    # The digest is the shipped table's, so a surface says which table steered its Newton paths.
    assert (name, word) == (DEFAULT_FILE.name, "sha256")
    assert digest == hashlib.sha256(DEFAULT_FILE.read_bytes()).hexdigest()
    copy = save_table(load_table(), tmp_path / "copy.npz", note="same arrays, other bytes")
    other = guess_record(copy)
    assert other["guess"] == "table" and digest not in other["guess_table"]
    assert other["guess_table"] == f"copy.npz sha256 {hashlib.sha256(copy.read_bytes()).hexdigest()}"
    missing = guess_record(tmp_path / "none.npz")
    assert missing["guess"] == "formula" and "not found" in missing["guess_table"]
    assert str(tmp_path / "none.npz") in missing["guess_table"]
    ds = compute_surface([0.5], [0.1])
    assert (ds.attrs["guess"], ds.attrs["guess_table"]) == (record["guess"], record["guess_table"])


def test_solver_refuses_to_fall_back_silently_when_the_table_is_unusable(monkeypatch):
    """Issue 29, N8: with the table missing the solver fell back to the formula guess (a warning)."""
    import contactalpha.engine.table as table

    def unusable(path=None):
        raise FileNotFoundError("exact-alpha table gone")

    monkeypatch.setattr(table, "table_arrays", unusable)
    with pytest.raises(
        FileNotFoundError, match="guess='table' needs the shipped table: exact-alpha table gone"
    ):
        contactalpha.solve_alpha(0.5, 0.2)
    s = contactalpha.solve_alpha(0.5, 0.2, guess="formula")
    assert s.status == "ok"


def test_surface_without_a_usable_table_is_solved_from_the_formula_and_says_so(tmp_path, monkeypatch):
    import contactalpha.paper.surface.compute as compute

    monkeypatch.setattr(compute, "DEFAULT_FILE", tmp_path / "gone.npz")
    monkeypatch.setattr(compute.guess_record, "__defaults__", (tmp_path / "gone.npz",))
    ds = compute_surface([0.5], [0.1])
    assert ds.attrs["guess"] == "formula" and "not found" in ds.attrs["guess_table"]
    assert float(ds.alpha.values.item()) == pytest.approx(contactalpha.solve_alpha(0.5, 0.1).alpha, rel=1e-9)
