"""Config errors are found before any job, with a message naming the key (issue 15, item 5)."""

import copy
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from snakemake.utils import validate

import contactalpha.config as config_module
from contactalpha.cli import main
from contactalpha.config import check_config, read_yaml

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
TEST_CONFIG = ROOT / "workflow" / "test-config.yaml"


def checked(config):
    """What the Snakefile does with a config: schema validation (defaults filled), then check_config."""
    config = copy.deepcopy(config)
    validate(config, str(SCHEMA))
    check_config(config, SCHEMA)
    return config


def edited(path, value):
    """The test config with the dotted ``path`` (list items as integers) set to ``value``."""
    config = yaml.safe_load(TEST_CONFIG.read_text())
    *parents, last = path.split(".")
    node = config
    for part in parents:
        node = node[int(part)] if part.isdigit() else node[part]
    node[int(last) if last.isdigit() else last] = value
    return config


def test_the_shipped_configs_pass():
    checked(yaml.safe_load(TEST_CONFIG.read_text()))
    checked(yaml.safe_load((ROOT / "config.yaml").read_text()))


@pytest.mark.parametrize(
    "path, value, message",
    [
        ("surface.solver.rtol", float("nan"), "surface.solver.rtol = nan is not a finite number"),
        ("surface.solver.tol", float("nan"), "surface.solver.tol = nan is not a finite number"),
        ("surface.xi.values.0", float("nan"), "surface.xi.values[0] = nan is not a finite number"),
        ("surface.epsilon.range.step", float("nan"), "surface.epsilon.range.step = nan is not a finite"),
        ("ball.scene.mass", float("nan"), "ball.scene.mass = nan is not a finite number"),
        ("models.fig9.xi.1", float("nan"), "models.fig9.xi[1] = nan is not a finite number"),
        ("surface.figures.eq26.tau", float("inf"), "surface.figures.eq26.tau = inf is not a finite number"),
        ("surface.chunks", 2.0, "surface.chunks = 2.0 is not a whole number; valid: an integer such as 2"),
        ("surface.solver.max_steps", 1e6, "surface.solver.max_steps = 1000000.0 is not a whole number"),
        ("models.table.n_eta", 40.0, "models.table.n_eta = 40.0 is not a whole number"),
        ("models.fig9.models.1", "hu_gou", "models.fig9.models[1] = 'hu_gou' is not a registered model"),
        ("models.fig9.reference", "exactt", "models.fig9.reference = 'exactt' is not a registered model"),
        ("models.fig9.new_model", "flores", "models.fig9.new_model = 'flores' is not in models.fig9.models"),
        ("engines.case_a_model", "nope", "engines.case_a_model = 'nope' is not a registered model"),
        ("fit.eq26", {"xi": 0.3, "eps_max": 0.15}, "fit.eq26.xi = 0.3 is not on the surface xi grid"),
        ("surface.figures.section_xi", 0.3, "surface.figures.section_xi = 0.3 is not on the xi grid"),
    ],
)
def test_a_bad_value_is_named_by_its_key(path, value, message):
    with pytest.raises(ValueError) as err:
        checked(edited(path, value))
    assert message in str(err.value)


def test_fit_eq26_xi_on_the_grid_passes():
    config = checked(edited("fit.eq26", {"xi": 0.2, "eps_max": 0.15}))
    assert config["fit"]["eq26"]["xi"] == 0.2


def test_nan_passes_the_schema_alone():
    """Why check_config looks at every number: JSON-schema bounds are comparisons, which NaN never fails."""
    config = edited("surface.solver.tol", float("nan"))
    validate(config, str(SCHEMA))
    with pytest.raises(ValueError, match="surface.solver.tol = nan"):
        check_config(config, SCHEMA)


PROJECT_YAML = ["config.yaml", "workflow/test-config.yaml", "workflow/schemas/config.schema.yaml"]


@pytest.mark.parametrize("name", PROJECT_YAML)
def test_read_yaml_gives_safe_loads_data(name):
    """read_yaml's fast path (libyaml) reads the project's files exactly as yaml.safe_load does."""
    text = (ROOT / name).read_text()
    assert read_yaml(ROOT / name) == yaml.safe_load(text)
    assert config_module.FAST_LOADER is getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def test_malformed_yaml_names_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("surface:\n  xi:\n    values: [0.1, 0.2\n  chunks: 2\n")
    with pytest.raises(ValueError) as err:
        read_yaml(bad)
    # The flow sequence opened on line 3 runs into the next key's colon, line 4, column 9.
    assert str(err.value) == f"{bad}:4:9: malformed YAML: expected ',' or ']', but got ':'"
    tab = tmp_path / "tab.yaml"
    tab.write_text("surface:\n\tchunks: 2\n")
    with pytest.raises(ValueError, match=rf"^{tab}:2:1: malformed YAML: found character '\\t'"):
        read_yaml(tab)


def test_config_yaml_holds_the_schema_defaults():
    """Keys missing from a --configfile come from config.yaml (Snakemake merges the files) where it is
    present, from the schema defaults elsewhere; this keeps the two the same."""
    defaults = {}
    validate(defaults, str(SCHEMA))
    assert yaml.safe_load((ROOT / "config.yaml").read_text()) == defaults


def snakemake_dry_run(workdir, *args):
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(workdir), "-n", *args]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    return done.returncode, done.stdout + done.stderr


def test_snakemake_n_stops_on_nan_and_on_a_float_count(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("surface:\n  chunks: 2.0\nball:\n  scene:\n    mass: .nan\n")
    code, out = snakemake_dry_run(tmp_path, "--configfile", str(bad))
    assert code != 0 and "ball.scene.mass = nan is not a finite number" in out
    bad.write_text("surface:\n  chunks: 2.0\n")
    code, out = snakemake_dry_run(tmp_path, "--configfile", str(bad))
    assert code != 0 and "surface.chunks = 2.0 is not a whole number" in out
    assert not (tmp_path / "results").exists()


def test_snakemake_n_names_the_line_of_a_malformed_config_yaml(tmp_path):
    (tmp_path / "config.yaml").write_text("surface:\n  chunks: [2\n")
    code, out = snakemake_dry_run(tmp_path)
    assert code != 0 and "config.yaml:3:1: malformed YAML:" in out


def test_check_config_command_names_the_line_or_the_key_of_a_configfile(tmp_path, capsys):
    """Snakemake parses a --configfile before the workflow and gives no position; this command does."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("surface:\n  xi:\n    values: [0.1, 0.2\n  chunks: 2\n")
    assert main(["check-config", str(bad), "--schema", str(SCHEMA)]) == 2
    assert (
        capsys.readouterr().err
        == f"contactalpha: error: {bad}:4:9: malformed YAML: expected ',' or ']', but got ':'\n"
    )
    bad.write_text("surface:\n  solver:\n    tol: 5\n")
    assert main(["check-config", str(bad), "--schema", str(SCHEMA)]) == 2
    assert capsys.readouterr().err == (
        f"contactalpha: error: {bad}: surface.solver.tol: 5 is greater than the maximum of 0.001\n"
    )
    bad.write_text("models:\n  fig9:\n    reference: exactt\n")
    assert main(["check-config", str(bad), "--schema", str(SCHEMA)]) == 2
    assert f"{bad}: models.fig9.reference = 'exactt' is not a registered model" in capsys.readouterr().err
    assert main(["check-config", str(TEST_CONFIG), str(ROOT / "config.yaml"), "--schema", str(SCHEMA)]) == 0
    assert capsys.readouterr().out == f"{TEST_CONFIG}: ok\n{ROOT / 'config.yaml'}: ok\n"


@pytest.mark.parametrize(
    "path, value, message",
    [
        (
            "ball.first_collision.classical",
            ["hunt_crossley", "flors"],
            "ball.first_collision.classical[1] = 'flors' is not a registered model",
        ),
        (
            "ball.first_collision.reference",
            ["exactt", "exact_slove"],
            "ball.first_collision.reference = ['exactt', 'exact_slove']: none is a registered model",
        ),
        (
            "ball.new_model",
            ["shen_publishd"],
            "ball.new_model = ['shen_publishd']: none is a registered model",
        ),
        (
            "closedform.models",
            ["closed_form", "nope"],
            "closedform.models[1] = 'nope' is not a registered model",
        ),
    ],
)
def test_every_key_that_names_a_model_is_checked_before_a_job_runs(tmp_path, capsys, path, value, message):
    """Issue 29, N2: these names passed `snakemake -n` and check-config, then failed inside a job."""
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    *parents, last = path.split(".")
    node = config
    for part in parents:
        node = node[part]
    node[last] = value
    with pytest.raises(ValueError, match=re.escape(message)):
        checked(config)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    assert main(["check-config", str(bad), "--schema", str(SCHEMA)]) == 2
    assert message in capsys.readouterr().err


def test_a_preference_list_with_one_registered_model_passes():
    config = yaml.safe_load((ROOT / "config.yaml").read_text())
    config["ball"]["new_model"] = ["not_yet_registered", "shen_published"]
    config["ball"]["first_collision"]["reference"] = ["nope", "exact"]
    checked(config)


def test_snakemake_n_names_an_unregistered_classical_model(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("ball:\n  first_collision:\n    classical: [hunt_crossley, flors]\n")
    code, out = snakemake_dry_run(tmp_path, "--configfile", str(bad))
    assert code != 0 and "ball.first_collision.classical[1] = 'flors' is not a registered model" in out


def test_check_config_refuses_an_empty_file_as_snakemake_does(tmp_path, capsys):
    """Issue 29, N12: an empty --configfile is refused by Snakemake; check-config said ok."""
    empty = tmp_path / "empty.yaml"
    for text in ("", "# only a comment\n", "null\n"):
        empty.write_text(text)
        assert main(["check-config", str(empty), "--schema", str(SCHEMA)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"{empty}" in err and "empty" in err
    code, out = snakemake_dry_run(tmp_path, "--configfile", str(empty))
    assert code != 0
