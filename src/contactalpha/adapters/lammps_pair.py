"""Two free spheres colliding in LAMMPS's ``pair_style granular``: the check of a species pair's line.

The two spheres (types 1 and 2, or both type 1 for a pair of one species) approach along x with
relative speed ``approach_speed`` and no net momentum; a constant force ``m* accel`` pushes each
towards the other (``fix addforce``), so their gap moves under the relative acceleration
``accel`` (``F/m_1 + F/m_2 = F/m*``) exactly as one sphere of the reduced mass ``m*`` on a wall
(``adapters.lammps_granular``).  Gravity is off: it moves both alike and never loads a free pair.
Velocity Verlet keeps the gap on its flight parabola at the sample times, so the gap and its rate
are measured as the wall drop's height and velocity (``adapters.stepped.measure_steps``).
"""

import math
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.lammps_granular import lammps_number, new_instance
from contactalpha.adapters.stepped import measure_steps


@dataclass(frozen=True)
class Sphere:
    """One sphere of a pair drop: ``radius`` (m), ``density`` (kg/m^3) and its LAMMPS ``atom_type``."""

    radius: float
    density: float
    atom_type: int = 1

    @property
    def mass(self) -> float:
        """The mass, kg."""
        return 4.0 / 3.0 * math.pi * self.radius**3 * self.density


def pair_drop_e_n(pair_lines, first, second, approach_speed, accel, timestep, steps, phase=0.0):
    """Newton's e_N of one collision of ``first`` and ``second`` under ``pair_lines`` (LAMMPS input).

    ``pair_lines`` are the ``pair_coeff`` lines of ``pair_style granular`` for the types present;
    ``accel`` (m/s^2, >= 0) the gap's constant acceleration towards contact; touchdown falls a
    fraction ``phase`` of a step after the second step.
    """
    m1, m2 = first.mass, second.mass
    mu = m1 * m2 / (m1 + m2)
    tau = (1.0 + phase) * timestep  # start to touchdown, on the gap's exact parabola
    u0 = approach_speed - accel * tau
    gap0 = u0 * tau + 0.5 * accel * tau * tau
    x1, x2 = -first.radius - 0.5 * gap0, second.radius + 0.5 * gap0
    size = 40.0 * (first.radius + second.radius) + 4.0 * gap0
    skin = 0.5 * (first.radius + second.radius)
    named = [
        int(w) for line in pair_lines.splitlines() for w in line.split()[1:3] if line.startswith("pair_coeff")
    ]
    types = max([first.atom_type, second.atom_type, *named])
    push = mu * accel
    bounds = f"{lammps_number(-size)} {lammps_number(size)}"
    lmp = new_instance()
    try:
        lmp.commands_string(f"""
units si
atom_style sphere
dimension 3
boundary f f f
atom_modify map array
comm_modify vel yes
region box block {bounds} {bounds} {bounds}
create_box {types} box
create_atoms {first.atom_type} single {lammps_number(x1)} 0 0
create_atoms {second.atom_type} single {lammps_number(x2)} 0 0
set atom 1 diameter {lammps_number(2 * first.radius)} density {lammps_number(first.density)}
set atom 2 diameter {lammps_number(2 * second.radius)} density {lammps_number(second.density)}
group one id 1
group two id 2
velocity one set {lammps_number(u0 * m2 / (m1 + m2))} 0 0
velocity two set {lammps_number(-u0 * m1 / (m1 + m2))} 0 0
pair_style granular
{pair_lines}
neighbor {lammps_number(skin)} bin
neigh_modify every 1 delay 0 check yes
fix p1 one addforce {lammps_number(push)} 0 0
fix p2 two addforce {lammps_number(-push)} 0 0
fix n all nve/sphere
timestep {lammps_number(timestep)}
variable gap equal x[2]-x[1]-{lammps_number(first.radius + second.radius)}
variable rate equal vx[2]-vx[1]
fix rec all vector 1 v_gap v_rate
run {int(steps)}
""")
        rows = np.array([[lmp.extract_fix("rec", 0, 2, j, c) for c in (0, 1)] for j in range(int(steps))])
    finally:
        lmp.close()
    z = np.concatenate(([gap0], rows[:, 0]))
    v = np.concatenate(([-u0], rows[:, 1])) + 0.5 * accel * timestep  # Verlet's v (lammps_granular)
    return measure_steps(z, v, accel, timestep, approach_speed).e_n
