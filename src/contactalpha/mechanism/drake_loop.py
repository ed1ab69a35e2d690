"""Drake's engine loop: a contact of an SDF or URDF solved on Drake's own drops of the whole model.

The design is ``engine_loop``'s (MuJoCo): the contact's e_N is the pair's signed gap's rate where
it first comes back through zero over its closing rate at touchdown; the drops start ``phase`` of
a step before touchdown at the midpoint phases; the mean's error estimate and the secant are
``engine_loop.PhaseSampler`` and ``engine_loop.solve_damping``.

The plant is Drake's discrete ``MultibodyPlant`` at its step with point contact and a discrete
approximation that honours ``hunt_crossley_dissipation`` (``lagged``, Drake's default, or
``tamsi``).  It is built once; the pair's parameters are each geometry's
``point_contact_stiffness`` and ``hunt_crossley_dissipation`` (Drake combines them to k1 k2 /
(k1 + k2) and (k2 d1 + k1 d2) / (k1 + k2): equal values give k/2 and d), replaced in the scene
graph's context before each phase mean (``SceneGraph.AssignRole`` with ``RoleAssign.kReplace``),
the geometries' other properties (friction) kept.  A URDF's root links are welded to the world
(``base="fixed"``, as MuJoCo and PyBullet load a URDF) unless ``base="floating"``.

Importing this module does not need Drake.
"""

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from .discrete import DRAKE_APPROXIMATIONS
from .drake_model import ParsedPlant, apply_forces, back_in_time, drake_module, set_coordinates
from .engine_loop import DropLoop
from .touch import landing_note

# The longest drop, s: a drop that touched and has not come back by then is captured (e_N = 0).
DURATION = 1.0
# Drake's discrete MultibodyPlant's own default step (MultibodyPlantConfig.time_step), s.
DRAKE_STEP = 1e-3


class DrakeLoop(DropLoop):
    """An SDF/URDF built once as Drake's discrete plant, dropped at many phases with any ``(k, d)``.

    Parameters
    ----------
    model : path of the SDF or URDF.
    pair : (geometry 1, geometry 2) collision names.
    qpos, qvel : touchdown positions and velocities (Drake's coordinates).
    timestep : the plant's step, s (default ``DRAKE_STEP``).
    approximation : ``DRAKE_APPROXIMATIONS`` (default "lagged").
    forces : {body: (fx, fy, fz)} constant forces at bodies' centres of mass, N, world axes.
    base : "fixed" or "floating" (``drake_model.BASES``).
    """

    engine = "Drake"
    damping_name = "hunt_crossley_dissipation (each geometry)"

    def __init__(
        self, model: str | Path, pair: Sequence[str], qpos: ArrayLike, qvel: ArrayLike, *,
        timestep: float | None = None, approximation: str = "lagged", forces: dict | None = None,
        base: str = "fixed",
    ) -> None:  # fmt: skip
        if approximation not in DRAKE_APPROXIMATIONS:
            raise ValueError(
                f"approximation = {approximation!r} is outside the valid choices {DRAKE_APPROXIMATIONS}"
            )
        dk = drake_module()
        self.timestep = DRAKE_STEP if timestep is None else float(timestep)
        self.pair = tuple(pair)
        self.forces = dict(forces or {})
        p = self.p = ParsedPlant(model, point_contact=True, time_step=self.timestep,
                                 approximation=approximation, base=base)  # fmt: skip
        self.groups = tuple(_group(p, name) for name in self.pair)
        self.g = min(self._pairs(), key=lambda ab: p.closest(*ab)[2])  # the lowest point's pair
        self.q0 = np.asarray(qpos, dtype=float)
        self.v0 = np.asarray(qvel, dtype=float)
        set_coordinates(p.plant, p.context, "qpos", self.q0, p.plant.num_positions())
        set_coordinates(p.plant, p.context, "qvel", self.v0, p.plant.num_velocities())
        self.speed = -float(p.gap_row(*self.g)[3] @ self.v0)
        apply_forces(dk, p, self.forces)
        self.clean = p.root.Clone()  # the state before any drop: the plant keeps more than q and v
        self.sim = dk.Simulator(p.diagram, p.root)
        self.sg_context = p.scene_graph.GetMyMutableContextFromRoot(p.root)
        self.drops = 0
        self._params: tuple | None = None

    def _pairs(self):
        return [(a, b) for a in self.groups[0] for b in self.groups[1]]

    def _gap(self):
        """The pair's gap: the least of its geometries' signed distances (one pair: its own)."""
        return min(self.p.closest(a, b)[2] for a, b in self._pairs())

    def heights(self) -> list[float]:
        """The signed distances (m, ascending) of each of the pair's geometry pairs at the start."""
        p = self.p
        p.root.SetTimeStateAndParametersFrom(self.clean)
        return sorted(p.closest(a, b)[2] for a, b in self._pairs())

    def landing(self, stiffness: float, effective_mass: float) -> str:
        """``touch.landing_note`` on the pair's points; ValueError where they rock or Drake gives one.

        Drake's point contact gives a pair of geometries one point (the deepest): a box on a box
        (or a half space) lands on one corner, and a flat box rocks.  A box's corners are its own
        geometries (small spheres at the corners, the pair naming the box's body): then each
        corner is one point.  The maximum compression is ``speed`` sqrt(m_eff / ``stiffness``).
        """
        inspector = self.p.scene_graph.model_inspector()
        for a, b in self._pairs():
            shapes = [type(inspector.GetShape(g)).__name__ for g in (a, b)]
            if "Box" in shapes and "Sphere" not in shapes:
                raise ValueError(
                    f"Drake's point contact gives the pair {self.pair[0]!r} / {self.pair[1]!r} "
                    f"({' / '.join(shapes)}) one contact point, its deepest: a box lands on one corner and a "
                    "flat box rocks; give the box small spheres at its corners (the pair naming its body), "
                    "or use hydroelastic contact"
                )
        delta = float(self.speed) * math.sqrt(float(effective_mass) / float(stiffness))
        return landing_note(self.heights(), delta)

    def _set_pair(self, params):
        if self._params == tuple(params):
            return
        dk = drake_module()
        k, d = (float(x) for x in params)
        inspector = self.p.scene_graph.model_inspector()
        source = self.p.plant.get_source_id()
        for gid in (g for group in self.groups for g in group):
            props = dk.ProximityProperties(inspector.GetProximityProperties(gid))
            for name, value in (("point_contact_stiffness", k), ("hunt_crossley_dissipation", d)):
                if props.HasProperty("material", name):
                    props.UpdateProperty("material", name, value)
                else:
                    props.AddProperty("material", name, value)
            self.p.scene_graph.AssignRole(self.sg_context, source, gid, props, dk.RoleAssign.kReplace)
        self._params = tuple(params)

    def drop(self, params, phase: float, mass: bool = False) -> tuple[float, float]:
        """``(e_N, relative change of m_eff over the contact)`` of one drop (the change NaN without ``mass``).

        NaN e_N: never touched; 0: touched and not back within ``DURATION``.
        """
        p, h = self.p, self.timestep
        # A discrete plant's state holds more than q and v (the previous step's contact results):
        # every drop starts from the state before any drop, and the pair's values are set again.
        p.root.SetTimeStateAndParametersFrom(self.clean)
        self._params = None
        self._set_pair(params)
        p.plant.SetPositions(p.context, self.q0)
        p.plant.SetVelocities(p.context, self.v0)
        back_in_time(p, float(phase) * h, h, self.forces, with_contacts=True)
        self.sim.Initialize()
        gaps, inv = [self._gap()], []
        for i in range(1, int(math.ceil(DURATION / h)) + 1):
            self.sim.AdvanceTo(i * h)
            if mass:
                _, _, first, J = p.gap_row(*self.g)
                if first < 0.0:
                    inv.append(float(J @ np.linalg.solve(p.plant.CalcMassMatrix(p.context), J)))
            gap = self._gap()
            gaps.append(gap)
            if gap > 0.0 and gaps[-2] >= 0.0 and min(gaps) < 0.0:
                break
        return self.read_drop(gaps, inv, h)


def _group(p, name):
    """The proximity geometries of a pair's side: the geometry ``name``, else all of the body ``name``."""
    try:
        return (p.geometry(name),)
    except ValueError:
        if not p.plant.HasBodyNamed(str(name)):
            raise
    body = p.plant.GetBodyByName(str(name))
    inspector = p.scene_graph.model_inspector()
    ids = [g for g in p.plant.GetCollisionGeometriesForBody(body) if inspector.GetProximityProperties(g)]
    if not ids:
        raise ValueError(f"body {name!r} has no collision geometry")
    return tuple(ids)
