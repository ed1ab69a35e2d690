"""A contact of an SDF or URDF model read with Drake's parser, and its drop on Drake's plant.

``read_drake`` parses the model into a ``MultibodyPlant`` (continuous), sets the configuration
(Drake's positions: a free body's are its quaternion and position) and reads:

- the contact point (midway between the closest points) and normal (from geometry 1 to 2) of
  ``QueryObject.ComputeSignedDistancePairClosestPoints``, and the gap;
- the gap row ``J = n . (J_p(body 2) - J_p(body 1))`` from ``CalcJacobianTranslationalVelocity``
  with respect to the velocities, and ``CalcMassMatrix``: ``m_eff = 1 / (J M^-1 J^T)``;
- ``CalcGravityGeneralizedForces``, the named forces ``J_com^T F`` and ``-CalcBiasTerm`` (the
  Coriolis and centrifugal forces at the joint velocity).

Signed distance in Drake covers pairs of spheres, boxes, capsules, cylinders and ellipsoids, not
a half space with anything but a sphere: model a floor as a large box.  ``drake_drop`` runs the
continuous plant with point contact from the touchdown state and measures the rebound.

**The base.** A URDF's root link is fixed to the world where MuJoCo and PyBullet load it (the
package's PyBullet drops load with ``useFixedBase``); Drake's parser leaves it floating, so the same
file was a fixed arm in two engines and a falling robot in the third.  Here a URDF's root links
(bodies no joint moves) are welded to the world at the origin by default (``base="fixed"``,
``BASES``); ``base="floating"`` keeps Drake's free body.  An SDF says its own base (a joint to
``world``, or none: floating), and is read as it says.

Importing this module does not need Drake.
"""

import math
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from contactalpha.adapters.drake_point import LOADER

from .contact import MechanismContact, MechanismDrop, approach, pressing_accel
from .crossing import rebound_speed
from .discrete import DRAKE_APPROXIMATIONS
from .inputs import check_link, link_inertias

# The continuous plant's integrator accuracy in drops, and samples per undamped contact period.
ACCURACY = 1e-9
# How a URDF's root links hang: welded to the world (as MuJoCo and PyBullet load a URDF), or free.
BASES = ("fixed", "floating")
# Steps back along the approach at which ``back_in_time`` reads the plant's acceleration with the
# other contacts acting: the discrete solver already pushes a pair one or two steps from touch.
PROBE_STEPS = 10.0


# The engine's one import guard and install hint (its record's loader): ``pydrake.all``.
drake_module = LOADER.load


class ParsedPlant:
    """A parsed model: diagram, plant, scene graph, root and plant contexts."""

    def __init__(self, model_path, point_contact=False, time_step=0.0, approximation=None, base="fixed"):
        if base not in BASES:
            raise ValueError(f"base = {base!r} is outside the valid choices {BASES}")
        dk = drake_module()
        builder = dk.DiagramBuilder()
        self.plant, self.scene_graph = dk.AddMultibodyPlantSceneGraph(builder, float(time_step))
        if point_contact:
            self.plant.set_contact_model(dk.ContactModel.kPoint)
        if time_step > 0.0:
            self.plant.set_discrete_contact_approximation(
                getattr(dk.DiscreteContactApproximation, "k" + approximation.capitalize())
            )
        try:
            instances = dk.Parser(self.plant).AddModels(str(model_path))
        except RuntimeError as err:
            text = " ".join(str(err).split())
            fix = ""
            if "unsupported extension" in text:
                fix = ("; Drake reads .obj, .vtk and .gltf meshes: convert the mesh (pybullet_data ships "
                       ".obj twins beside its .stl files), or tune with --engine mujoco or pybullet, "
                       "whose readers take .stl")  # fmt: skip
            raise ValueError(
                f"model = {str(model_path)!r}: Drake cannot parse it: {text[:300]}{fix}"
            ) from None
        self.welded = ()
        if base == "fixed" and str(model_path).lower().endswith(".urdf"):
            self.welded = _weld_roots(self.plant, instances)
        self.plant.Finalize()
        self.diagram = builder.Build()
        self.root = self.diagram.CreateDefaultContext()
        self.context = self.plant.GetMyContextFromRoot(self.root)

    def geometry(self, name):
        """The proximity geometry id called ``name``; ValueError listing the model's otherwise."""
        dk = drake_module()
        inspector = self.scene_graph.model_inspector()
        ids = inspector.GetAllGeometryIds(dk.Role.kProximity)
        names = {gid: inspector.GetName(gid) for gid in ids}
        hits = [gid for gid, n in names.items() if n == name or n.split("::")[-1] == name]
        if len(hits) != 1:
            raise ValueError(
                f"geometry {name!r} matches {len(hits)} collision geometries; "
                f"the model's: {sorted(names.values())}"
            )
        return hits[0]

    def body(self, gid):
        """The body that carries geometry ``gid``."""
        return self.plant.GetBodyFromFrameId(self.scene_graph.model_inspector().GetFrameId(gid))

    def closest(self, g1, g2):
        """``(point, normal from 1 to 2, gap)`` in world."""
        qo = self.plant.get_geometry_query_input_port().Eval(self.context)
        try:
            r = qo.ComputeSignedDistancePairClosestPoints(g1, g2)
        except RuntimeError as err:
            raise ValueError(
                f"Drake has no signed distance for this pair: {' '.join(str(err).split())[:200]}"
            ) from None
        # Drake may return the pair in its own order (id_A is geometry 2): then A and B swap.
        p1, p2, n_21 = (r.p_ACa, r.p_BCb, np.asarray(r.nhat_BA_W)) if r.id_A == g1 else (
            r.p_BCb, r.p_ACa, -np.asarray(r.nhat_BA_W))  # fmt: skip
        pa = qo.GetPoseInWorld(g1) @ p1
        pb = qo.GetPoseInWorld(g2) @ p2
        point, normal = 0.5 * (pa + pb), -n_21
        if not np.all(np.isfinite(normal)):  # touching: the pair has no direction; geometry 1's normal
            normal = self._outward(qo, g1, point)
        return point, normal, float(r.distance)

    def _outward(self, qo, gid, point):
        for d in qo.ComputeSignedDistanceToPoint(np.asarray(point), 1e-6):
            if d.id_G == gid:
                return np.asarray(d.grad_W) / np.linalg.norm(d.grad_W)
        raise ValueError("Drake gives no normal at the contact point of the touching pair")

    def point_jacobian(self, body, point):
        """(3, nv) translational Jacobian of the world ``point`` fixed to ``body``."""
        dk = drake_module()
        frame = body.body_frame()
        p_B = frame.CalcPoseInWorld(self.context).inverse() @ np.asarray(point)
        world = self.plant.world_frame()
        return self.plant.CalcJacobianTranslationalVelocity(
            self.context, dk.JacobianWrtVariable.kV, frame, p_B, world, world
        )

    def gap_row(self, g1, g2):
        """``(point, normal, gap, J)``: the pair's closest points and the gap's row."""
        point, normal, gap = self.closest(g1, g2)
        J = normal @ (self.point_jacobian(self.body(g2), point) - self.point_jacobian(self.body(g1), point))
        return point, normal, gap, J


def set_coordinates(plant, context, name, value, size):
    """Set ``qpos`` or ``qvel`` (``name``) of ``context``; ValueError unless it has ``size`` values."""
    arr = np.asarray(value, dtype=float).ravel()
    if arr.size != size:
        raise ValueError(f"{name} has {arr.size} values; the model has {size}")
    getattr(plant, "SetPositions" if name == "qpos" else "SetVelocities")(context, arr)


def _weld_roots(plant, instances):
    """Weld the root bodies of ``instances`` (no joint moves them) to the world; their names."""
    moved = {plant.get_joint(j).child_body().index() for j in plant.GetJointIndices()}
    roots = [plant.get_body(b) for inst in instances for b in plant.GetBodyIndices(inst)
             if b not in moved and b != plant.world_body().index()]  # fmt: skip
    for body in roots:
        plant.WeldFrames(plant.world_frame(), body.body_frame())
    return tuple(body.name() for body in roots)


def read_drake(
    model_path: str | Path,
    pair: tuple[str, str],
    qpos: ArrayLike | None = None,
    qvel: ArrayLike | None = None,
    speed: float | None = None,
    forces: dict | None = None,
    base: str = "fixed",
) -> MechanismContact:
    """``MechanismContact`` of ``pair`` in the SDF/URDF ``model_path`` (see the module doc)."""
    p = ParsedPlant(model_path, base=base)
    plant, ctx = p.plant, p.context
    _check_links(plant, model_path)
    if qpos is not None:
        set_coordinates(plant, ctx, "qpos", qpos, plant.num_positions())
    g1, g2 = (p.geometry(name) for name in pair)
    point, normal, gap, J = p.gap_row(g1, g2)
    M = plant.CalcMassMatrix(ctx)
    m_eff, v, qv = approach(J, M, qvel, speed)
    tau_g = plant.CalcGravityGeneralizedForces(ctx)
    tau_f = np.zeros(plant.num_velocities())
    for name, force in (forces or {}).items():
        body = plant.GetBodyByName(str(name))
        f = np.asarray(force, dtype=float)
        com = body.CalcCenterOfMassInBodyFrame(ctx)
        world = plant.world_frame()
        _drk = drake_module()
        Jc = plant.CalcJacobianTranslationalVelocity(
            ctx, _drk.JacobianWrtVariable.kV, body.body_frame(), com, world, world
        )
        tau_f += Jc.T @ f
    set_coordinates(plant, ctx, "qvel", qv, plant.num_velocities())
    tau_v = -plant.CalcBiasTerm(ctx)
    parts = [pressing_accel(J, M, tau) for tau in (tau_g, tau_f, tau_v)]
    return MechanismContact(
        engine="drake", model=str(model_path), pair=tuple(pair), point=point, normal=normal, gap=gap,
        jacobian=J, effective_mass=m_eff, accel=float(sum(parts)), gravity_accel=parts[0],
        forces_accel=parts[1], velocity_accel=parts[2], approach_speed=v,
        qpos=np.array(plant.GetPositions(ctx)), qvel=np.array(qv), forces=dict(forces or {}),
        engine_row={"base": _base_text(p, base)},
    )  # fmt: skip


def _base_text(p, base):
    if p.welded:
        return (f"fixed: the URDF's root link {', '.join(p.welded)} welded to the world (as MuJoCo and "
                "PyBullet load a URDF; weld it in your diagram too: plant.WeldFrames(plant.world_frame(), "
                f"plant.GetFrameByName({p.welded[0]!r})))")  # fmt: skip
    return "as the file says" if base == "fixed" else "floating (Drake's free root body)"


def _check_links(plant, model_path):
    """``inputs.check_link`` on every link of the file; a link moves when its joint has velocities.

    A moving link with links welded to it (fixed joints) moves as one body with them: the group's
    mass must be above 0 (each link's own values physical), as MuJoCo fuses such links.
    """
    dk = drake_module()
    joints = [plant.get_joint(dk.JointIndex(j)) for j in range(plant.num_joints())]
    moving = {j.child_body().name() for j in joints if j.num_velocities() > 0}
    welded: dict = {}
    for j in joints:
        if j.num_velocities() == 0:
            welded.setdefault(j.parent_body().name(), []).append(j.child_body().name())
    links = link_inertias(model_path)
    for name, (mass, inertia) in links.items():
        group, stack = [], [name]
        while stack:
            group.append(stack.pop())
            stack += welded.get(group[-1], [])
        if name not in moving or len(group) == 1:
            check_link(name, mass, inertia, name in moving)
            continue
        check_link(name, mass, inertia, False)
        total = sum(links.get(g, (0.0,))[0] for g in group)
        if not total > 0.0:
            raise ValueError(f"link {name!r} and the links welded to it {group[1:]}: mass = {total!r} kg; "
                             "it must be above 0 for links that move with their own joint")  # fmt: skip


def drake_drop(
    model_path: str | Path, pair: tuple[str, str], qpos: ArrayLike, qvel: ArrayLike, *, report: float = 1e-5,
    duration: float = 1.0, accuracy: float = ACCURACY, forces: dict | None = None, time_step: float = 0.0,
    approximation: str = "lagged", phase: float = 0.0, base: str = "fixed",
) -> MechanismDrop:  # fmt: skip
    """``MechanismDrop`` of the plant with point contact from touchdown.

    The pair's stiffness and dissipation are the model file's ``drake:proximity_properties``.
    ``report``: the gap's sampling interval, s; ``forces``: {body: (fx, fy, fz)} constant, N, world
    axes, at the bodies' centres of mass.  ``time_step`` > 0 runs the discrete plant with the
    discrete contact ``approximation`` (``DRAKE_APPROXIMATIONS``), sampled at every step
    (``report`` is then the step), and ``phase`` in [0, 1) starts it that fraction of a step
    before touchdown on the free motion (``back_in_time``).
    """
    dk = drake_module()
    if time_step > 0.0 and approximation not in DRAKE_APPROXIMATIONS:
        raise ValueError(
            f"approximation = {approximation!r} is outside the valid choices {DRAKE_APPROXIMATIONS}"
        )
    p = ParsedPlant(
        model_path, point_contact=True, time_step=time_step, approximation=approximation, base=base
    )
    g1, g2 = (p.geometry(name) for name in pair)
    if qpos is not None:
        set_coordinates(p.plant, p.context, "qpos", qpos, p.plant.num_positions())
    set_coordinates(p.plant, p.context, "qvel", qvel, p.plant.num_velocities())
    speed0 = -float(p.gap_row(g1, g2)[3] @ np.asarray(qvel, dtype=float))
    if time_step > 0.0:
        report = float(time_step)
        back_in_time(p, float(phase) * report, report, forces)
    sim = dk.Simulator(p.diagram, p.root)
    apply_forces(dk, p, forces)
    if time_step == 0.0:
        dk.ResetIntegratorFromFlags(sim, "runge_kutta3", report)
        sim.get_mutable_integrator().set_target_accuracy(accuracy)
    sim.Initialize()
    times, gaps, inv_masses = [0.0], [p.closest(g1, g2)[2]], []
    n = int(math.ceil(duration / report))
    for i in range(1, n + 1):
        sim.AdvanceTo(i * report)
        _, _, gap, J = p.gap_row(g1, g2)
        if gap < 0.0:  # J M^-1 J^T in contact: how far the effective mass moves
            inv_masses.append(float(J @ np.linalg.solve(p.plant.CalcMassMatrix(p.context), J)))
        times.append(i * report)
        gaps.append(gap)
        if gap > 0.0 and gaps[-2] >= 0.0 and min(gaps) < 0.0:
            break
    exit_speed, t_exit = rebound_speed(times, gaps)
    return MechanismDrop.of(exit_speed / speed0, exit_speed, t_exit, inv_masses, report)


def _generalized_forces(p, forces):
    """``J_com^T F`` summed over the named constant forces."""
    dk = drake_module()
    tau = np.zeros(p.plant.num_velocities())
    world = p.plant.world_frame()
    for name, force in (forces or {}).items():
        body = p.plant.GetBodyByName(str(name))
        com = body.CalcCenterOfMassInBodyFrame(p.context)
        Jc = p.plant.CalcJacobianTranslationalVelocity(
            p.context, dk.JacobianWrtVariable.kV, body.body_frame(), com, world, world
        )
        tau += Jc.T @ np.asarray(force, dtype=float)
    return tau


def back_in_time(p, tc, h, forces, with_contacts=False):
    """Move the plant's state back by ``tc`` on its free motion (second order).

    The velocity stored is that of half a step earlier, as the discrete plant's semi-implicit
    update stores it (``stepping.flight``).  ``with_contacts``: the motion's acceleration is the
    discrete plant's own at the state (its velocity's change over one step taken on a copy of the
    context: every other contact acting, the named forces fixed on its input port; not its
    acceleration output port, which reports the last step taken: 0 in a fresh context), read at
    the configuration PROBE_STEPS steps earlier, where the pair is apart: a body resting on a
    support (the stack's lower sphere) stays at rest, and the pair's own implicit contact impulse
    is not in it.
    """
    plant, ctx = p.plant, p.context
    v = np.array(plant.GetVelocities(ctx))
    if with_contacts:  # read PROBE_STEPS steps earlier: the pair (closing at v) is apart, pushes nothing
        q = np.array(plant.GetPositions(ctx))
        plant.SetPositions(ctx, q + plant.MapVelocityToQDot(ctx, -PROBE_STEPS * h * v))
        probe = p.root.Clone()  # one step taken on a copy: the velocity's change over it
        sim = drake_module().Simulator(p.diagram, probe)
        sim.AdvanceTo(probe.get_time() + h)
        vdot = (np.array(plant.GetVelocities(plant.GetMyContextFromRoot(probe))) - v) / h
        plant.SetPositions(ctx, q)
    else:
        tau = (
            plant.CalcGravityGeneralizedForces(ctx) + _generalized_forces(p, forces) - plant.CalcBiasTerm(ctx)
        )
        vdot = np.linalg.solve(plant.CalcMassMatrix(ctx), tau)
    qdot = plant.MapVelocityToQDot(ctx, -tc * v + 0.5 * tc * tc * vdot)
    plant.SetPositions(ctx, np.array(plant.GetPositions(ctx)) + qdot)
    plant.SetVelocities(ctx, v - (tc + 0.5 * h) * vdot)


def apply_forces(dk, p, forces) -> None:
    """Fix ``forces`` ({body: (fx, fy, fz)} N, world axes, at each body's centre of mass) on ``p``'s plant."""
    pushes = []
    for name, force in (forces or {}).items():
        body = p.plant.GetBodyByName(str(name))
        push = dk.ExternallyAppliedSpatialForce()
        push.body_index = body.index()
        push.p_BoBq_B = body.CalcCenterOfMassInBodyFrame(p.context)
        push.F_Bq_W = dk.SpatialForce(np.zeros(3), np.asarray(force, dtype=float))
        pushes.append(push)
    if pushes:
        p.plant.get_applied_spatial_force_input_port().FixValue(p.context, pushes)
