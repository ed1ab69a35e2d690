"""The one list of engine adapters.

The front door, the command line, the engines study and the tests iterate it.  Adding an engine
is one module with an object keeping ``contactalpha.adapters.contract.EngineAdapter`` and one
line here (docs/adding-an-engine.md).
"""

import importlib.util
import reprlib
from dataclasses import dataclass

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
from contactalpha.laws import get_law

# Every engine adapter, in the order tables and the command line list them.
ADAPTERS = tuple(
    check_adapter(a)
    for a in (
        opensim_hc.ADAPTER,
        exudyn_contact.ADAPTER,
        mujoco_soft.ADAPTER,
        drake_point.ADAPTER,
        pybullet_kv.ADAPTER,
        lammps_granular.ADAPTER,
        pybullet_impulse.ADAPTER,
        physx_sapien.ADAPTER,
    )
)
ENGINE_NAMES = tuple(a.name for a in ADAPTERS)


def adapter(name):
    """The registered adapter called ``name``; ValueError naming the valid choices otherwise."""
    for a in ADAPTERS:
        if a.name == name:
            return a
    raise ValueError(f"engine = {name!r} is outside the valid choices {ENGINE_NAMES}")


def installed(a):
    """True when the Python module of adapter ``a``'s engine can be imported here."""
    return importlib.util.find_spec(a.module) is not None


def engine_parameters(law, damping, scene):
    """Every registered engine's parameters for ``law`` with the law's ``damping`` in ``scene``.

    ``scene`` needs ``mass``, ``stiffness``, ``approach_speed`` and ``radius`` (None allowed: the
    parameters that need a geometry are left out).  Engines whose law is another are not listed.
    """
    return {a.name: a.parameters(damping, scene) for a in _of_law(law)}


def _of_law(law):
    name = get_law(law).name
    # An impulse engine (``impulse`` set) has no continuous block: it is answered at its step only.
    return [a for a in ADAPTERS if a.law.name == name and getattr(a, "impulse", None) is None]


def check_radius_used(law, radius):
    """Refuse a ``radius`` that no engine of ``law`` reads (its parameters would ignore it silently)."""
    if radius is None:
        return
    probe = _ProbeScene(1.0, 1.0, 1.0, None)
    with_radius = _ProbeScene(1.0, 1.0, 1.0, 1.0)
    if all(a.parameters(0.0, probe) == a.parameters(0.0, with_radius) for a in _of_law(law)):
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
