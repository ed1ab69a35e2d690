"""A fresh clone with the usual virtual environment folders shows nothing untracked (issue 29, also)."""

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.skipif(
    shutil.which("git") is None or not (ROOT / ".git").exists(), reason="needs a git checkout"
)
@pytest.mark.parametrize("folder", [".venv", "venv", "env", ".tox", ".mypy_cache"])
def test_environment_folders_are_ignored(folder):
    probe = f"{folder}/bin/python"
    run = subprocess.run(
        ["git", "-C", str(ROOT), "check-ignore", "--no-index", "-q", probe], capture_output=True, text=True
    )
    assert run.returncode == 0, f"{probe} is not ignored by .gitignore"
