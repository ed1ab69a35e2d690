"""Reading and writing result files: atomically, so an interrupted run leaves no half-written file."""

import json
import math
import os
import re
import socket
import sys
import tempfile
from collections.abc import Mapping
from pathlib import Path, PurePath
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray as xr

# netCDF4/HDF5 through h5py: no netCDF C library needed.
ENGINE = "h5netcdf"
# Permissions of written files before the umask, as open() would give them.
FILE_MODE = 0o666


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


# Temporary files of ``write_atomic``: ``.<target>.atomic-<host>-<pid>.<random>.tmp`` beside the
# target.  Host and process name the writer, so that a later write can tell a temporary file left
# by a killed process (kill -9 inside the write) from one being written now.
TMP_TAG = "atomic"
TMP_PATTERN = re.compile(rf"^\.(?P<target>.+)\.{TMP_TAG}-(?P<host>[A-Za-z0-9-]+)-(?P<pid>\d+)\.[^.]+\.tmp$")


def _host():
    """The name of this machine, reduced to letters, digits and dashes (no dots: it sits in a file name)."""
    return re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname()) or "localhost"


def _alive(pid):
    """Whether process ``pid`` of this machine exists (a reused pid counts as alive: kept, not deleted)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def stale_temporaries(directory, target=None):
    """Temporary files of ``write_atomic`` in ``directory`` whose writer is dead.

    Only files written on this machine are judged (a process of another host, on a
    shared file system, cannot be checked); those whose process no longer exists are
    stale: a ``kill -9`` or a power loss hit their write.

    Parameters
    ----------
    directory : path-like
        Searched without recursion; a missing directory has none.
    target : str, optional
        Only the temporary files of this target name.

    Returns
    -------
    list of Path
        Sorted.
    """
    directory = Path(directory)
    if not directory.is_dir():
        return []
    host, stale = _host(), []
    for path in directory.iterdir():
        match = TMP_PATTERN.match(path.name)
        if match is None or match["host"] != host or (target is not None and match["target"] != target):
            continue
        if not _alive(int(match["pid"])):
            stale.append(path)
    return sorted(stale)


def remove_stale_temporaries(directory, target=None, recursive=False):
    """Delete ``stale_temporaries(directory, target)`` (in every subfolder if ``recursive``).

    Returns
    -------
    list of Path
        The files removed.
    """
    folders = [Path(directory)]
    if recursive and folders[0].is_dir():
        folders += sorted(p for p in folders[0].rglob("*") if p.is_dir())
    removed = []
    for folder in folders:
        for path in stale_temporaries(folder, target):
            path.unlink(missing_ok=True)
            removed.append(path)
    return removed


def write_atomic(path, write):
    """Call ``write(tmp_path)`` on a temporary file beside ``path``, then rename it to ``path``.

    The rename is atomic on one file system, so ``path`` is either the old file,
    absent, or complete.  The temporary file is removed if ``write`` fails; one
    left by a killed earlier write of ``path`` (``stale_temporaries``) is removed first.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(path.parent, target=path.name)
    prefix = f".{path.name}.{TMP_TAG}-{_host()}-{os.getpid()}."
    fd, tmp = tempfile.mkstemp(prefix=prefix, suffix=".tmp", dir=path.parent)
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


# A workflow run holds an exclusive lock (flock) on this file, in its working directory, while it
# lives; the kernel releases it when the process ends, however it ends (kill -9 included).  So a
# run that gets the lock knows that no other run is alive there.
RUN_LOCK = Path(".snakemake") / "contactalpha.run.lock"
# Snakemake's own lock files (file persistence): left behind by a run that was killed.
SNAKEMAKE_LOCKS = re.compile(r"^\d+\.(input|output)\.lock$")
# Open lock files of this process: kept open for its lifetime.
_HELD: dict = {}


def claim_workdir(workdir="."):
    """Lock ``workdir`` for this workflow run and clear what killed runs left there.

    Called by the Snakefile in Snakemake's main process.  If no other run holds
    the directory's ``RUN_LOCK``, every Snakemake lock file in ``.snakemake/locks``
    is stale (left by ``kill -9`` or a power loss), so it is removed, and so are
    stale ``write_atomic`` temporaries under ``results/``: the same command then
    resumes, with no ``--unlock``.  If another run is alive, nothing is touched
    and Snakemake reports its lock as usual.

    Returns
    -------
    held : bool
        Whether this process holds the run lock (False: another run is alive, or the
        file system cannot lock).
    removed : list of Path
        Stale files removed.
    """
    import fcntl  # POSIX only: imported here so that the package still imports elsewhere

    workdir = Path(workdir).resolve()
    lock = workdir / RUN_LOCK
    if lock in _HELD:
        return True, []
    lock.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # held by a live run (EWOULDBLOCK), or no locks on this file system
        os.close(fd)
        return False, []
    _HELD[lock] = fd
    locks = workdir / ".snakemake" / "locks"
    removed = sorted(p for p in locks.iterdir() if SNAKEMAKE_LOCKS.match(p.name)) if locks.is_dir() else []
    for path in removed:
        path.unlink(missing_ok=True)
    removed += remove_stale_temporaries(workdir / "results", recursive=True)
    return True, removed


def other_run_alive(workdir="."):
    """True when another process holds ``workdir``'s ``RUN_LOCK``: a workflow run is alive there."""
    import errno
    import fcntl

    lock = Path(workdir).resolve() / RUN_LOCK
    if lock in _HELD or not lock.exists():
        return False
    fd = os.open(lock, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError as err:
        return err.errno in (errno.EWOULDBLOCK, errno.EAGAIN)
    else:
        fcntl.flock(fd, fcntl.LOCK_UN)
        return False
    finally:
        os.close(fd)


# What a second run in the same directory is told (Snakemake's own message advises --unlock,
# which would let two runs write the same files).
ANOTHER_RUN = (
    "contactalpha: another workflow run is alive in this directory ({workdir}); wait for it to "
    "finish (or stop it) and run the command again. Do not use --unlock: both runs would write "
    "the same files."
)


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


def read_json(path, what="data file"):
    """The JSON file ``path`` as Python data; an unreadable or malformed file raises naming itself.

    Raises
    ------
    ValueError
        ``<what> <path> cannot be read (...)`` for a truncated, corrupted or non-UTF-8 file.
    """
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as err:
        raise ValueError(
            f"{what} {path} cannot be read ({type(err).__name__}: {err}): truncated or corrupted; "
            "reinstall the package or ship it again"
        ) from None


def write_json_atomic(path, obj):
    """Write ``obj`` as indented JSON (``json_text``, one space per level) to ``path`` atomically."""
    return write_text_atomic(path, json_text(obj, indent=1) + "\n")


# Global attribute of a written Dataset: the SHA-256 of its variables' values (``data_digest``),
# checked when it is read back, so that a value changed or corrupted after the write is refused.
DIGEST_ATTR = "contactalpha_data_sha256"


def data_digest(ds):
    """SHA-256 (hex) of every variable's name, dims, shape and values, as written and as read back.

    NaN counts as one value whatever its bits (netCDF's fill value reads back as numpy's NaN);
    text is hashed as UTF-8 whether numpy holds it as ``<U`` or as objects.
    """
    import hashlib

    digest = hashlib.sha256()
    for name in sorted(ds.variables, key=str):
        var = ds.variables[name]
        values = np.asarray(var.values)
        digest.update(repr((str(name), tuple(map(str, var.dims)), values.shape)).encode())
        if values.dtype.kind in "OUS":
            digest.update("\0".join(map(str, values.ravel())).encode())
            continue
        if values.dtype.kind in "fc":
            values = np.where(np.isnan(values), np.nan, values).astype(values.dtype)
        digest.update(values.dtype.kind.encode() + str(values.dtype.itemsize).encode())
        digest.update(np.ascontiguousarray(values).tobytes())
    return digest.hexdigest()


def write_dataset_atomic(ds, path):
    """Write an xarray Dataset as netCDF4/HDF5 to ``path`` atomically, with its ``data_digest``."""
    ds = ds.assign_attrs({DIGEST_ATTR: data_digest(ds)})
    return write_atomic(path, lambda tmp: ds.to_netcdf(tmp, engine=ENGINE, invalid_netcdf=False))


def _read_dataset(path):
    """``(ds, digest)``: the file's Dataset without the digest attribute, and the digest (or None).

    Raises ``ValueError`` naming the file when it is not readable netCDF/HDF5 (e.g. truncated).
    """
    import xarray as xr  # here: io is imported by light processes (Snakemake's own) that read none

    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: no such file")
    try:
        ds = xr.load_dataset(path, engine=ENGINE)
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise ValueError(
            f"{path} is not a readable netCDF4/HDF5 file (truncated or corrupted?): {err}; "
            "rerun the step that writes it"
        ) from None
    digest = ds.attrs.pop(DIGEST_ATTR, None)
    if digest is not None and digest != data_digest(ds):
        raise ValueError(
            f"{path}: its values do not match the checksum written with them ({DIGEST_ATTR}): "
            "the file was changed or corrupted after it was written; rerun the step that writes it"
        )
    return ds, digest


def load_dataset(path):
    """Read a netCDF4/HDF5 file fully into memory (the file is closed on return).

    A file written by ``write_dataset_atomic`` is checked against its ``data_digest``.

    Raises
    ------
    ValueError
        Naming the file, if it cannot be read or its values fail the checksum.
    """
    return _read_dataset(path)[0]


def _load_with_digest(path):
    """``load_dataset`` of a workflow result, which must carry its checksum."""
    ds, digest = _read_dataset(path)
    if digest is None:
        raise ValueError(
            f"{path} carries no checksum ({DIGEST_ATTR}); valid: a file written by the workflow "
            "(io.write_dataset_atomic)"
        )
    return ds


def _checked_surface(ds, path):
    """``ds`` if it is an alpha surface (float alpha over strictly increasing epsilon and xi)."""
    if "alpha" not in ds or ds["alpha"].dims != ("epsilon", "xi"):
        raise ValueError(f"{path} is not an alpha surface; valid: a Dataset with alpha over (epsilon, xi)")
    if ds["alpha"].dtype.kind != "f":
        raise ValueError(f"{path}: alpha has dtype {ds['alpha'].dtype}; valid: floating point numbers")
    for dim in ("epsilon", "xi"):
        values = ds[dim].values
        if values.dtype.kind != "f" or not np.all(np.diff(values) > 0):
            raise ValueError(
                f"{path}: coordinate {dim} is not strictly increasing floats ({values[:6]!r}...); "
                "valid: sorted values without duplicates"
            )
    alpha = ds["alpha"].values
    solved = ds["status"].values == 0 if "status" in ds else np.isfinite(alpha)
    bad = solved & ~(np.isfinite(alpha) & (alpha >= 0.0))
    if np.any(bad):
        i, j = (int(k[0]) for k in np.nonzero(bad))
        raise ValueError(
            f"{path}: {int(bad.sum())} point(s) solved (status 0) with alpha not a finite number >= 0, "
            f"first alpha = {float(alpha[i, j])!r} at epsilon = {float(ds['epsilon'][i])!r}, "
            f"xi = {float(ds['xi'][j])!r}; valid: alpha >= 0 where solved, NaN with a failed status"
        )
    return ds


def load_surface(path: str | Path) -> "xr.Dataset":
    """The alpha(eps, xi) surface Dataset written by the workflow (``results/surface.h5``).

    Raises
    ------
    ValueError
        Naming the file: if it cannot be read (e.g. truncated), carries no checksum or fails it
        (a value changed after the write), holds no floating-point ``alpha`` over dims ``epsilon``
        and ``xi``, a solved point (status 0) has an alpha that is not finite and >= 0, a
        coordinate is not strictly increasing, or it is a single chunk of a surface
        (``load_surface_chunk``).
    """
    ds = _checked_surface(_load_with_digest(path), path)
    if "chunk" in ds.attrs:
        raise ValueError(
            f"{path} is chunk {ds.attrs['chunk']} of {ds.attrs.get('chunks', '?')}, not a whole surface; "
            "valid: the merged file (results/surface.h5), or read chunks with load_surface_chunk"
        )
    return ds


def load_surface_chunk(path):
    """One chunk file of a surface (``results/surface/chunks/chunk_<k>.h5``), checked as ``load_surface``.

    Raises
    ------
    ValueError
        If it is not an alpha surface or carries no ``chunk`` and ``chunks`` attributes.
    """
    ds = _checked_surface(_load_with_digest(path), path)
    if "chunk" not in ds.attrs or "chunks" not in ds.attrs:
        raise ValueError(
            f"{path} is not a surface chunk (no chunk attribute); valid: a file of compute_chunk"
        )
    return ds


def script_logger(name, path=None):
    """A logger for a workflow script that writes to stderr and, if given, to the log file ``path``."""
    import logging

    logger = logging.getLogger(name)
    logger.setLevel(logging.INFO)
    logger.propagate = False
    fmt = logging.Formatter("%(asctime)s %(name)s %(levelname)s: %(message)s", "%Y-%m-%d %H:%M:%S")
    handlers: list[logging.Handler] = [logging.StreamHandler()]
    if path:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(logging.FileHandler(path, mode="w"))
    for handler in handlers:
        handler.setFormatter(fmt)
        logger.addHandler(handler)
    if path:
        _log_uncaught(logger, handlers[-1])
    return logger


def _log_uncaught(logger, file_handler):
    """Write a script's uncaught exception, traceback included, to its log file too.

    Snakemake shows a failed job's stderr in its own output only; the rule's log would end
    mid-way with no word of the error.  The exception still reaches the previous hook
    (Python's: the traceback on stderr, exit status 1).
    """
    import logging

    previous = sys.excepthook

    def hook(kind, value, tb):
        if not issubclass(kind, KeyboardInterrupt):
            record = logger.makeRecord(
                logger.name, logging.ERROR, "", 0, "uncaught exception", None, (kind, value, tb)
            )
            file_handler.handle(record)
            file_handler.flush()
        previous(kind, value, tb)

    sys.excepthook = hook
