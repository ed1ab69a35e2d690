"""Numba's on-disk cache, keyed on every package source a kernel can depend on.

Numba keys a ``cache=True`` function on the source of the file that defines it
only.  A kernel inlines the functions and module constants it calls, so an
edit of a callee module (``rk.py``, ``events.py``, ``tableau.py``, ...), a
revert, or a ``git checkout`` that touches only such a module would leave the
old compiled code running with no warning.  ``PackageSourceLocator`` keys the
cache of every function defined inside this package on
``provenance.source_hash`` of the defining file, the hash of its whole import
closure: the cache lives in a sub-folder named after the hash, and the hash is
the index's source stamp.  A changed closure finds an empty folder and
compiles; a reverted one finds its old folder again.

Where no base folder can be written (a read-only install, no writable home, no
``NUMBA_CACHE_DIR``), the kernels are cached in a temporary folder of this process
only (``ProcessTempLocator``): they compile in every process, and a warning says so
once, naming ``NUMBA_CACHE_DIR``.

Functions defined outside the package (users' own jitted code) never reach
this locator's folders: it declines them and numba's own locators take over.
Concurrent cold starts are as safe as numba's own cache: the folder is created
with ``exist_ok``, and numba writes index and data files to a temporary name
and renames them into place.
"""

import atexit
import os
import shutil
import tempfile
import time
import warnings
from functools import cache
from pathlib import Path

from numba.core.caching import (
    CacheImpl,
    InTreeCacheLocator,
    UserProvidedCacheLocator,
    UserWideCacheLocator,
    _CacheLocator,
)

from contactalpha.provenance import PACKAGE_DIR, source_hash

# Prefix of the hash-named cache folders inside numba's usual cache folder.
FOLDER_PREFIX = "numba-src-"
# Characters of the hash in the folder name (64 bits: collisions are not a concern).
FOLDER_HASH_CHARS = 16
# Folders of other code versions kept beside the current one (most recently used first),
# so that switching branches back and forth does not recompile every time.
KEEP_FOLDERS = 8
# Never prune a folder used this recently (seconds): another process may be using it.
PRUNE_GRACE_S = 3600.0
# numba's own locators, in numba's order; the first that can write gives the base folder.
BASE_LOCATORS = (UserProvidedCacheLocator, InTreeCacheLocator, UserWideCacheLocator)


@cache
def _code_version(py_file):
    # Once per process and file: the modules a process runs are imported once.
    return source_hash(Path(py_file))


def _inside_package(py_file):
    try:
        return PACKAGE_DIR in Path(py_file).resolve().parents
    except OSError:
        return False


def prune(base, keep=KEEP_FOLDERS, grace_s=PRUNE_GRACE_S):
    """Remove all but the ``keep`` most recently used hash folders in ``base``.

    Folders modified within ``grace_s`` seconds are kept in any case.
    """
    folders = []
    for entry in os.scandir(base):
        if entry.name.startswith(FOLDER_PREFIX) and entry.is_dir():
            try:
                folders.append((entry.stat().st_mtime, entry.path))
            except OSError:
                continue  # removed by another process meanwhile
    folders.sort(reverse=True)
    now = time.time()
    for mtime, path in folders[keep:]:
        if now - mtime > grace_s:
            shutil.rmtree(path, ignore_errors=True)


class PackageSourceLocator(_CacheLocator):
    """Cache locator for functions of this package: folder and stamp from the source hash."""

    def __init__(self, base, digest):
        self._base = base
        self._digest = digest
        self._path = os.path.join(base.get_cache_path(), FOLDER_PREFIX + digest[:FOLDER_HASH_CHARS])

    def get_cache_path(self):
        """The hash-named folder inside the base locator's folder."""
        return self._path

    def get_source_stamp(self):
        """The source hash of the defining file's import closure."""
        return self._digest

    def get_disambiguator(self):
        """As numba's: the line number of the function."""
        return self._base.get_disambiguator()

    @classmethod
    def from_function(cls, py_func, py_file):
        """A locator for functions defined in this package; None (numba decides) otherwise."""
        if not _inside_package(py_file):
            return None
        digest = _code_version(str(Path(py_file).resolve()))
        for base_cls in (*BASE_LOCATORS, ProcessTempLocator):
            base = base_cls.from_function(py_func, py_file)
            if base is None:
                continue
            self = cls(base, digest)
            is_new = not os.path.isdir(self._path)
            try:
                self.ensure_cache_path()
            except OSError:
                continue
            if is_new:
                prune(base.get_cache_path())
            return self
        return None


class ProcessTempLocator(UserWideCacheLocator):
    """numba's user-wide locator moved into a temporary folder that lives as long as this process.

    The last resort of ``PackageSourceLocator``: without it numba refuses to compile a
    ``cache=True`` function when no folder can be written ("no locator available").
    """

    def __init__(self, py_func, py_file):
        super().__init__(py_func, py_file)
        self._cache_path = os.path.join(_process_temp_folder(), self.get_suitable_cache_subpath(py_file))


@cache
def _process_temp_folder():
    folder = tempfile.mkdtemp(prefix="contactalpha-numba-")
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    warnings.warn(
        "contactalpha: no writable folder for numba's cache (a read-only install?): compiled kernels are "
        "kept for this process only and compile again in the next; set NUMBA_CACHE_DIR to a writable "
        "folder to keep them",
        RuntimeWarning,
        stacklevel=2,
    )
    return folder


def install():
    """Put ``PackageSourceLocator`` first in numba's list of cache locators (idempotent)."""
    if PackageSourceLocator not in CacheImpl._locator_classes:
        CacheImpl._locator_classes.insert(0, PackageSourceLocator)
