"""Provenance of every result: package version, git commit, time-stamped history lines."""

import ast
import hashlib
import subprocess
from datetime import UTC, datetime
from functools import cache
from pathlib import Path

from contactalpha.io import json_text
from contactalpha.version import __version__


def git_commit(path=None):
    """Commit hash of the checkout at ``path`` (``+dirty`` if modified), or ``unknown``."""
    cwd = Path(path or Path(__file__).parent)
    try:
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=cwd, capture_output=True, text=True, check=True, timeout=10
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=cwd,
            capture_output=True,
            text=True,
            check=True,
            timeout=10,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("+dirty" if dirty else "")


def history_line(step):
    """One ``history`` entry: UTC time stamp, the step, the package version."""
    stamp = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    return f"{stamp} {step} (contactalpha {__version__})"


def result_attrs(config, step):
    """Attributes every results file carries: package version, git commit, its settings, a history line.

    ``config`` (the settings that made the result) is stored as JSON text with sorted keys.
    """
    return {
        "contactalpha_version": __version__,
        "git_commit": git_commit(),
        "config": json_text(config, sort_keys=True),
        "history": history_line(step),
    }


def settings_fingerprint(settings, *modules):
    """SHA-256 (hex) of ``settings`` (JSON, sorted keys) and of the sources of ``modules``.

    Equal fingerprints mean the same settings run by the same code: what a checkpoint
    must match before its rows are resumed.
    """
    text = json_text({"settings": settings, "code": source_hash(*modules) if modules else ""}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


# The package whose sources ``source_hash`` reads.
PACKAGE_DIR = Path(__file__).resolve().parent
PACKAGE = PACKAGE_DIR.name


def _module_file(parts):
    """The source file of package module ``parts`` (a tuple of names), or None."""
    base = PACKAGE_DIR.joinpath(*parts)
    if base.with_suffix(".py").is_file():
        return base.with_suffix(".py")
    if (base / "__init__.py").is_file():
        return base / "__init__.py"
    return None


def _imported_files(path):
    """Package source files that ``path`` imports (relative, absolute, and inside functions)."""
    return _imports_of_source(path, path.read_bytes())


@cache
def _imports_of_source(path, source):
    # Keyed on the file's bytes: parsing is the cost (the jitted modules' cache keys parse
    # overlapping closures, ~100 parses per process), and an edited file is parsed again.
    package = path.parent.relative_to(PACKAGE_DIR).parts
    found = set()
    for node in ast.walk(ast.parse(source, filename=str(path))):
        if isinstance(node, ast.ImportFrom):
            module = tuple(node.module.split(".")) if node.module else ()
            if node.level:
                base = package[: len(package) - (node.level - 1)] + module
            elif module[:1] == (PACKAGE,):
                base = module[1:]
            else:
                continue
            for alias in node.names:
                found.add(_module_file(base + (alias.name,)) or _module_file(base))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                parts = tuple(alias.name.split("."))
                if parts[0] == PACKAGE:
                    # The longest prefix that is a module of the package.
                    found.update(_module_file(parts[1:n]) for n in range(len(parts), 0, -1))
    found.discard(None)
    return frozenset(found)


def source_files(*modules):
    """Source files of the package that ``modules`` can depend on: their import closure.

    Parameters
    ----------
    modules : str or Path
        Dotted module names (``"contactalpha.engine.kernel"``) or source file paths
        inside the package.

    Returns
    -------
    list of Path
        Sorted; each module's own file included.  Package ``__init__`` files are
        included only when imported by name.
    """
    todo = []
    for module in modules:
        if isinstance(module, Path) or str(module).endswith(".py"):
            path = Path(module).resolve()
        else:
            parts = str(module).split(".")
            path = _module_file(tuple(parts[1:]) if parts[0] == PACKAGE else tuple(parts))
        if path is None or PACKAGE_DIR not in path.parents:
            raise ValueError(f"module {module!r} is not a source file of package {PACKAGE} at {PACKAGE_DIR}")
        todo.append(path)
    seen = set()
    while todo:
        path = todo.pop()
        if path not in seen:
            seen.add(path)
            todo.extend(_imported_files(path) - seen)
    return sorted(seen)


def source_hash(*modules):
    """SHA-256 (hex) of the package sources that ``modules`` can depend on: their code version.

    Any edit of those files, a ``git checkout`` or a revert changes it exactly when the
    code that can run changes; it keys the compiled-kernel cache (``engine.jitcache``)
    and is a parameter of the workflow rules whose results the engine computes.
    """
    digest = hashlib.sha256()
    for path in source_files(*modules):
        digest.update(path.relative_to(PACKAGE_DIR).as_posix().encode() + b"\0")
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()
