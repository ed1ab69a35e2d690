"""Shipped exact-damping tables of the nonlinear laws: loaded, checked, evaluated at formula speed.

A law's file (``data/law_table_<law>.npz``, built by ``table_build.py``) holds two tables in
the layout of the Hunt-Crossley n = 3/2 tables (``engine/table.py``), so the engine's jitted
evaluators ``alpha_from_table`` (Stronge's eps: two regions cut along the law's separation
boundary) and ``kinematic_alpha_from_table`` (Newton's e_N) read them as they are; they return
the law's damping ``p`` in place of alpha.  On load every array's shape is checked against its
grid and the file's SHA-256 of the arrays against the one it records: a changed or truncated
file is refused, never evaluated.
"""

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contactalpha.engine.codes import NOT_CONVERGED, OK
from contactalpha.engine.table import (
    G_COUNT,
    G_K_ETA,
    G_K_Q,
    G_N_ETA,
    G_N_P,
    G_S_ETA,
    G_S_P,
    alpha_from_table_rows,
    kinematic_alpha_from_table_rows,
    lookup_many,
)
from contactalpha.io import json_text, write_atomic

DATA = Path(__file__).parents[1] / "data"
# Bumped whenever the meaning of the stored arrays changes.
TABLE_FORMAT = "law-table-1"
# Arrays of the energetic table, in the argument order of ``engine.table.alpha_from_table``.
ENERGETIC_NAMES = ("b_t", "b_c", "s_tx", "s_ty", "s_c", "n_tx", "n_ty", "n_c", "geom")
# Arrays of the kinematic table, in the argument order of ``kinematic_alpha_from_table``.
KINEMATIC_NAMES = ("k_tx", "k_ty", "k_c", "k_geom")
BUILD_COMMAND = "python -m contactalpha.laws.table_build"


def checksum(arrays):
    """SHA-256 (hex) of the arrays' names, dtypes, shapes and bytes, in name order."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}:{a.dtype.str}:{a.shape};".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _expected_shapes(a):
    """Shape each array must have, from the node counts in its grid (quintic, clamped uniform knots)."""

    def count(geom, start):
        return int(geom[start + G_COUNT])

    g, k = a["geom"], a["k_geom"]
    se, sp, ne, np_ = (count(g, s) for s in (G_S_ETA, G_S_P, G_N_ETA, G_N_P))
    ke, kq = count(k, G_K_ETA), count(k, G_K_Q)
    return {
        "geom": g.shape,
        "k_geom": k.shape,
        "b_t": (se + 10,),
        "b_c": (se + 4,),
        "s_tx": (se + 10,),
        "s_ty": (sp + 10,),
        "s_c": (se + 4, sp + 4),
        "n_tx": (ne + 10,),
        "n_ty": (np_ + 10,),
        "n_c": (ne + 4, np_ + 4),
        "k_tx": (ke + 10,),
        "k_ty": (kq + 10,),
        "k_c": (ke + 4, kq + 4),
    }


def check_arrays(arrays, meta, path):
    """Refuse tables whose format, shapes or checksum differ from what their file records."""
    hint = f"rebuild it with `{BUILD_COMMAND} {meta.get('law', '')}`"
    if meta.get("format") != TABLE_FORMAT:
        raise ValueError(f"law table {path} has format {meta.get('format')!r}, expected {TABLE_FORMAT}; {hint}")
    for name, shape in _expected_shapes(arrays).items():
        if arrays[name].shape != shape:
            raise ValueError(f"law table {path}: array {name} has shape {arrays[name].shape}, expected {shape}")
    got = checksum(arrays)
    if got != meta.get("sha256"):
        raise ValueError(f"law table {path}: checksum {got[:12]}… differs from the recorded one; {hint}")


def save_law_tables(arrays, meta, path):
    """Write a law's tables and their meta (with the arrays' checksum) to ``path`` atomically."""
    meta = dict(meta, sha256=checksum(arrays))

    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **arrays, meta=json_text(meta))

    return write_atomic(Path(path), write)


def load_law_tables(path):
    """``(arrays by name, meta)`` of a law's table file, checked (``check_arrays``)."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"law table {path} not found; build it with `{BUILD_COMMAND}`")
    with np.load(path) as z:
        meta = json.loads(str(z["meta"]))
        arrays = {k: np.ascontiguousarray(z[k]) for k in (*ENERGETIC_NAMES, *KINEMATIC_NAMES)}
    check_arrays(arrays, meta, path)
    return arrays, meta


_LOADED: dict = {}


@dataclass(frozen=True)
class LawTable:
    """A law's shipped exact-damping tables (``file`` in the package's data): the inverse only.

    ``damping`` returns the law's ``p`` for 0.01 <= target <= 1 and 0 <= xi <= 0.99 (``NaN`` with
    status NOT_CONVERGED outside, never an extrapolated number).
    """

    file: str
    name: str = "law table"

    @property
    def path(self):
        """The shipped file."""
        return DATA / self.file

    def arrays(self):
        """The checked arrays by name and the meta (read once per process)."""
        if self.file not in _LOADED:
            _LOADED[self.file] = load_law_tables(self.path)
        return _LOADED[self.file]

    def restitution(self, law, p, A, xi, kinematic):
        """Not offered: the table holds the inverse."""
        raise ValueError(f"law {law.name!r} has no fast forward map; law.impact(p, xi) computes it")

    def damping(self, law, target, kinematic, A, xi):
        """(p, status code) from the table at flat ``target``, ``xi``."""
        a, _ = self.arrays()
        if kinematic:
            p = lookup_many(kinematic_alpha_from_table_rows, target, xi, tuple(a[k] for k in KINEMATIC_NAMES))
        else:
            p = lookup_many(alpha_from_table_rows, target, xi, tuple(a[k] for k in ENERGETIC_NAMES))
        return p, np.where(np.isfinite(p), OK, NOT_CONVERGED)
