"""Robot files as they ship: unnamed collisions, no floor, meshes one engine reads and another not.

- **Unnamed collisions.**  pybullet_data's URDFs (and most exported robots) leave their
  ``<collision>`` elements unnamed, so no ``--pair`` could name them.  ``prepared_urdf`` names
  each unnamed one ``LINK/collisionN``, N its index among the link's ``<collision>`` elements
  (from 0; ``collision_name``), before any engine reads the file.
- **A floor.**  ``ground=True`` adds a link ``ground`` with a box collision ``ground`` (its top at
  z = 0, ``GROUND_SIZE``: a box, since Drake has no signed distance between a half space and
  anything but a sphere), fixed to the URDF's root link: the world where the base is fixed (the
  default in every engine).  Its material is the engine's default; ``tune`` writes the pair's
  values on it.
- **Meshes.**  ``unreadable_meshes`` lists the mesh files an engine's reader refuses (Drake
  reads no ``.stl`` or ``.dae``); ``engine_for`` picks the first installed engine that reads the
  file (``ENGINE_ORDER``), and ``tune`` prints the choice.

Every file name of the prepared copy is absolute (``uris.resolved_text``), so it loads from the
folder it is written to.
"""

import importlib.util
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

from contactalpha.adapters.registry import ENGINES

from . import uris

# The floor ``ground=True`` adds: a box (m), its top at z = 0.
GROUND_SIZE = (20.0, 20.0, 0.2)
GROUND = "ground"
# A model file's format by its suffix.
FORMATS = {".xml": "mjcf", ".mjcf": "mjcf", ".urdf": "urdf", ".sdf": "sdf"}
# The engines ``engine_for`` tries first, in this order, before the rest in the registry's order (a
# URDF: Drake first, as ``tune`` chose before, then MuJoCo, then PyBullet).
PREFERRED = ("drake",)


def _engine_order():
    """``((engine, module, suffixes it opens, mesh suffixes its reader refuses), ...)`` from the records."""
    files = {e.name: (e.loader.module, e.model_file) for e in ENGINES
             if e.model_file is not None and e.model_file.tuner is not None}  # fmt: skip
    names = [n for n in PREFERRED if n in files] + [n for n in files if n not in PREFERRED]
    rows = ((n, *files[n]) for n in names)
    return tuple((n, module, mf.opens, mf.refused_meshes) for n, module, mf in rows if mf is not None)


# Which engine opens which model files, in the order ``engine_for`` tries them; the Python module
# each needs, and the mesh suffixes its reader refuses (each engine's record: ``model_file``).
ENGINE_ORDER = _engine_order()


def collision_name(link: str, index: int) -> str:
    """The name ``prepared_urdf`` gives the ``index``-th unnamed ``<collision>`` of ``link``."""
    return f"{link}/collision{int(index)}"


def _meshes(path):
    root = ET.parse(path).getroot()
    return [m.get("filename") or "" for m in root.iter("mesh")]


def unreadable_meshes(path: str | Path, engine: str) -> list[str]:
    """The mesh file names of the robot file that ``engine``'s reader refuses."""
    return _refused(path, file_format(path), engine)


def _refused(path, fmt, engine):
    refused = next(row[3] for row in ENGINE_ORDER if row[0] == engine)
    if fmt == "mjcf" or not refused:
        return []
    return [m for m in _meshes(path) if Path(m).suffix.lower() in refused]


def file_format(path: str | Path) -> str:
    """The model file's format by its suffix (``FORMATS``): "mjcf", "urdf", "sdf", or "" for another."""
    return FORMATS.get(Path(path).suffix.lower(), "")


def engine_by_suffix(path: str | Path) -> str:
    """The engine ``engine_for`` tries first for the file's suffix, without opening the file.

    For a file that is not there (it is refused where it is read): the first of ``ENGINE_ORDER``
    that opens the suffix, else the first engine that reads model files.
    """
    suffix = Path(path).suffix.lower()
    opening = [row[0] for row in ENGINE_ORDER if suffix in row[2]]
    readers = [e.name for e in ENGINES if e.model_file is not None and e.model_file.reader is not None]
    return (opening or readers)[0]


def engine_for(path: str | Path) -> tuple[str, str]:
    """``(engine, why)``: the first installed engine of ``ENGINE_ORDER`` that reads the file."""
    suffix = Path(path).suffix.lower()
    fmt = file_format(path)
    skipped = []
    for name, module, suffixes, _ in ENGINE_ORDER:
        if suffix not in suffixes:
            continue
        if importlib.util.find_spec(module) is None:
            skipped.append(f"{name} is not installed")
            continue
        refused = _refused(path, fmt, name)
        if refused:
            skipped.append(f"{name} reads no {Path(refused[0]).suffix} meshes ({refused[0]})")
            continue
        return name, "; ".join(skipped) or "the installed engine that reads it"
    raise ValueError(f"model = {str(path)!r}: no installed engine reads it ({'; '.join(skipped) or suffix})")


def needs_preparing(fmt: str, pair, ground: bool) -> bool:
    """True for a URDF (``fmt``) whose pair names an unnamed collision ``LINK/collisionN``, or ``ground``."""
    if fmt != "urdf":
        return False
    return bool(ground) or any("/collision" in str(name) for name in pair)


def prepared_urdf(path: str | Path, ground: bool = False, folder: str | Path | None = None) -> Path:
    """A copy of the URDF with its unnamed collisions named and, with ``ground``, a floor added.

    Written into ``folder`` (default a new temporary folder, kept: the tuned files refer to it).
    """
    path = Path(path)
    root = ET.fromstring(uris.resolved_text(path, uris.active()))
    for link in root.iter("link"):
        for i, col in enumerate(link.findall("collision")):
            if not col.get("name"):
                col.set("name", collision_name(link.get("name", ""), i))
    if ground:
        names = {link.get("name") for link in root.iter("link")}
        if GROUND in names:
            raise ValueError(f"model = {str(path)!r} has a link {GROUND!r} already: --ground adds one")
        children = {c.get("link") for j in root.iter("joint") for c in j.findall("child")}
        base = str(
            next(link.get("name") for link in root.findall("link") if link.get("name") not in children)
        )
        link = ET.SubElement(root, "link", name=GROUND)
        col = ET.SubElement(link, "collision", name=GROUND)
        ET.SubElement(col, "origin", xyz=f"0 0 {-GROUND_SIZE[2] / 2!r}", rpy="0 0 0")
        ET.SubElement(ET.SubElement(col, "geometry"), "box", size=" ".join(repr(s) for s in GROUND_SIZE))
        joint = ET.SubElement(root, "joint", name=f"{GROUND}_joint", type="fixed")
        ET.SubElement(joint, "parent", link=base)
        ET.SubElement(joint, "child", link=GROUND)
        ET.SubElement(joint, "origin", xyz="0 0 0", rpy="0 0 0")
    out = Path(folder) if folder is not None else Path(tempfile.mkdtemp(prefix="contactalpha_"))
    target = out / path.name
    ET.ElementTree(root).write(target)
    return target
