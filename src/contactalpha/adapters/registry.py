"""The one list of engines: a record per engine (``adapters.record.Engine``), one line each.

The front door, the command line, the engines study, ``tune``'s readers and tuners, the JAX
blocks and the tests iterate it; every table keyed by an engine's name is derived from it here
(``ADAPTERS``, ``model_readers``, ``tuners``, ``batched_blocks``), and the step map of each record
joins ``stepping.registry.STEPPERS``.  Adding an engine is one
module holding its ``ENGINE`` record and one line here (docs/adding-an-engine.md).
"""

import reprlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from contactalpha.adapters import (
    drake_point,
    exudyn_contact,
    lammps_granular,
    mujoco_soft,
    opensim_hc,
    physx_sapien,
    pybullet_impulse,
    pybullet_kv,
)
from contactalpha.adapters.contract import check_adapter
from contactalpha.adapters.record import Engine, ModelFile, Tuner, check_engine, resolved
from contactalpha.laws import get_law
from contactalpha.stepping import registry as stepping_registry

# Every engine, in the order tables and the command line list them.
ENGINES = tuple(
    check_engine(e)
    for e in (
        opensim_hc.ENGINE,
        exudyn_contact.ENGINE,
        mujoco_soft.ENGINE,
        drake_point.ENGINE,
        pybullet_kv.ENGINE,
        lammps_granular.ENGINE,
        lammps_granular.UNFLOORED_ENGINE,
        lammps_granular.VISCOELASTIC_ENGINE,
        lammps_granular.VISCOELASTIC_UNFLOORED_ENGINE,
        pybullet_impulse.ENGINE,
        physx_sapien.ENGINE,
    )
)
# The step map of a record outside ``stepping`` (its kernel code from ``kernels.register_map``).
for _e in ENGINES:
    if _e.step_map is not None:
        stepping_registry.register(_e.step_map)
ADAPTERS = tuple(check_adapter(e.adapter) for e in ENGINES)
ENGINE_NAMES = tuple(e.name for e in ENGINES)
if len(set(ENGINE_NAMES)) != len(ENGINE_NAMES):
    raise ImportError(f"two engine records share a name: {ENGINE_NAMES}")
_UNCLAIMED = sorted(
    {s.name for s in stepping_registry.STEPPERS}
    - {e.step_map.name for e in ENGINES if e.step_map is not None}
)
if _UNCLAIMED:
    raise ImportError(f"step maps {_UNCLAIMED} of stepping.registry belong to no engine record")


def engine(name: str) -> Engine:
    """The record of the engine called ``name``; ValueError naming the valid choices otherwise."""
    for e in ENGINES:
        if e.name == name:
            return e
    raise ValueError(f"engine = {name!r} is outside the valid choices {ENGINE_NAMES}")


def adapter(name):
    """The registered adapter called ``name``; ValueError naming the valid choices otherwise."""
    return engine(name).adapter


def installed(a):
    """True when the Python module of adapter ``a``'s engine can be imported here."""
    return engine(a.name).loader.installed()


def model_files() -> dict[str, ModelFile]:
    """``{engine: ModelFile}`` of the engines that do something with a model file, in registry order."""
    return {e.name: e.model_file for e in ENGINES if e.model_file is not None}


def model_readers() -> dict[str, tuple[str, tuple[str, ...], Callable[..., Any]]]:
    """``{engine: (module, suffixes, read)}`` of the engines that read model files, in registry order."""
    return {
        e.name: (e.loader.module, e.model_file.suffixes, resolved(e.model_file.reader))
        for e in ENGINES
        if e.model_file is not None and e.model_file.reader is not None
    }


def tuners() -> dict[str, Tuner]:
    """``{engine: Tuner}`` of the engines ``tune`` writes model files for, in registry order."""
    out = {}
    for e in ENGINES:
        if e.model_file is not None and e.model_file.tuner is not None:
            t = resolved(e.model_file.tuner)
            if not isinstance(t, Tuner) or t.name != e.name:
                raise TypeError(f"engine record {e.name!r}: model_file.tuner {t!r} is not its Tuner")
            out[e.name] = t
    return out


def batched_blocks() -> dict[str, tuple[str, Callable[..., Any]]]:
    """``{batched engine: (law name, block)}`` of every record's JAX blocks (``xla.engines``)."""
    out: dict[str, tuple[str, Callable[..., Any]]] = {}
    for e in ENGINES:
        for name, block in (e.batched or {}).items():
            if name in out:
                raise ValueError(f"batched engine {name!r} has a block in two engine records")
            out[name] = (e.law.name, resolved(block))
    return out


def engine_parameters(law, damping, scene):
    """Every registered engine's parameters for ``law`` with the law's ``damping`` in ``scene``.

    ``scene`` needs ``mass``, ``stiffness``, ``approach_speed`` and ``radius`` (None allowed: the
    parameters that need a geometry are left out).  Engines whose law is another are not listed.
    """
    return {a.name: a.parameters(damping, scene) for a in continuous_adapters(law)}


def continuous_adapters(law):
    """The adapters of engines applying ``law`` with a continuous block (not impulse engines)."""
    name = get_law(law).name
    # An impulse engine (``impulse`` set) has no continuous block: it is answered at its step only.
    return [a for a in ADAPTERS if a.law.name == name and getattr(a, "impulse", None) is None]


def check_radius_used(law, radius):
    """Refuse a ``radius`` that no engine of ``law`` reads (its parameters would ignore it silently)."""
    if radius is None:
        return
    probe = _ProbeScene(1.0, 1.0, 1.0, None)
    with_radius = _ProbeScene(1.0, 1.0, 1.0, 1.0)
    if all(a.parameters(0.0, probe) == a.parameters(0.0, with_radius) for a in continuous_adapters(law)):
        raise ValueError(
            f"radius = {reprlib.repr(radius)} is not used by law {get_law(law).name!r}: none of its engines' "
            "parameters needs a geometry; leave radius out"
        )


@dataclass(frozen=True)
class _ProbeScene:
    mass: float
    stiffness: float
    approach_speed: float
    radius: object
