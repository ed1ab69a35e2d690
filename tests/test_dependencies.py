"""Every third-party module the package and its workflow scripts import is a declared dependency."""

import ast
import importlib.metadata as md
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _imported_top_names():
    names = set()
    for folder in (ROOT / "src" / "contactalpha", ROOT / "workflow" / "scripts"):
        for path in folder.rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Import):
                    names |= {a.name.split(".")[0] for a in node.names}
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    names.add(node.module.split(".")[0])
    return names - set(sys.stdlib_module_names) - {"contactalpha"}


def _declared():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    specs = list(project["dependencies"])
    for extra in project.get("optional-dependencies", {}).values():
        specs += extra
    return {re.split(r"[<>=!~\[; ]", s, maxsplit=1)[0].lower().replace("_", "-") for s in specs}


def test_every_imported_distribution_is_declared():
    dists = md.packages_distributions()
    declared = _declared()
    missing = {
        name: dists.get(name, [name])
        for name in _imported_top_names()
        if not any(d.lower().replace("_", "-") in declared for d in dists.get(name, [name]))
    }
    assert not missing, f"imported but not declared in pyproject.toml: {missing}"
