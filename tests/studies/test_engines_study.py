"""The engines stage: a tiny grid in both engines, its verdicts, tables, figure and provenance.

Needs the optional engines (skipped with the reason without them, except under CI=true).
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
SCENE = {"mass": 0.5, "radius": 0.08, "stiffness": 1.4e8, "approach_speed": 0.5, "gravity": 9.81}
SETTINGS = {
    "opensim": {"accuracy": 1e-8, "per_tstar": 100, "window": 12.0},
    "exudyn": {"tolerance": 1e-9, "steps_per_tstar": 200, "window": 12.0},
}


@pytest.fixture(scope="module")
def study(opensim, exudyn, tmp_path_factory):
    from contactalpha.io import load_dataset, write_dataset_atomic
    from contactalpha.studies.engines import compute

    scene = compute.scene_from_config(SCENE)
    work = tmp_path_factory.mktemp("engines")
    out = {}
    for engine in compute.ENGINES:
        settings = compute.ENGINE_SETTINGS[engine](**SETTINGS[engine])
        ds = compute.round_trip(engine, scene, [0.5], [5.1, 495.0], settings, {"test": True})
        write_dataset_atomic(ds, work / f"{engine}.nc")
        out[engine] = load_dataset(work / f"{engine}.nc")
    out["static"] = compute.static_checks(scene, [5.1])
    out["static"].attrs["engine_versions"] = "{}"
    return out


def test_exact_alpha_meets_both_requirements_in_both_engines(study):
    from contactalpha.studies.engines.compute import verdicts

    for engine in ("opensim", "exudyn"):
        checks = verdicts(study[engine], 1e-3)
        assert checks, engine
        for run, c in checks.items():
            assert c["separating_ok"] and c["nonseparating_ok"], (run, c)
            assert c["max_eps_error"] < 1e-5, (run, c)
            # eps = 0.5 separates at F = 5.1 N and does not at F = 495 N (xi = 0.8).
            assert c["separating_points"] == 1 and c["nonseparating_points"] == 1


def test_builtin_mappings_miss_the_target_and_the_engines_agree_with_the_package(study):
    os_hc = study["opensim"].sel(run="opensim_hunt_crossley")
    ex_m1 = study["exudyn"].sel(run="exudyn_model1")
    # Both are Hunt-Crossley's alpha = 3(1 - eps)/2: the two engines must deliver the same eps.
    np.testing.assert_allclose(os_hc["eps_measured"], ex_m1["eps_measured"], atol=1e-4)
    assert float(os_hc["eps_measured"].sel(force=5.1, epsilon=0.5)) - 0.5 > 0.1
    for name in ("opensim", "exudyn"):
        ds = study[name]
        np.testing.assert_allclose(ds["eps_measured"], ds["eps_package"], atol=2e-5)


def test_results_carry_provenance_through_a_write_and_read(study, opensim):
    import contactalpha
    from contactalpha.studies.engines.compute import engine_version

    ds = study["opensim"]
    assert ds.attrs["contactalpha_version"] == contactalpha.__version__
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?|unknown", ds.attrs["git_commit"])
    assert json.loads(ds.attrs["config"]) == {"test": True}
    assert json.loads(ds.attrs["settings"]) == SETTINGS["opensim"]
    assert json.loads(ds.attrs["engine_versions"])["opensim"] == engine_version("opensim")
    assert re.fullmatch(
        r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ engine round trip: opensim \(contactalpha .+\)", ds.attrs["history"]
    )
    assert ds["eps_measured"].attrs["units"] == "1"


def test_summary_tables_hold_every_grid_point_and_the_verdicts(study):
    from contactalpha.studies.engines.report import error_summary, roundtrip_table, static_table

    rounds = [study["opensim"], study["exudyn"]]
    table = roundtrip_table(rounds)
    assert len(table.strip().splitlines()) == 2 + 2  # head, rule, one row per (F, eps)
    assert "0.5000 ns" in table  # F = 495 N does not separate
    summary = error_summary(rounds, 1e-3)
    assert summary.count("Target ≤ 0.001: met") == 3 and "NOT met" not in summary
    assert "| 5.1 |" in static_table(study["static"])


def test_figure_draws_every_run(study):
    from contactalpha.studies.engines.figures import ERROR_FLOOR, RUN_HEADS, roundtrip_figure

    rounds = [study["opensim"], study["exudyn"]]
    fig = roundtrip_figure(rounds)
    runs = [str(r) for ds in rounds for r in ds["run"].values]
    assert fig.axes[0].get_legend_handles_labels()[1] == [RUN_HEADS[r] for r in runs] and len(runs) == 6
    # Each column draws every run's delivered eps (top) and its error (bottom) at the target eps.
    forces = rounds[0]["force"].values
    for k in range(forces.size):
        top, bottom = fig.axes[k], fig.axes[forces.size + k]
        want_top, want_bottom = [], []
        for ds in rounds:
            for run in ds["run"].values:
                y = ds["eps_measured"].sel(run=run).isel(force=k).values
                eps = ds["epsilon"].values
                want_top += list(zip(eps, y, strict=True))
                want_bottom += list(zip(eps, np.maximum(abs(y - eps), ERROR_FLOOR), strict=True))
        for ax, want in ((top, want_top), (bottom, want_bottom)):
            drawn = [tuple(p) for c in ax.collections for p in np.asarray(c.get_offsets())]
            assert sorted(drawn) == sorted(want), (k, ax.get_title())


def test_engines_config_defaults_have_one_owner():
    from snakemake.utils import validate

    from contactalpha.adapters import exudyn_contact, opensim_hc

    config = yaml.safe_load((ROOT / "config.yaml").read_text())["engines"]
    filled = {}
    validate(filled, str(ROOT / "workflow/schemas/config.schema.yaml"))
    assert filled["engines"] == config
    assert config["opensim"] == {
        "accuracy": opensim_hc.ACCURACY,
        "per_tstar": opensim_hc.SAMPLES_PER_TSTAR,
        "window": opensim_hc.WINDOW_TSTAR,
    }
    assert config["exudyn"] == {
        "tolerance": exudyn_contact.TOLERANCE,
        "steps_per_tstar": exudyn_contact.STEPS_PER_TSTAR,
        "window": exudyn_contact.WINDOW_TSTAR,
    }
