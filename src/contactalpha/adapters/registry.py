"""The one list of engine adapters.

The front door, the command line, the engines study and the tests iterate it.  Adding an engine
is one module with an object keeping ``contactalpha.adapters.contract.EngineAdapter`` and one
line here (docs/adding-an-engine.md).
"""

import importlib.util

from contactalpha.adapters import drake_point, exudyn_contact, mujoco_soft, opensim_hc, pybullet_kv
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
    name = get_law(law).name
    return {a.name: a.parameters(damping, scene) for a in ADAPTERS if a.law.name == name}
