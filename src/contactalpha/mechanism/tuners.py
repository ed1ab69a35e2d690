"""The engines' tuners: each one's reduced solve (``reduced``) and writer (``writers``), one record each.

The engines' records (``adapters.registry``) name these (``ModelFile.tuner``); ``TUNERS`` lists
them in the registry's order.
"""

from contactalpha.adapters.record import Tuner
from contactalpha.adapters.registry import tuners

from .reduced import drake_solve, mujoco_solve, pybullet_solve
from .writers import write_drake, write_mujoco, write_pybullet

MUJOCO_TUNER = Tuner("mujoco", "mujoco", ".xml", mujoco_solve, write_mujoco, True)
DRAKE_TUNER = Tuner("drake", "drake", ".sdf", drake_solve, write_drake, True)
PYBULLET_TUNER = Tuner("pybullet", None, ".py", pybullet_solve, write_pybullet, True)
TUNERS = tuple(tuners().values())
TUNER_NAMES = tuple(t.name for t in TUNERS)


def tuner(engine: str):
    """The ``Tuner`` of ``engine``; ValueError naming the valid choices otherwise."""
    for t in TUNERS:
        if t.name == engine:
            return t
    raise ValueError(f"engine = {engine!r} is outside the valid choices {TUNER_NAMES}")
