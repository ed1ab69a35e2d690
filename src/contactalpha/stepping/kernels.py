"""The table of the engines' step maps, and one compiled copy of each generic kernel per engine.

Numba cannot cache a kernel that takes a function argument, so the drop, phase and inverse kernels
(``drop``, ``phase``, ``affine_phase``, ``batch_inverse``) are written once as *templates* that
call the map through the placeholders below (``engine_step``, ``engine_surface``,
``engine_branches``, ``engine_branch``) and take the engine's *kernel code*.  ``for_engine(code,
template)`` is the template compiled for one engine: a copy of its function (and of every
template it calls) whose globals name that engine's map (``specialise``), with its own numba
cache entry.  A first call therefore compiles the kernels of its path for its engine only, never
another engine's map.

Inside a copy the code is checked: a code other than the copy's own gives NaN (and so a failed
drop, a failed mean), never another engine's step.  From Python, an unknown code is a ValueError
naming the registered ones (``engine_map``).  The built-in maps are one ``EngineMap`` line each in
``MAPS``; an engine outside this folder registers its map at run time (``register_map``, from its
step-map module: docs/adding-an-engine.md), which gives it a fresh code, never one another map has
or had.  The registry (``registry.py``) carries the code with the engine's capabilities.
"""

import hashlib
import inspect
import itertools
import math
import threading
import types
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numba import jit, njit
from numba.core.caching import NullCache
from numba.core.registry import CPUDispatcher

from contactalpha.provenance import PACKAGE_DIR, source_hash

from . import drake_map, mujoco_map, pybullet_map

# Kernel codes: the key of each engine's map in ``MAPS``.
MUJOCO = 0
PYBULLET = 1
DRAKE = 2


@njit(cache=True)
def no_surface(p: np.ndarray) -> float:
    """The surface a user reads a drop at, for maps whose solver surface is that surface: 0."""
    return 0.0


@njit(cache=True)
def _unknown_step(z, w, p, h, accel):
    return math.nan, math.nan


@njit(cache=True)
def _unknown_branches(p, h, accel, forms, maps):
    maps[:] = math.nan
    return 0


@njit(cache=True)
def _unknown_branch(vals):
    return 0


@dataclass(frozen=True)
class EngineMap:
    """One engine's step map as the kernels call it.

    Attributes
    ----------
    name : the engine's key (as in ``registry.STEPPERS``).
    code : its kernel code.
    step : ``step_<engine>(z, w, p, h, accel) -> (z, w)`` (jitted).
    surface : ``p -> `` the height in the map's z of the surface a user reads a drop at (jitted).
    branches : ``branches_<engine>(p, h, accel, forms, maps) -> forms' count`` for a piecewise-affine
        map (``affine_phase``), else None.
    branch : ``branch_<engine>(vals) -> branch`` from the forms' values, else None.
    n_forms, n_branches : the piecewise-affine map's forms and branches (0 otherwise).
    tag : the suffix of the kernels' copies for this map (their names and numba cache entries);
        "" is the name (the built-in maps).  ``register_map`` adds the code and the map's sources'
        hash, so that an edited map compiles afresh.
    cached : whether the copies are cached on disk (``register_map``: not for a map without a
        source file).
    """

    name: str
    code: int
    step: Callable
    surface: Callable = no_surface
    branches: Callable | None = None
    branch: Callable | None = None
    n_forms: int = 0
    n_branches: int = 0
    tag: str = ""
    cached: bool = True

    @property
    def affine(self) -> bool:
        """Whether the map is piecewise affine (branches and their affine steps)."""
        return self.branches is not None

    def overrides(self) -> dict[str, Any]:
        """The placeholders' globals a template's copy for this engine takes (``specialise``)."""
        return {
            "MAP_CODE": self.code,
            "MAP_STEP": self.step,
            "MAP_SURFACE": self.surface,
            "MAP_BRANCHES": self.branches if self.affine else _unknown_branches,
            "MAP_BRANCH": self.branch if self.affine else _unknown_branch,
            "MAP_N_BRANCHES": self.n_branches,
        }


MAPS = {
    m.code: m
    for m in (
        EngineMap("mujoco", MUJOCO, mujoco_map.step_mujoco, no_surface, mujoco_map.branches_mujoco,
                  mujoco_map.branch_mujoco, mujoco_map.N_FORMS, mujoco_map.N_BRANCHES),
        EngineMap("pybullet", PYBULLET, pybullet_map.step_pybullet, pybullet_map.surface_pybullet,
                  pybullet_map.branches_pybullet, pybullet_map.branch_pybullet, pybullet_map.N_FORMS,
                  pybullet_map.N_BRANCHES),
        EngineMap("drake", DRAKE, drake_map.step_drake),
    )
}  # fmt: skip

# Piecewise-affine maps (``affine_phase``): code -> (forms, branches).  Branch 0 applies no force.
AFFINE = {code: (m.n_forms, m.n_branches) for code, m in MAPS.items() if m.affine}
MAX_FORMS = max(forms for forms, _ in AFFINE.values())
MAX_BRANCHES = max(count for _, count in AFFINE.values())

# The placeholders' globals in the templates themselves: no engine (every code is unknown there).
MAP_CODE = -1
MAP_STEP = _unknown_step
MAP_SURFACE = no_surface
MAP_BRANCHES = _unknown_branches
MAP_BRANCH = _unknown_branch
MAP_N_BRANCHES = 0


# The next code ``register_map`` hands out: past every built-in one, and never handed out twice.
_FRESH_CODES = itertools.count(max(MAPS) + 1)
_REGISTER_LOCK = threading.Lock()


def register_map(
    name: str,
    step: Callable,
    *,
    surface: Callable = no_surface,
    branches: Callable | None = None,
    branch: Callable | None = None,
    n_forms: int = 0,
    n_branches: int = 0,
) -> EngineMap:
    """Register an engine's step map at run time: its ``EngineMap``, with a fresh kernel code.

    ``step``, ``surface``, ``branches`` and ``branch`` are jitted functions as in ``EngineMap``.
    The code is one no map has or had in this process, so a kernel given it runs this map only;
    ``for_engine`` then makes the kernels' copies for it, cached on disk under a tag holding the
    code and the hash of the map's source files (their import closure for the package's own).
    ValueError for a name that is not an identifier or is registered already, for branches
    without their branch function and counts, and for more forms or branches than the affine
    kernels hold (``MAX_FORMS``, ``MAX_BRANCHES``).
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"step map name = {name!r} is not an identifier (it names the kernels' copies)")
    functions = [f for f in (step, surface, branches, branch) if f is not None]
    if not all(callable(f) for f in functions):
        raise ValueError(f"step map {name!r}: step, surface, branches and branch must be jitted functions")
    affine = branches is not None
    if (branch is not None) != affine or (affine and not (n_forms > 0 and n_branches > 0)):
        raise ValueError(f"step map {name!r}: an affine map needs branches, branch, n_forms and n_branches")
    if n_forms > MAX_FORMS or n_branches > MAX_BRANCHES:
        raise ValueError(
            f"step map {name!r}: n_forms = {n_forms}, n_branches = {n_branches}; the affine kernels hold "
            f"at most {MAX_FORMS} forms and {MAX_BRANCHES} branches"
        )
    digest = _sources_digest(functions)
    with _REGISTER_LOCK:
        for m in MAPS.values():
            if m.name == name:
                raise ValueError(f"step map {name!r} is registered already, with kernel code {m.code}")
        code = next(_FRESH_CODES)
        m = EngineMap(name, code, step, surface, branches, branch, n_forms, n_branches,
                      tag=f"{name}_{code}_{(digest or '')[:12]}", cached=digest is not None)  # fmt: skip
        MAPS[code] = m
        if m.affine:
            AFFINE[code] = (n_forms, n_branches)
    return m


def _sources_digest(functions) -> str | None:
    """Hash of the files defining ``functions`` (the package's: their import closure); None without a file."""
    h = hashlib.sha256()
    for f in functions:
        fn = getattr(f, "py_func", f)
        try:
            path = Path(inspect.getsourcefile(fn) or "").resolve()
            inside = PACKAGE_DIR in path.parents
            text = source_hash(path) if inside else hashlib.sha256(path.read_bytes()).hexdigest()
        except (OSError, TypeError, ValueError):
            return None
        h.update(text.encode())
    return h.hexdigest()


def engine_map(code: int) -> EngineMap:
    """The map of kernel code ``code``; ValueError naming the registered codes otherwise."""
    m = MAPS.get(code) if isinstance(code, (int, np.integer)) else None
    if m is None:
        valid = ", ".join(f"{c} ({m.name})" for c, m in MAPS.items())
        raise ValueError(f"kernel code = {code!r} is not an engine's map; the valid codes are {valid}")
    return m


def engine_affine_map(code: int) -> EngineMap:
    """``engine_map(code)`` for a piecewise-affine map; ValueError naming the affine codes otherwise."""
    m = engine_map(code)
    if not m.affine:
        valid = ", ".join(f"{c} ({MAPS[c].name})" for c in AFFINE)
        raise ValueError(f"kernel code = {code!r} ({m.name}) has no piecewise-affine map; valid: {valid}")
    return m


_COPIES: dict = {}
_COPIES_LOCK = threading.RLock()


def specialise(template: Any, tag: str, overrides: dict[str, Any], cache: bool = True) -> Any:
    """``template`` (a numba dispatcher) with the globals ``overrides`` and every template it calls so.

    A function that reads none of ``overrides``' names and calls no function that does is returned
    as it is (one compiled copy serves every engine).  Otherwise the copy is a new ``cache=True``
    dispatcher of the same source, named ``<name>__<tag>``: numba caches it apart, keyed on its
    defining file's sources as every kernel of this package (``engine.jitcache``).  Under
    ``NUMBA_DISABLE_JIT=1`` the plain functions are copied the same way.  ``cache`` False keeps
    every copy off the disk.
    """
    key = (template, tag)
    with _COPIES_LOCK:
        if key not in _COPIES:
            _COPIES[key] = _copy(template, tag, overrides, cache)
        return _COPIES[key]


def _copy(template, tag, overrides, cache):
    jitted = isinstance(template, CPUDispatcher)
    fn = template.py_func if jitted else template
    if not isinstance(fn, types.FunctionType) or fn.__module__.split(".")[:2] != ["contactalpha", "stepping"]:
        return template  # a map's own functions, numpy's, numba's: shared
    scope = dict(fn.__globals__)
    changed = False
    for name in fn.__code__.co_names:
        if name in overrides:
            scope[name] = overrides[name]
            changed = True
        elif name in scope and (isinstance(scope[name], CPUDispatcher) or _is_template(scope[name])):
            callee = specialise(scope[name], tag, overrides, cache)
            if callee is not scope[name]:
                scope[name] = callee
                changed = True
    if not changed:
        return template
    copy = types.FunctionType(fn.__code__, scope, f"{fn.__name__}__{tag}", fn.__defaults__, fn.__closure__)
    copy.__qualname__ = f"{fn.__qualname__}__{tag}"
    copy.__module__ = fn.__module__
    copy.__doc__ = fn.__doc__
    copy.__annotations__ = dict(fn.__annotations__)
    if not jitted:
        return copy
    # ``targetoptions`` leaves out ``cache``: a template cached on disk gives a copy cached on disk.
    return jit(cache=cache and not isinstance(template._cache, NullCache), **template.targetoptions)(copy)


def _is_template(value):
    # Under NUMBA_DISABLE_JIT=1 the templates are plain functions of this folder.
    return isinstance(value, types.FunctionType) and value.__module__.startswith("contactalpha.stepping.")


def for_engine(code: int, template: Any) -> Any:
    """The template compiled for the engine of kernel code ``code`` (ValueError for an unknown code)."""
    m = engine_map(code)
    return specialise(template, m.tag or m.name, m.overrides(), m.cached)


@njit(cache=True)
def engine_step(code: int, z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One step of the engine's map (a template's placeholder): ``(z, w)`` after it; NaN for another code."""
    if code == MAP_CODE:
        return MAP_STEP(z, w, p, h, accel)
    return math.nan, math.nan


@njit(cache=True)
def engine_surface(code: int, p: np.ndarray) -> float:
    """Height in the map's ``z`` of the surface a user reads a drop at; NaN for another code.

    PyBullet's geometric surface lies ``slop`` above its solver's (``pybullet_map``); the other
    engines' surfaces are the same.
    """
    if code == MAP_CODE:
        return MAP_SURFACE(p)
    return math.nan


@njit(cache=True)
def engine_branches(
    code: int, p: np.ndarray, h: float, accel: float, forms: np.ndarray, maps: np.ndarray
) -> int:
    """Fill the map's branch forms and affine steps (``<engine>_map.branches_<engine>``); the forms' count.

    They are written in the height above ``engine_surface`` (``zeta = z - surface``), where a drop
    is read.  For another code (or a map that is not piecewise affine) every affine step is NaN and
    no form is written.
    """
    if code != MAP_CODE:  # every affine step NaN (written here: no other function to compile)
        for b in range(maps.shape[0]):
            for j in range(maps.shape[1]):
                maps[b, j] = math.nan
        return 0
    nf, nb = MAP_BRANCHES(p, h, accel, forms, maps), MAP_N_BRANCHES
    zs = MAP_SURFACE(p)
    if zs != 0.0:
        for i in range(nf):
            forms[i, 2] += forms[i, 0] * zs
        for b in range(nb):
            maps[b, 2] += maps[b, 0] * zs - zs
            maps[b, 5] += maps[b, 3] * zs
    return nf


@njit(cache=True)
def engine_branch(code: int, vals: np.ndarray) -> int:
    """The branch picked by the forms' values ``vals`` at a state (0, whose step is NaN, for another code)."""
    if code == MAP_CODE:
        return MAP_BRANCH(vals)
    return 0


def step_map(code: int, z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One step of the engine with kernel code ``code``: ``(z, w)`` after it."""
    return for_engine(code, engine_step)(code, z, w, p, h, accel)


def surface(code: int, p: np.ndarray) -> float:
    """``engine_surface`` of the engine with kernel code ``code``."""
    return for_engine(code, engine_surface)(code, p)


def branches(code: int, p: np.ndarray, h: float, accel: float, forms: np.ndarray, maps: np.ndarray) -> int:
    """``engine_branches`` of the piecewise-affine map with kernel code ``code``."""
    engine_affine_map(code)
    return for_engine(code, engine_branches)(code, p, h, accel, forms, maps)


def branch_of(code: int, vals: np.ndarray) -> int:
    """``engine_branch`` of the piecewise-affine map with kernel code ``code``."""
    engine_affine_map(code)
    return for_engine(code, engine_branch)(code, vals)
