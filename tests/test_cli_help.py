"""``contactalpha ... --help`` imports no kernel: no numba, no SciPy, no NumPy (issue 44, S19).

The parser is built from the leaf ``contactalpha.defaults`` (benchmarks/bench_help.py times it
against ``python -c pass``); here every help runs in a fresh process and its modules are listed.
"""

import json
import subprocess
import sys

import pytest

from contactalpha import cli, defaults

HEAVY = ("numba", "scipy", "numpy", "contactalpha.engine", "contactalpha.laws", "contactalpha.mechanism.tune")
PROGRAM = """
import contextlib, io, json, sys
from contactalpha.cli import main
with contextlib.redirect_stdout(io.StringIO()) as out:
    try:
        main({argv!r})
    except SystemExit as stop:
        code = stop.code
print(json.dumps({{"code": code, "help": out.getvalue(), "modules": sorted(sys.modules)}}))
"""
SUBCOMMANDS = sorted(cli.COMMANDS)


@pytest.mark.parametrize("command", ["", *SUBCOMMANDS])
def test_help_imports_no_kernel(command):
    argv = [command, "--help"] if command else ["--help"]
    run = subprocess.run([sys.executable, "-c", PROGRAM.format(argv=argv)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["code"] == 0 and "usage: contactalpha" in got["help"]
    loaded = [m for m in got["modules"] if any(m == h or m.startswith(h + ".") for h in HEAVY)]
    assert loaded == [], f"`contactalpha {' '.join(argv)}` imported {loaded[:8]}"


def test_the_helps_defaults_are_the_registries():
    from contactalpha.engine.driver import ATOL, RTOL
    from contactalpha.engine.solver import EPS_TOL
    from contactalpha.laws import LAWS

    assert defaults.STIFFNESS_UNITS == {law.name: law.stiffness_unit for law in LAWS}
    assert (defaults.RTOL, defaults.ATOL, defaults.EPS_TOL) == (RTOL, ATOL, EPS_TOL) == (1e-12, 1e-14, 1e-12)
    engine = next(a for a in cli.build_parser()._subparsers._group_actions[0].choices["params"]._actions
                  if a.dest == "engine")  # fmt: skip
    assert engine.choices is None  # any name: the registry checks it (one home; adding one is one line)
    tune = cli.build_parser()._subparsers._group_actions[0].choices["tune"]
    assert next(a for a in tune._actions if a.dest == "engine").choices is None  # likewise
