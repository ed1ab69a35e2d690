"""What a model file is and which engine tunes it: decided once, where ``tune`` starts.

``ModelKind`` holds the file's format (``robot_files.file_format``: MJCF, URDF or SDF) and the
engine's tuner record (``tuners``): the engine given, or the first installed engine that reads
the file (``robot_files.engine_for``), with why.  The contact read from the file carries the
format on (``MechanismContact.file_format``).
"""

from dataclasses import dataclass
from pathlib import Path

from contactalpha.adapters.record import Tuner

from .inputs import check_model_size
from .robot_files import engine_by_suffix, engine_for, file_format
from .tuners import tuner


@dataclass(frozen=True)
class ModelKind:
    """``format`` ("mjcf", "urdf", "sdf"; "" for another suffix), ``tuner`` (the engine's), ``chosen``.

    ``chosen`` says why the engine was chosen where none was given ("" where one was, or where
    the file is not there: it is refused where it is read).
    """

    format: str
    tuner: Tuner
    chosen: str = ""

    @property
    def engine(self) -> str:
        """The engine's name (its record's)."""
        return self.tuner.name


def model_kind(model, engine: str | None = None) -> ModelKind:
    """The ``ModelKind`` of ``model`` tuned for ``engine`` (None: the first installed that reads it)."""
    why = ""
    if engine is None:
        if Path(model).is_file():
            check_model_size(model)  # named before the engine that would read it is looked for
            engine, why = engine_for(model)
        else:
            engine = engine_by_suffix(model)
    return ModelKind(file_format(model), tuner(engine), why)
