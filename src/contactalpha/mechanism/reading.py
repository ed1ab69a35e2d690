"""Reading a pair's contact from a model file: the engines' readers, chosen once per file.

``READERS`` are the model-file readers of the engines' records (``adapters.registry``);
``reader_for`` picks the one that reads a file's suffix (and is installed); ``reading`` checks the
file and chooses its reader once, and reads the pair's ``MechanismContact`` at any configuration
with it, the file's format (``robot_files.file_format``) carried on the contact for the writers
and the engine loops; ``read_contact`` is one such reading.
"""

import importlib.util
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from contactalpha.adapters.registry import model_readers

from .contact import MechanismContact
from .inputs import check_coordinates, check_model_size
from .robot_files import file_format


@dataclass(frozen=True)
class Reader:
    """A model reader: ``name``, the Python ``module`` it needs, file ``suffixes``, ``read`` call."""

    name: str
    module: str
    suffixes: tuple
    read: Callable[..., Any]


# The engines' model-file readers, from their records (``adapters.registry``).
READERS = tuple(Reader(name, *reader) for name, reader in model_readers().items())


def reader_for(model, reader: str | None = None) -> Reader:
    """The ``Reader`` of ``model``'s suffix: ``reader`` (a name of ``READERS``), else the first installed.

    ValueError where ``reader`` is not one, or none reads the suffix; ImportError where none that
    reads it is installed.
    """
    path = Path(model)
    names = tuple(r.name for r in READERS)
    if reader is not None and reader not in names:
        raise ValueError(f"reader = {reader!r} is outside the valid choices {names}")
    fits = [r for r in READERS if (reader is None or r.name == reader) and path.suffix.lower() in r.suffixes]
    if not fits:
        raise ValueError(
            f"model = {str(model)!r}: no reader for {path.suffix!r} files "
            "(mujoco: MJCF/URDF, drake: SDF/URDF)"
        )
    ready = [r for r in fits if importlib.util.find_spec(r.module) is not None]
    if not ready:
        raise ImportError(f"reading {path.suffix} models needs {' or '.join(r.module for r in fits)}")
    return ready[0]


def read_contact(model, pair, *, reader=None, qpos=None, qvel=None, speed=None, forces=None, base=None):
    """``MechanismContact`` of ``pair`` in ``model`` read by ``reader`` (default: the first that reads it).

    Parameters
    ----------
    model : path of an MJCF, URDF or SDF file.
    pair : (geometry 1, geometry 2) names; the normal points from 1 to 2.
    reader : "mujoco" or "drake" (``READERS``), or None.
    qpos : joint positions (the engine's coordinates; default the model's own).
    qvel, speed : the approach: joint velocities, or the closing speed of the contact point, m/s.
    forces : {body: (fx, fy, fz)} constant forces at bodies' centres of mass, N, world axes.
    base : Drake: "fixed" (default: a URDF's root link welded to the world, as MuJoCo and PyBullet
        load it) or "floating" (``drake_model.BASES``).
    """
    return reading(model, pair, reader=reader, qvel=qvel, speed=speed, forces=forces, base=base)(qpos)


def reading(model, pair, *, reader=None, qvel=None, speed=None, forces=None, base=None):
    """``read(qpos) -> MechanismContact`` of ``pair`` in ``model``: the file checked, its reader chosen once.

    The parameters are ``read_contact``'s; ``tune`` reads the pair at several configurations
    (``touch.first_touch``) with one reader.
    """
    path = Path(model)
    if not path.is_file():
        raise ValueError(f"model = {str(model)!r} is not a file")
    check_model_size(path)
    qvel = check_coordinates("qvel", qvel)
    pair = tuple(str(g) for g in pair)
    if len(pair) != 2:
        raise ValueError(f"pair = {pair!r} must name two geometries")
    chosen = reader_for(path, reader)
    extra = {}
    if base is not None:
        if chosen.name != "drake":
            raise ValueError(f"base = {base!r}: MuJoCo fixes a URDF's root link (an MJCF says its own base "
                             "with a <freejoint>); base chooses Drake's")  # fmt: skip
        extra["base"] = base
    fmt = file_format(path)

    def read(qpos) -> MechanismContact:
        q = check_coordinates("qpos", qpos)
        contact = chosen.read(path, pair, qpos=q, qvel=qvel, speed=speed, forces=forces, **extra)
        return replace(contact, file_format=fmt)

    return read
