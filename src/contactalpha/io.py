"""Reading and writing result files: atomically, so an interrupted run leaves no half-written file."""

import json
import math
import os
import tempfile
from collections.abc import Mapping
from pathlib import Path, PurePath

import numpy as np
import xarray as xr

# netCDF4/HDF5 through h5py: no netCDF C library needed.
ENGINE = "h5netcdf"
# Permissions of written files before the umask, as open() would give them.
FILE_MODE = 0o666


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path, write):
    """Call ``write(tmp_path)`` on a temporary file beside ``path``, then rename it to ``path``.

    The rename is atomic on one file system, so ``path`` is either the old file,
    absent, or complete.  The temporary file is removed if ``write`` fails.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.chmod(tmp, FILE_MODE & ~_umask())  # mkstemp makes 0600; results are for everyone to read
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def write_text_atomic(path, text):
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return write_atomic(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))


def jsonable(obj):
    """``obj`` as plain JSON data, for ``json_text``.

    NumPy scalars and arrays become Python numbers and lists, tuples lists, keys and paths strings,
    NaN and infinite floats ``None`` (JSON has no such numbers).  Anything else is returned
    unchanged, so that ``json`` refuses what it cannot write.
    """
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple | np.ndarray):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, PurePath):
        return str(obj)
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def json_text(obj, *, indent=None, sort_keys=False):
    """The one JSON form of results: ``jsonable(obj)``, strict (no NaN literals)."""
    return json.dumps(jsonable(obj), indent=indent, sort_keys=sort_keys, allow_nan=False)


def write_json_atomic(path, obj):
    """Write ``obj`` as indented JSON (``json_text``, one space per level) to ``path`` atomically."""
    return write_text_atomic(path, json_text(obj, indent=1) + "\n")


def write_dataset_atomic(ds, path):
    """Write an xarray Dataset as netCDF4/HDF5 to ``path`` atomically."""
    return write_atomic(path, lambda tmp: ds.to_netcdf(tmp, engine=ENGINE, invalid_netcdf=False))


def load_dataset(path):
    """Read a netCDF4/HDF5 file fully into memory (the file is closed on return)."""
    return xr.load_dataset(path, engine=ENGINE)


def load_surface(path):
    """The alpha(eps, xi) surface Dataset written by the workflow (``results/surface.h5``).

    Raises
    ------
    ValueError
        If the file holds no ``alpha`` over dims ``epsilon`` and ``xi``.
    """
    ds = load_dataset(path)
    if "alpha" not in ds or ds["alpha"].dims != ("epsilon", "xi"):
        raise ValueError(f"{path} is not an alpha surface; valid: a Dataset with alpha over (epsilon, xi)")
    return ds


def script_logger(name, path=None):
    """A logger for a workflow script that writes to stderr and, if given, to the log file ``path``."""
    import logging

    logger = logging.getLogger(name)
    logger.setLevel(logging.INFO)
    logger.propagate = False
    fmt = logging.Formatter("%(asctime)s %(name)s %(levelname)s: %(message)s", "%Y-%m-%d %H:%M:%S")
    handlers = [logging.StreamHandler()]
    if path:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(logging.FileHandler(path, mode="w"))
    for handler in handlers:
        handler.setFormatter(fmt)
        logger.addHandler(handler)
    return logger
