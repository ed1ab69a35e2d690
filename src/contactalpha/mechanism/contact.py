"""A contact between two geometries of a mechanism, as the contact sees it along its normal.

``MechanismContact`` holds what a model file and a configuration give at first touch: the contact
point and normal, the effective mass ``m_eff = 1 / (J M^-1 J^T)`` along the normal, the free normal
acceleration of the contact point and the approach speed.  The readers (``mujoco_model``,
``drake_model``) fill it; ``tune`` turns it into engine parameters.

**What the free acceleration includes.**  With ``J`` the row mapping the joint velocities to the
rate of the gap between the two geometries (the velocity of the contact point on geometry 2
relative to geometry 1, along the normal from 1 to 2), the gap accelerates, with no contact force,
by ``J M^-1 (tau_gravity + tau_forces - C(q, v) v)``: gravity, the constant forces named by the
user (each at a body's centre of mass, in world axes) and the Coriolis and centrifugal terms at
the given joint velocity.  ``J' v`` (the Jacobian's own rate) is left out, as MuJoCo's contact row
leaves it out; it vanishes at zero joint velocity.  ``accel`` is minus that gap acceleration: the
load pressing the geometries together (m/s^2, >= 0 for a load that presses).
"""

import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

# A gap (m) above which a configuration is not at first touch: the values are then at that
# configuration, and ``tune`` says so.
TOUCH_TOLERANCE = 1e-6


@dataclass(frozen=True)
class MechanismContact:
    """One contact of a mechanism at a configuration (SI units, world axes).

    Attributes
    ----------
    engine : the engine whose parser and dynamics read the model ("mujoco", "drake").
    model : the model file's path.
    pair : (geometry 1, geometry 2) names.
    point : (3,) contact point, m (midway between the two surfaces).
    normal : (3,) unit normal from geometry 1 to geometry 2.
    gap : signed distance between the geometries at the configuration, m (0 at first touch).
    jacobian : (nv,) row ``J``: gap rate = ``J @ qvel``, m/s per unit joint velocity.
    effective_mass : ``1 / (J M^-1 J^T)``, kg.
    accel : free normal acceleration pressing the geometries together, m/s^2 (see module doc).
    gravity_accel, forces_accel, velocity_accel : its parts from gravity, the named forces and
        the joint velocity (Coriolis and centrifugal), m/s^2.
    approach_speed : closing speed of the contact point at touchdown, m/s (> 0 closes).
    qpos, qvel : the configuration and joint velocity (the engine's coordinates).
    forces : {body: (fx, fy, fz)} the named constant forces (N, world axes, at the bodies'
        centres of mass).
    engine_row : what the engine builds for this contact beyond the physics (MuJoCo: ``diagA``,
        the contact row's approximation of ``J M^-1 J^T``, and ``R``, ``solref``, ``solimp`` of
        the model as it is, its ``timestep`` and ``integrator``).
    file_format : the model file's format, "mjcf", "urdf" or "sdf" (``robot_files.file_format``),
        set where the file is read (``reading``); the writers and the engine loops go by it.
    """

    engine: str
    model: str
    pair: tuple
    point: np.ndarray
    normal: np.ndarray
    gap: float
    jacobian: np.ndarray
    effective_mass: float
    accel: float
    gravity_accel: float
    forces_accel: float
    velocity_accel: float
    approach_speed: float
    qpos: np.ndarray
    qvel: np.ndarray
    forces: dict = field(default_factory=dict)
    engine_row: dict = field(default_factory=dict)
    file_format: str = ""

    @property
    def at_touch(self) -> bool:
        """True when the configuration is at first touch (``|gap| <= TOUCH_TOLERANCE``)."""
        return abs(self.gap) <= TOUCH_TOLERANCE

    def summary(self) -> list[str]:
        """Text lines of the contact's values."""
        lines = [
            f"model            {self.model} ({self.engine})",
            f"pair             {self.pair[0]} / {self.pair[1]}",
            f"point            {_vec(self.point)} m",
            f"normal           {_vec(self.normal)} (from {self.pair[0]} to {self.pair[1]})",
            f"gap              {self.gap:.6g} m",
            f"effective mass   {self.effective_mass:.12g} kg",
            f"free accel       {self.accel:.12g} m/s^2 (gravity {self.gravity_accel:.6g}, forces "
            f"{self.forces_accel:.6g}, velocity {self.velocity_accel:.6g})",
            f"approach speed   {self.approach_speed:.12g} m/s",
        ]
        lines += [f"{name:16s} {_show(value)}" for name, value in self.engine_row.items()]
        return lines


def _vec(x):
    return "(" + ", ".join(f"{v:.9g}" for v in x) + ")"


def _show(value):
    if isinstance(value, (tuple, list)) and all(isinstance(v, str) for v in value):
        return "; ".join(value) or "none"
    if isinstance(value, (tuple, list, np.ndarray)):
        return _vec(value)
    return f"{value:.12g}" if isinstance(value, float) else str(value)


def approach(
    jacobian: ArrayLike, mass_matrix: np.ndarray, qvel: ArrayLike | None, speed: float | None
) -> tuple[float, float, np.ndarray]:
    """``(m_eff, approach speed, qvel)`` of the gap row ``J`` with mass matrix ``M``.

    Parameters
    ----------
    jacobian : (nv,) gap row J.
    mass_matrix : (nv, nv) M.
    qvel : (nv,) joint velocity, or None.
    speed : closing speed of the contact point, m/s, or None (exactly one of the two is given).

    Returns
    -------
    (float, float, ndarray)
        ``m_eff = 1 / (J M^-1 J^T)``; the closing speed ``-J qvel``; the joint velocity (for
        ``speed``: the one of least kinetic energy, ``-speed m_eff M^-1 J^T``, what an impulse
        along the normal gives).
    """
    J = np.asarray(jacobian, dtype=float)
    minv_jt = np.linalg.solve(mass_matrix, J)
    inv_m = float(J @ minv_jt)
    if not inv_m > 0.0:
        raise ValueError("the pair's contact row moves no joint: J M^-1 J^T = 0 (both geometries fixed?)")
    m_eff = 1.0 / inv_m
    if (qvel is None) == (speed is None):
        raise ValueError("give the approach as exactly one of speed (m/s) and qvel (joint velocities)")
    if qvel is None:
        assert speed is not None  # exactly one of the two is given (checked above)
        speed = float(speed)
        if not (math.isfinite(speed) and speed > 0.0):
            raise ValueError(f"speed = {speed!r} is outside the valid range (0, inf) m/s")
        return m_eff, speed, -speed * m_eff * minv_jt
    qvel = np.asarray(qvel, dtype=float)
    if qvel.shape != J.shape:
        raise ValueError(f"qvel has {qvel.size} values; the model has {J.size} joint velocities")
    speed = -float(J @ qvel)
    if not speed > 0.0:
        raise ValueError(f"qvel gives the contact point a closing speed of {speed!r} m/s; it must be > 0")
    return m_eff, speed, qvel


def pressing_accel(jacobian: ArrayLike, mass_matrix: np.ndarray, tau: ArrayLike) -> float:
    """Free acceleration pressing the gap closed, ``-J M^-1 tau``, m/s^2, of a generalized force."""
    return -float(
        np.asarray(jacobian, dtype=float) @ np.linalg.solve(mass_matrix, np.asarray(tau, dtype=float))
    )


@dataclass(frozen=True)
class MechanismDrop:
    """A drop of a mechanism in an engine (MuJoCo, Drake, PyBullet) from the touchdown state.

    ``e_n`` Newton's restitution of the gap (NaN: no rebound within ``duration``); ``exit_speed``
    m/s; ``contact_time`` s from touchdown to the rebound; ``inv_mass_range`` (min, max) of
    ``J M^-1 J^T`` over the steps in contact and ``inv_mass_touch`` at touchdown, 1/kg;
    ``steps`` in contact; ``timestep`` s.
    """

    e_n: float
    exit_speed: float
    contact_time: float
    inv_mass_touch: float
    inv_mass_range: tuple
    steps: int
    timestep: float

    @classmethod
    def of(
        cls, e_n: float, exit_speed: float, contact_time: float, inv_masses: Iterable[float], timestep: float
    ) -> "MechanismDrop":
        """The drop from its e_N, exit speed, contact time and ``J M^-1 J^T`` at each step in contact."""
        inv = [float(x) for x in inv_masses]
        rng = (min(inv), max(inv)) if inv else (math.nan, math.nan)
        touch = inv[0] if inv else math.nan
        return cls(float(e_n), float(exit_speed), float(contact_time), touch, rng, len(inv), float(timestep))

    @property
    def mass_change(self) -> float:
        """Largest relative change of the effective mass over the contact (vs touchdown)."""
        lo, hi = self.inv_mass_range
        return max(abs(self.inv_mass_touch / lo - 1.0), abs(self.inv_mass_touch / hi - 1.0))
