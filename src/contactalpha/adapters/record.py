"""The engine record: everything the package knows of one engine, in one value.

An ``Engine`` holds, for one engine, each layer's part (docs/design.md draws them):

- ``adapter``: the engine adapter (``adapters.contract.EngineAdapter``): its ``name`` (the
  registry key), its ``law``, its parameter block (``parameters``, with its ``units``) and its
  in-engine drop (``build_drop``, ``run``, ``measure``, ``delivered``, ``calibrate``);
- ``loader``: the one import guard and install hint (``adapters.loader.Loader``);
- ``step_map``: its ``stepping.registry.Stepper`` (the engine's discrete step, whose kernel code
  runs its own map: ``stepping.kernels.register_map`` for a map outside ``stepping``), or None;
- ``model_file``: its ``ModelFile`` (a model-file reader and a tuner in ``mechanism``), or None;
- ``batched``: its batched JAX blocks, ``{batched engine: Ref to block(zeta, EngineScene)}``
  (``xla.engines``), or None.

Every part must be given (``Engine(...)`` without one is a TypeError naming it); None says the
engine has none of it.  ``check_engine`` refuses a record whose parts disagree or do not keep
their contracts, naming the part.  Parts living in layers above ``adapters`` (``mechanism``,
``xla``) are ``Ref``s: a dotted path resolved when the part is used, so the record imports none
of them (tests/test_architecture.py).
"""

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from contactalpha.stepping.registry import Stepper, map_problem

from .contract import missing_parts
from .loader import Loader


@dataclass(frozen=True)
class Ref:
    """A lazy reference ``"package.module:name"`` to a value in a layer above ``adapters``."""

    path: str

    def __post_init__(self):
        module, _, name = self.path.partition(":")
        if not module or not name or not name.isidentifier():
            raise ValueError(f"Ref path = {self.path!r} is not of the form 'package.module:name'")

    def get(self) -> Any:
        """The value the path names (its module imported)."""
        module, _, name = self.path.partition(":")
        try:
            return getattr(importlib.import_module(module), name)
        except AttributeError as err:
            raise ImportError(f"Ref {self.path!r}: {module} has no {name!r}") from err

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        """Call the value the path names (a function)."""
        return self.get()(*args, **kwargs)


def resolved(part: Any) -> Any:
    """``part`` itself, or the value of a ``Ref``."""
    return part.get() if isinstance(part, Ref) else part


@dataclass(frozen=True)
class ModelFile:
    """What the engine does with a user's model file (``mechanism``; ``contactalpha tune``).

    Attributes
    ----------
    suffixes : the file suffixes its reader reads (lowercase, with the dot); empty without a reader.
    reader : ``read(path, pair, *, qpos, qvel, speed, forces, **extra) -> MechanismContact``, or
        None where the engine reads no model file itself (its tuner takes another engine's reading).
    tuner : a ``Tuner`` (``tune``'s solve and write calls), or None where ``tune`` writes nothing
        for the engine.
    loads : the file suffixes the engine loads itself to drop a tuned model, where it has no
        reader (PyBullet: a URDF); default none beyond ``suffixes``.
    refused_meshes : the mesh suffixes its reader refuses (Drake: ``.stl``, ``.dae``).
    """

    suffixes: tuple[str, ...]
    reader: Ref | Callable[..., Any] | None
    tuner: "Ref | Tuner | None"
    loads: tuple[str, ...] = ()
    refused_meshes: tuple[str, ...] = ()

    @property
    def opens(self) -> tuple[str, ...]:
        """Every file suffix the engine opens: its reader's, then those it loads itself."""
        return self.suffixes + tuple(s for s in self.loads if s not in self.suffixes)


@dataclass(frozen=True)
class Tuner:
    """How ``mechanism.tune`` writes an engine's parameters into a model file.

    ``name``: the engine's (its record's name); ``reader``: the engine whose reader reads the
    file (None: the first that reads it); ``suffix``: the written file's suffix; ``solve(contact,
    target, stiffness, impedance, timestep, discrete) -> (parameters, notes, details, step)``;
    ``write(contact, output, parameters, notes) -> path``; ``drop``: ``tune(check=True)`` can
    drop the written file.
    """

    name: str
    reader: str | None
    suffix: str
    solve: Callable[..., Any]
    write: Callable[..., Any]
    drop: bool


# The record's parts, in the order the docs list them.
PARTS = ("adapter", "loader", "step_map", "model_file", "batched")


@dataclass(frozen=True, kw_only=True)
class Engine:
    """One engine: each layer's part of it (the module docstring); None where it has none."""

    adapter: Any  # an EngineAdapter (its attributes are the engine's own types; check_engine checks it)
    loader: Loader
    step_map: Stepper | None
    model_file: ModelFile | None
    batched: Mapping[str, Ref | Callable[..., Any]] | None

    @property
    def name(self) -> str:
        """The registry key (the adapter's ``name``)."""
        return self.adapter.name

    @property
    def law(self) -> Any:
        """The contact law the engine applies (a ``contactalpha.laws.ContactLaw``)."""
        return self.adapter.law

    @property
    def units(self) -> dict[str, str]:
        """``{parameter: unit}`` of the parameter block."""
        return dict(self.adapter.units)


def record_problems(record: Engine) -> list[str]:
    """What is wrong with ``record``, one line per problem, each starting with the part's name."""
    a = record.adapter
    missing = missing_parts(a)
    if missing:
        why = ", ".join(missing)
        return [f"adapter: misses part(s) of the contract or has them with another signature: {why}"]
    problems = []
    if not isinstance(record.loader, Loader):
        problems.append(f"loader: {record.loader!r} is not an adapters.loader.Loader")
    elif a.module != record.loader.module:
        problems.append(f"loader: imports {record.loader.module!r} but the adapter's module is {a.module!r}")
    units = getattr(a, "units", None)
    if not isinstance(units, Mapping) or not units:
        problems.append("adapter.units: the parameter block needs {parameter: unit}")
    s = record.step_map
    if s is not None and (not isinstance(s, Stepper) or s.name != a.name):
        problems.append(f"step_map: {s!r} is not a stepping.registry.Stepper named {a.name!r}")
    elif s is not None and map_problem(s):
        problems.append(f"step_map: {map_problem(s)}")
    mf = record.model_file
    if mf is not None and not isinstance(mf, ModelFile):
        problems.append(f"model_file: {mf!r} is not an adapters.record.ModelFile")
    elif mf is not None and (mf.reader is None) != (not mf.suffixes):
        problems.append("model_file: a reader needs the suffixes it reads, and suffixes need a reader")
    b = record.batched
    if b is not None and (not isinstance(b, Mapping) or not b or not all(callable(v) for v in b.values())):
        problems.append("batched: {batched engine: block} with a Ref or a function for each")
    return problems


def check_engine(record: Engine) -> Engine:
    """``record`` if it keeps the record's contract; TypeError naming each wrong part otherwise."""
    if not isinstance(record, Engine):
        raise TypeError(f"{record!r} is not an engine record (adapters.record.Engine)")
    problems = record_problems(record)
    if problems:
        raise TypeError(f"engine record {record.adapter!r}: " + "; ".join(problems))
    return record
