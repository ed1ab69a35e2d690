"""End to end: the whole Snakemake workflow on workflow/test-config.yaml, in a temporary directory."""

import hashlib
import json
import re
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

import contactalpha
from contactalpha.baselines.reference import impact_scipy
from contactalpha.engine.codes import END_STATES
from contactalpha.io import TMP_TAG, load_dataset
from contactalpha.paper.surface.compute import grid_from_config

# Heavy (workflow runs, compiles, real engines): run by `pytest -m integration` (.ci/run).
pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]
TEST_CONFIG = ROOT / "workflow" / "test-config.yaml"
SURFACE_FIGURES = ["fig4_alpha_surface", "fig5_alpha_section", "end_states"]


def snakemake(workdir, *args, configfile=TEST_CONFIG):
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(workdir)]
    cmd += ["--configfile", str(configfile), "--cores", "2", *args]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return done.stdout + done.stderr


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """Run chunk 0 alone (a run killed midway), leave a stale temporary file, then the rest."""
    work = tmp_path_factory.mktemp("workflow")
    snakemake(work, "results/surface/chunks/chunk_0.h5")
    chunk0 = work / "results/surface/chunks/chunk_0.h5"
    first_mtime = chunk0.stat().st_mtime_ns
    # A temporary file of a writer that is gone (a kill -9 inside write_atomic): the next run removes it.
    gone = subprocess.Popen(["true"])
    gone.wait()
    host = re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname())
    stale = work / "results" / f".surface.h5.{TMP_TAG}-{host}-{gone.pid}.x1y2z3.tmp"
    stale.write_bytes(b"\x89HDF half written")
    package_before = _package_data()
    log = snakemake(work)
    return {
        "work": work,
        "log": log,
        "chunk0_resumed": chunk0.stat().st_mtime_ns == first_mtime,
        "stale_removed": not stale.exists(),
        "package_unchanged": _package_data() == package_before,
        "top_level": {p.name for p in work.iterdir()},
    }


def _package_data():
    """Digest of every file shipped in contactalpha/data/."""
    folder = Path(contactalpha.__file__).parent / "data"
    return {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()
    }


def test_rerun_resumes_and_then_has_nothing_to_do(run):
    assert run["chunk0_resumed"], "chunk 0 was computed again"
    assert run["stale_removed"], "a killed write's temporary file was left"
    assert "rule surface_chunk" in run["log"] and "chunk=1" in run["log"]
    assert "chunk=0" not in run["log"]
    again = snakemake(run["work"], "--dry-run")
    assert "Nothing to be done" in again


def test_a_figure_setting_reruns_only_what_uses_it(run):
    config = yaml.safe_load(TEST_CONFIG.read_text())
    config["surface"]["figures"]["section_xi"] = 0.4
    edited = run["work"] / "edited-config.yaml"
    edited.write_text(yaml.safe_dump(config, sort_keys=False))  # Snakemake compares params in key order
    plan = snakemake(run["work"], "--dry-run", configfile=edited)
    assert "rule surface_report:" in plan  # Fig. 5 and the summary
    for rule in ("surface_chunk", "surface_merge", "surface_figures"):  # Fig. 4, end states
        assert f"rule {rule}:" not in plan, rule


def test_an_engine_edit_reruns_the_surface_and_the_table(run, tmp_path):
    """The code version (hash of the sources a rule runs) is a parameter of the rules that use the engine."""
    import os
    import shutil

    copy = tmp_path / "src" / "contactalpha"
    shutil.copytree(Path(contactalpha.__file__).parent, copy, ignore=shutil.ignore_patterns("__pycache__"))
    env = {**os.environ, "PYTHONPATH": str(tmp_path / "src")}
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(run["work"])]
    cmd += ["--configfile", str(TEST_CONFIG), "--cores", "2", "--dry-run"]

    def plan():
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)
        assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
        return done.stdout + done.stderr

    assert "Nothing to be done" in plan()  # the same sources elsewhere: the same code version
    rk = copy / "engine" / "rk.py"
    rk.write_text(rk.read_text().replace("HERTZ = 1.25\n", "HERTZ = 1.3\n"))
    edited = plan()
    assert "rule surface_chunk:" in edited and "rule table:" in edited
    assert "Params have changed" in edited


def test_outputs_exist_and_are_complete(run):
    results = run["work"] / "results"
    for name in SURFACE_FIGURES:
        assert (results / "figures" / f"{name}.png").read_bytes()[:4] == b"\x89PNG"
        assert (results / "figures" / f"{name}.pdf").read_bytes()[:4] == b"%PDF"
    summary = (results / "summary.md").read_text()
    assert "12 points" in summary and "0 of 12 points failed" in summary
    assert "## Section xi = 0.2" in summary
    logs = (run["work"] / "logs" / "surface" / "chunk_1.log").read_text()
    assert "points/s" in logs


def test_surface_file_contents_match_the_library(run):
    config = yaml.safe_load(TEST_CONFIG.read_text())["surface"]
    eps, xi = grid_from_config(config)
    ds = contactalpha.load_surface(run["work"] / "results" / "surface.h5")
    assert ds.alpha.shape == (3, 4)
    np.testing.assert_array_equal(ds.epsilon.values, eps)
    np.testing.assert_array_equal(ds.xi.values, xi)
    assert np.all(ds.status.values == 0)
    for e, x in [(0.2, 0.0), (0.5, 0.001), (0.8, 0.2), (0.2, 0.4)]:
        sol = contactalpha.solve_alpha(e, x)
        point = ds.sel(epsilon=e, xi=x)
        assert float(point.alpha) == float(sol.alpha)  # same code path: the same bits
        assert END_STATES[int(point.state)] == sol.state
        # and a value that could be wrong: the SciPy oracle, fed the file's alpha, restitutes eps
        assert impact_scipy(float(point.alpha), x, rtol=1e-12, atol=1e-14).eps == pytest.approx(e, abs=1e-9)
    attrs = ds.attrs
    assert json.loads(attrs["config"])["surface"]["epsilon"] == config["epsilon"]
    assert attrs["contactalpha_version"] == contactalpha.__version__
    assert attrs["chunks"] == 2 and attrs["rtol"] == 1e-12
    chunks = sorted((run["work"] / "results" / "surface" / "chunks").glob("chunk_*.h5"))
    assert len(chunks) == 2  # the merge's compute time is the chunks' CPU time
    seconds = sum(load_dataset(c).attrs["compute_seconds"] for c in chunks)
    assert attrs["compute_seconds"] == pytest.approx(seconds, rel=1e-12)
    assert len(attrs["history"].splitlines()) == 3  # two chunks and the merge


def test_a_built_table_records_its_settings_and_build_time(run):
    """A table built by the workflow records its grid, tolerances and build time (wall_time_s)."""
    from contactalpha.engine.table import load_table

    meta = load_table(run["work"] / "results" / "models" / "alpha_table.npz").meta
    built = yaml.safe_load(TEST_CONFIG.read_text())["models"]["table"]
    assert {k: meta[k] for k in built} == built  # n_eta, n_p, refine_n, tol, rtol, atol
    assert meta["contactalpha_version"] == contactalpha.__version__
    assert re.fullmatch(r"[0-9a-f]{40}(\+dirty)?|unknown", meta["git_commit"])
    # The recorded build time is the one the build logged, not any positive number.
    logged = re.search(r"table built in ([0-9.]+) s", (run["work"] / "logs/models/table.log").read_text())
    assert meta["wall_time_s"] == pytest.approx(float(logged[1]), abs=0.05)


def test_bad_config_fails_before_any_job(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("surface:\n  xi:\n    values: [0.3, 0.2]\n")
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(tmp_path)]
    cmd += ["--configfile", str(bad), "-c1"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    assert "surface.xi.values is not strictly increasing: 0.2 comes after 0.3" in done.stdout + done.stderr
    assert not (tmp_path / "results").exists()


def test_a_run_writes_only_under_results(run):
    """Issue 15, item 6: no file of the checkout (the shipped constants, the table) is touched."""
    assert run["package_unchanged"], "the run rewrote a file shipped in contactalpha/data/"
    assert run["top_level"] <= {"results", "logs", ".snakemake"}, run["top_level"]
    assert not list((run["work"] / "results").glob("*/*_package.*")), "a default run shipped"


def test_the_default_config_checks_the_shipped_table_and_builds_none(tmp_path):
    """The shipped table was built with config.yaml's models.table: the default run reuses it."""
    plan = snakemake(tmp_path, "--dry-run", "results/models/table_check.md", configfile=ROOT / "config.yaml")
    assert "rule table_check:" in plan and "rule table:" not in plan
    # The tiny test config asks for another table: that one is built and checked, not shipped.
    plan = snakemake(tmp_path, "--dry-run", "results/models/table_check.md")
    assert "rule table_check:" in plan and "rule table:" in plan


def test_lint_is_clean():
    cmd = [sys.executable, "-m", "snakemake", "--lint", "-s", str(ROOT / "Snakefile")]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Lints for" not in done.stdout + done.stderr


def test_slurm_profile_is_accepted(tmp_path):
    # No cluster here: a dry run checks that the profile and the executor plugin load and plan the jobs.
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(tmp_path)]
    cmd += ["--profile", str(ROOT / "workflow/profiles/slurm"), "--configfile", str(TEST_CONFIG), "-n"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    out = done.stdout + done.stderr
    assert re.search(rf"Using profiles? {re.escape(str(ROOT / 'workflow/profiles/slurm'))}", out)
    # one job per chunk (test config: 2) and one merge
    assert re.search(r"^surface_chunk\s+2$", out, re.MULTILINE), out[-2000:]
    assert re.search(r"^surface_merge\s+1$", out, re.MULTILINE)


def test_ship_copies_the_refit_and_a_checked_table_to_the_configured_files(run):
    """`snakemake ship` (test config: the package files are under results/) copies the run's results."""
    package_before = _package_data()
    log = snakemake(run["work"], "ship")
    results = run["work"] / "results"
    assert "rule table_check_built:" in log
    pairs = [("fit/shen_refit.json", "fit/shen_refit_package.json", "shen_refit")]
    pairs += [("models/alpha_table.npz", "models/alpha_table_package.npz", "alpha_table")]
    for source, destination, record in pairs:
        data = (results / source).read_bytes()
        assert (results / destination).read_bytes() == data
        shipped = json.loads((results / "ship" / f"{record}.json").read_text())
        assert shipped["sha256"] == hashlib.sha256(data).hexdigest()
        assert shipped["destination"] == f"results/{destination}"
    assert _package_data() == package_before


def test_a_value_changed_in_the_surface_stops_the_jobs_that_read_it(run, tmp_path):
    """Issue 29, N4: a value changed inside results/surface.h5 went unnoticed (the downstream jobs
    reran on it and the run exited 0); its checksum now stops the first job that reads it."""
    import shutil

    import h5py

    work = tmp_path / "work"
    shutil.copytree(run["work"], work, symlinks=True)
    surface = work / "results" / "surface.h5"
    with h5py.File(surface, "r+") as f:
        f["alpha"][1, 1] = f["alpha"][1, 1] * 1.001
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(work)]
    cmd += ["--configfile", str(TEST_CONFIG), "--cores", "2"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    out = done.stdout + done.stderr
    assert done.returncode != 0, out[-3000:]
    assert "results/surface.h5: its values do not match the checksum" in out, out[-3000:]
