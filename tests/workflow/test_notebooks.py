"""The notebooks (jupytext percent files) run end to end against a tiny surface."""

from pathlib import Path

import jupytext
import pytest
from nbclient import NotebookClient

from contactalpha.io import write_dataset_atomic
from contactalpha.paper.surface.compute import compute_surface

NOTEBOOKS = sorted((Path(__file__).resolve().parents[2] / "notebooks").glob("*.py"))
# Per-cell time limit, seconds: a cell that hangs fails the test instead of the CI job.
CELL_TIMEOUT = 120
# Text each notebook must print (it shows that the cells did their work, not just ran).
# The tiny surface below has 8 x 10 points, 8 of them at xi = 0, all solved.
EXPECTED_OUTPUT = {
    "fit_explorer": [
        "8 eps x 10 xi values",
        "72 points with xi > 0, 8 at xi = 0",
        "0 points excluded",
        "| `beta` |",
        "RMS rel. err. alpha",
    ]
}


@pytest.fixture(scope="module")
def tiny_surface(tmp_path_factory):
    path = tmp_path_factory.mktemp("surface") / "surface.h5"
    eps = [0.05, 0.1, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95]
    xi = [0.0, 0.001, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9]
    write_dataset_atomic(compute_surface(eps, xi), path)
    return path


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path, tiny_surface, monkeypatch):
    monkeypatch.setenv("CONTACTALPHA_SURFACE", str(tiny_surface))
    monkeypatch.setenv("MPLBACKEND", "agg")
    nb = jupytext.read(path)
    NotebookClient(
        nb, timeout=CELL_TIMEOUT, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}
    ).execute()
    text = "".join(o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []))
    for snippet in EXPECTED_OUTPUT.get(path.stem, []):
        assert snippet in text, f"{path.name} did not print {snippet!r}"
