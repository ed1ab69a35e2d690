"""The bench stage's runs take a BenchSettings, record it, and resume only under the same one."""

import json

import pandas as pd
import pytest

from contactalpha.paper.bench.report import (
    BenchSettings,
    FailureSettings,
    grid_description,
    method_settings,
    run_failures,
)

# One point, engine and RK4 only: a few seconds.
TINY = BenchSettings(
    rtols=(1e-4,),
    rk4_steps=(0.01,),
    scipy_methods=(),
    failure=FailureSettings(eps=(0.5,), xi=(0.2,), eps_coarse=(0.5,), xi_coarse=(0.2,)),
)


def test_method_settings_follow_the_settings():
    s = BenchSettings(rtols=(1e-4, 1e-8), rk4_steps=(0.01,), scipy_methods=("Radau",))
    assert method_settings(s) == {
        "engine": [1e-4, 1e-8],
        "engine-table": [1e-4, 1e-8],
        "rk4": [0.01],
        "scipy-Radau": [1e-4, 1e-8],
    }


def test_grid_description_names_the_settings_grids():
    text = grid_description(TINY)
    assert text.startswith("1 × 1 points for engine and rk4, 1 × 1 for SciPy; ε ∈ {0.5}, ξ ∈ {0.2}")
    assert "1,000,000 RHS evaluations" in text


def test_failure_map_runs_the_settings_and_fingerprints_them(tmp_path):
    table, counts = tmp_path / "failure_map.csv", tmp_path / "failure_counts.csv"
    said = []
    run_failures(TINY, table, counts, log=said.append)
    rows = pd.read_csv(table)
    assert list(rows.method) == ["engine", "engine-table", "rk4"]
    assert list(rows.eps) == [0.5] * 3 and list(rows.xi) == [0.2] * 3
    assert list(rows.setting) == [1e-8, 1e-8, 1e-3]
    assert list(pd.read_csv(counts).ok) == [1, 1, 1]
    # An interrupted run under other settings leaves rows that the next run must not resume.
    partial = tmp_path / "failure_map.csv.partial"
    stamp = {"fingerprint": "written under other settings"}
    partial.write_text(json.dumps(stamp) + "\n" + json.dumps({"method": "engine", "category": "ok"}) + "\n")
    run_failures(TINY, table, counts, log=said.append)
    assert any("discarded" in msg for msg in said)
    assert len(pd.read_csv(table)) == 3 and not partial.exists()


def test_unknown_bench_settings_are_refused():
    with pytest.raises(TypeError):
        BenchSettings(rtol=1e-4)
