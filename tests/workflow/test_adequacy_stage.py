"""The adequacy stage on workflow/test-config.yaml: its files hold the library's numbers."""

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

import contactalpha
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL, impact
from contactalpha.io import load_dataset, load_surface
from contactalpha.paper.statements import statements_markdown
from contactalpha.scene import advisor
from contactalpha.scene.advisor import cheapest, is_adequate
from contactalpha.scene.threshold import critical_speed
from contactalpha.studies.adequacy import maps, report

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
TEST_CONFIG = ROOT / "workflow" / "test-config.yaml"
TARGETS = [
    "results/adequacy/maps.h5",
    "results/adequacy/statements.md",
    "results/adequacy/summary.md",
    "results/adequacy/thresholds.md",
    "results/figures/critical_speed.png",
]


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    work = tmp_path_factory.mktemp("adequacy")
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(work)]
    cmd += ["--configfile", str(TEST_CONFIG), "--cores", "2", *TARGETS]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return work


@pytest.fixture(scope="module")
def config():
    return yaml.safe_load(TEST_CONFIG.read_text())["adequacy"]


def test_maps_are_the_advisors_rule_on_the_surface(work, config):
    surface = load_surface(work / "results" / "surface.h5")
    ds = load_dataset(work / "results" / "adequacy" / "maps.h5")
    np.testing.assert_array_equal(ds["epsilon"].values, surface["epsilon"].values)  # strides 1: whole grid
    np.testing.assert_array_equal(ds["xi"].values, surface["xi"].values)
    np.testing.assert_array_equal(ds["tol"].values, config["tols"])
    d = float(ds["delivered_eps"].sel(model="hunt_crossley", epsilon=0.5, xi=0.2))
    assert d == float(impact(0.75, 0.2).eps)
    requested = np.broadcast_to(ds["epsilon"].values[:, None], ds["exact_state"].shape)
    for t in config["tols"]:
        ok = is_adequate(ds["delivered_eps"], ds["state"], requested, surface["state"].values, t)
        np.testing.assert_array_equal(ds["adequate"].sel(tol=t).values, ok)
        got = maps.xi_ignore(ds["xi"].values, ds["ignore_adequate"].sel(tol=t).values)
        np.testing.assert_array_equal(ds["xi_ignore"].sel(tol=t).values, got)


def test_cheapest_map_is_reproducible_from_the_file(work):
    ds = load_dataset(work / "results" / "adequacy" / "maps.h5")
    names = list(ds["model"].values)
    costs = dict(zip(names, ds["cost"].values, strict=True))
    assert costs == advisor.model_costs(names)  # the fixed cost model, not this run's timings
    errors = np.abs(ds["delivered_eps"].values - ds["epsilon"].values[None, :, None])
    for t in ds["tol"].values:
        ok = ds["adequate"].sel(tol=t).values.astype(bool)
        for idx in np.ndindex(ok.shape[1:]):
            pick = cheapest(names, ok[(slice(None), *idx)], costs, errors[(slice(None), *idx)])
            assert int(ds["cheapest"].sel(tol=t).values[idx]) == names.index(pick)


def test_maps_carry_provenance(work, config):
    attrs = load_dataset(work / "results" / "adequacy" / "maps.h5").attrs
    surface = load_surface(work / "results" / "surface.h5").attrs
    assert json.loads(attrs["config"]) == {"adequacy": {"tols": config["tols"], "stride": config["stride"]}}
    # The version, commit and history of the run that made them, not merely non-empty strings.
    assert attrs["contactalpha_version"] == contactalpha.__version__
    assert attrs["surface_git_commit"] == surface["git_commit"]
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?|unknown", attrs["git_commit"])
    assert re.fullmatch(r"\S+Z adequacy maps \(contactalpha .+\)", attrs["history"])
    assert attrs["surface_config"] == surface["config"] and attrs["grid_fraction"] == 1.0
    # The integrator and cost settings the maps were made with: the engine's and the advisor's.
    assert (attrs["rtol"], attrs["atol"], attrs["max_steps"]) == (RTOL, ATOL, MAX_STEPS)
    assert attrs["cost_tie"] == advisor.COST_TIE
    assert attrs["compute_seconds"] > 0


def test_statements_and_summary_are_the_maps_verdicts(work, config):
    ds = load_dataset(work / "results" / "adequacy" / "maps.h5")
    text = (work / "results" / "adequacy" / "statements.md").read_text()
    rows = report.small_claim_statements(ds)
    table = statements_markdown(rows, "x").split("\n| # |", 1)[1]
    assert table in text
    assert len(rows) == 2 * len(config["tols"])
    summary = (work / "results" / "adequacy" / "summary.md").read_text()
    assert report.share_table(ds) in summary and report.xi_ignore_table(ds, config["report_eps"]) in summary


def test_threshold_table_is_the_critical_speed(work):
    th = load_dataset(work / "results" / "adequacy" / "thresholds.nc")
    scenes = yaml.safe_load((ROOT / "config.yaml").read_text())["adequacy"]["scenes"]  # schema defaults
    assert list(th["scene"].values) == [s["name"] for s in scenes]
    for s, v in zip(scenes, th["v_crit"].values, strict=True):
        k = 4.0 / 3.0 * s["modulus"] * math.sqrt(s["radius"])  # Hertz, rigid ground, Poisson 0
        assert v == pytest.approx(critical_speed(s["eps"], s["mass"], k, s["accel"]), rel=1e-10)
    np.testing.assert_allclose(th["v_crit_fit"], th["v_crit"], rtol=1e-3)
    table = (work / "results" / "adequacy" / "thresholds.md").read_text()
    assert all(f"{v:.4g}" in table for v in th["v_crit"].values)
    assert (work / "results" / "figures" / "critical_speed.png").read_bytes()[:4] == b"\x89PNG"
