"""Every `snakemake` command line the docs, the README and the config files' headers give is one that runs.

Each is read with Snakemake's own argument parser (a target after ``--configfile FILE`` is read as a
second config file: issue 44, S17), and its targets are dry-run (``snakemake -n``) with its own config
files, or the tiny test config where it names none.
"""

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from snakemake.cli import get_argument_parser

ROOT = Path(__file__).resolve().parents[2]
TEST_CONFIG = "workflow/test-config.yaml"
SOURCES = [
    ROOT / "README.md",
    *sorted((ROOT / "docs").rglob("*.md")),
    *sorted((ROOT / "workflow").rglob("*.yaml")),
]
# `snakemake ...` inside inline code, or in a figure comment's parentheses.
INLINE = re.compile(r"`(snakemake [^`]+)`|\((snakemake -[^)]+)\)")
FENCE = re.compile(r"^\s*```")


def _lines(text):
    """Command lines of ``text``: inline ones, and fenced or commented ones with their continuations."""
    found = [a or b for a, b in INLINE.findall(text)]
    fenced, pending = False, ""
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
            continue
        body = line.strip().lstrip("#").strip()
        if pending:
            pending += " " + body
        elif (fenced or line.lstrip().startswith("#")) and re.match(r"(\S+ && )?snakemake ", body):
            pending = body.split("&& ", 1)[-1]
        if pending.endswith("\\"):
            pending = pending[:-1].rstrip()
        elif pending:
            found.append(pending)
            pending = ""
    return found


def documented_commands():
    """``(source, command line)`` of every documented snakemake command, each line once."""
    seen = {}
    for path in SOURCES:
        for line in _lines(path.read_text(encoding="utf-8")):
            seen.setdefault(" ".join(line.split()), path.relative_to(ROOT))
    return [(str(where), line) for line, where in seen.items()]


COMMANDS = documented_commands()


def test_the_docs_give_snakemake_commands_with_config_files():
    lines = [line for _, line in COMMANDS]
    assert len(lines) >= 20
    assert any("--configfile workflow/configs/fine.yaml" in line for line in lines)
    assert any("--profile workflow/profiles/slurm" in line for line in lines)


@pytest.mark.parametrize(("source", "line"), COMMANDS, ids=[line for _, line in COMMANDS])
def test_documented_command_parses_as_written(source, line):
    args = get_argument_parser().parse_args(shlex.split(line, comments=True)[1:])
    for config in args.configfile or ():
        assert (ROOT / config).is_file() and config.suffix in {".yaml", ".yml"}, (
            f"{source}: `{line}` gives {str(config)!r} as a config file (a target after --configfile?)"
        )
    for profile in args.profile or ():
        assert (ROOT / profile / "config.yaml").is_file(), f"{source}: no profile {profile}"


def test_documented_targets_dry_run(tmp_path):
    groups = {}
    for _, line in COMMANDS:
        args = get_argument_parser().parse_args(shlex.split(line, comments=True)[1:])
        configs = tuple(str(c) for c in args.configfile or ()) or (TEST_CONFIG,)
        groups.setdefault(configs, set()).update(args.targets)
    for configs, targets in groups.items():
        cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "-d", str(tmp_path), "-n",
               *sorted(targets), "--configfile", *(str(ROOT / c) for c in configs)]  # fmt: skip
        run = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
        assert run.returncode == 0, f"{' '.join(cmd)}:\n{run.stdout[-2000:]}{run.stderr[-2000:]}"
