"""The four test cases: model files, pair, approach and the contact stiffness of the drops.

``omega`` (1/s) sets the stiffness k = m_eff omega^2: short enough a contact that the effective
mass moves by under 0.3 % (the tune's first-order premise), and MuJoCo's step is ``1/2000`` of
the undamped contact time.
"""

import math
from dataclasses import dataclass

from hand import MODELS


@dataclass(frozen=True)
class Case:
    name: str
    pair: tuple
    qvel_mujoco: tuple
    qvel_drake: tuple
    forces: dict
    omega: float

    def path(self, suffix):
        return str(MODELS / f"{self.name}{suffix}")

    @property
    def timestep(self):
        return math.pi / self.omega / 2000


SPEED = 0.8
CASES = (
    # A motor pushes the arm to the wall with 20 N: a load factor near 0.2.
    Case("pendulum", ("wall", "tip"), (SPEED / 0.5,), (SPEED / 0.5,), {"arm": (-20.0, 0.0, 0.0)}, 316.0),
    Case("capsule", ("floor", "capsule"), (0, 0, -SPEED, 0, 0, 0), (0, 0, 0, 0, 0, -SPEED), {}, 1e4),
    Case("leg", ("floor", "foot"), (-SPEED, 0, 0), (-SPEED, 0, 0), {}, 3e4),
    Case("box", ("floor", "box"), (0, 0, -SPEED, 0, 0, 0), (0, 0, 0, 0, 0, -SPEED), {}, 3e4),
)
TARGETS = (0.3, 0.6, 0.9)
