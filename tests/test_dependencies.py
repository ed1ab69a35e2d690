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
    local = {p.stem for p in (ROOT / "workflow" / "scripts").glob("*.py")}  # e.g. prefork, beside the scripts
    return names - set(sys.stdlib_module_names) - {"contactalpha"} - local


def _declared():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    specs = list(project["dependencies"])
    for extra in project.get("optional-dependencies", {}).values():
        specs += extra
    return {re.split(r"[<>=!~\[; ]", s, maxsplit=1)[0].lower().replace("_", "-") for s in specs}


# Import names whose distribution is named otherwise, for when it is not installed here (an
# optional engine): installed, the distribution's own metadata says it.
NOT_INSTALLED_NAMES = {"pydrake": "drake", "yaml": "pyyaml", "warp": "warp-lang"}


def test_every_imported_distribution_is_declared():
    dists = md.packages_distributions()
    declared = _declared()

    def distributions(name):
        return dists.get(name) or [NOT_INSTALLED_NAMES.get(name, name)]

    missing = {
        name: distributions(name)
        for name in _imported_top_names()
        if not any(d.lower().replace("_", "-") in declared for d in distributions(name))
    }
    assert not missing, f"imported but not declared in pyproject.toml: {missing}"


def test_the_core_install_needs_only_numpy_scipy_numba():
    """``pip install .`` installs the library and its CLI on these alone; the rest are extras."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = {re.split(r"[<>=!~\[; ]", s, maxsplit=1)[0].lower() for s in project["dependencies"]}
    assert core == {"numpy", "scipy", "numba"}
    workflow = {
        re.split(r"[<>=!~\[; ]", s, maxsplit=1)[0].lower()
        for s in project["optional-dependencies"]["workflow"]
    }
    assert {"snakemake", "xarray", "matplotlib", "pyyaml"} <= workflow


def test_core_modules_import_no_workflow_dependency():
    """Importing the core's public entry points (and the CLI) loads none of the workflow's libraries."""
    import subprocess

    code = (
        "import sys, contactalpha as ca, contactalpha.cli, contactalpha.warmup\n"
        "for name in ca.__all__:\n"
        "    if name != 'load_surface': getattr(ca, name)\n"
        "import contactalpha.export.c_source, contactalpha.scene.bounces, contactalpha.scene.threshold\n"
        # Not yaml: numba reads its config with it when it is installed.
        "bad = {'xarray', 'pandas', 'matplotlib', 'snakemake', 'jsonschema', 'h5py', 'tqdm'}\n"
        "print(sorted(bad & {m.split('.')[0] for m in sys.modules}))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
