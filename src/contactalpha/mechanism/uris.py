"""``package://`` URIs of a robot file resolved to files, as ROS and PyBullet resolve them.

A URDF names its meshes ``package://NAME/path``.  ``NAME``'s folder is, in this order: the
user's ``--package-path NAME=DIR`` (``packages``), a folder ``NAME`` inside one of the
``ROS_PACKAGE_PATH`` entries, or, as PyBullet does, the robot file's own folder when
``NAME/path`` lies under it (pybullet_data's robots write ``package://meshes/...`` beside
their URDF).  Every other relative file name is made absolute against the robot file's folder,
so the resolved text loads from anywhere.  A URI that resolves to no file raises ValueError
naming it and the fix.
"""

import contextlib
import contextvars
import os
import re
from pathlib import Path

ENVIRONMENT = "ROS_PACKAGE_PATH"
_FILENAME = re.compile(r'(filename|file|uri)="([^"]*)"')


def parse_package_paths(items):
    """``{NAME: DIR}`` from ``NAME=DIR`` strings; ValueError naming a malformed one."""
    out = {}
    for item in items or ():
        name, sep, folder = str(item).partition("=")
        if not sep or not name or not folder:
            raise ValueError(f"--package-path {item!r} must be NAME=DIR")
        if not Path(folder).is_dir():
            raise ValueError(f"--package-path {item!r}: {folder!r} is not a folder")
        out[name] = Path(folder)
    return out


def _package_folder(name, packages, base):
    if name in packages:
        return Path(packages[name])
    for entry in os.environ.get(ENVIRONMENT, "").split(os.pathsep):
        if entry and (Path(entry) / name).is_dir():
            return Path(entry) / name
    return None


def resolve(uri, base, packages=None):
    """The file a ``uri`` of a robot file in folder ``base`` names (a ``Path``)."""
    base = Path(base)
    if uri.startswith("package://"):
        name, _, rest = uri.removeprefix("package://").partition("/")
        folder = _package_folder(name, packages or {}, base)
        candidates = [folder / rest] if folder is not None else []
        candidates.append(base / name / rest)  # PyBullet's rule: beside the robot file
        for path in candidates:
            if path.is_file():
                return path
        raise ValueError(
            f"{uri!r}: no file for package {name!r}; give its folder with --package-path {name}=DIR "
            f"(or add its parent to {ENVIRONMENT})"
        )
    if uri.startswith("file://"):
        return Path(uri.removeprefix("file://"))
    return Path(uri) if os.path.isabs(uri) else base / uri


def resolved_text(path, packages=None):
    """The robot file's text with every file name absolute and ``package://`` resolved."""
    path = Path(path)
    text = path.read_text(encoding="utf-8")

    def one(match):
        key, value = match.group(1), match.group(2)
        return f'{key}="{resolve(value, path.parent, packages)}"'

    return _FILENAME.sub(one, text)


def needs_resolving(path):
    """True when the robot file names a ``package://`` URI."""
    return "package://" in Path(path).read_text(encoding="utf-8", errors="replace")


_ACTIVE: contextvars.ContextVar[dict | None] = contextvars.ContextVar("package_paths", default=None)


@contextlib.contextmanager
def using(packages):
    """Resolve ``package://`` with ``packages`` ({NAME: DIR}) inside the block (``tune``'s call)."""
    token = _ACTIVE.set(dict(packages or {}))
    try:
        yield
    finally:
        _ACTIVE.reset(token)


def active():
    """The ``{NAME: DIR}`` of the enclosing ``using`` block ({} outside one)."""
    return _ACTIVE.get() or {}
