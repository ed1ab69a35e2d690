"""CI runs the README's own test command first, in a fresh virtual environment with only [test]."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_ci_runs_the_readmes_test_command_in_a_fresh_environment_first():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    command = re.search(r"^(pip install -e \"\.\[test\]\" && python -m pytest)\s*$", readme, flags=re.M)
    assert command, "the README shows its test command"
    script = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    lines = [line.strip() for line in script if line.strip() and not line.strip().startswith("#")]
    venv = next(i for i, line in enumerate(lines) if line.startswith("python -m venv"))
    run = lines.index(command.group(1))
    engines = next(i for i, line in enumerate(lines) if "engines" in line and "pip install" in line)
    assert venv < run < engines  # nothing but [test] in it, before the engines come
    assert "unset CI" in lines[venv:run]  # as a user runs it: a missing engine's tests skip
    assert any("-m 'integration and not slow'" in line for line in lines[engines:])
    assert any(line.startswith("python -m mypy") for line in lines[engines:])
    assert any(".ci/slurm-cluster up" in line for line in lines[engines:])


def test_ci_lints_and_checks_the_format_with_the_dev_extras_ruff():
    script = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    lines = [line.strip() for line in script if line.strip() and not line.strip().startswith("#")]
    engines = next(i for i, line in enumerate(lines) if "engines" in line and "pip install" in line)
    assert "python -m ruff check . || status=$?" in lines[engines:]
    assert "python -m ruff format --check . || status=$?" in lines[engines:]
    pinned = re.search(r'"(ruff[^"]*)"', (ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert pinned, "the dev extra names ruff"
    assert f'"{pinned.group(1)}"' in lines[engines]  # stage 2 installs the dev extra's ruff
