"""A contact of an MJCF (or URDF) model read with MuJoCo, and its drop in MuJoCo.

``read_mujoco`` loads the model with MuJoCo's own compiler (``MjModel.from_xml_path`` reads MJCF
and URDF), puts it at the configuration, finds the pair's contact and reads from the engine:

- the contact point and normal (``mjContact.pos``, ``frame[:3]``, from geometry 1 to 2), and the
  gap (``mj_geomDistance``);
- the gap row ``J = n . (J_p(body 2) - J_p(body 1))`` at the contact point (``mj_jac``) and the
  mass matrix (``mj_fullM``): ``m_eff = 1 / (J M^-1 J^T)``;
- the generalized forces of gravity (``-qfrc_bias`` at zero velocity), of the named forces
  (``J_com^T F``) and of the velocity (``qfrc_bias(v) - qfrc_bias(0)``);
- the contact row as MuJoCo builds it: ``efc_diagA`` (from the bodies' ``body_invweight0`` at
  ``qpos0``, ``mj_diagApprox``), ``efc_R``, and the contact's ``solref`` and ``solimp``.

The contact exists at first touch only within a margin: the reader raises the two geometries'
margin in its own copy of the model (the model file is not touched; ``diagA`` does not depend on
the margin).  ``mujoco_drop`` runs the engine from the touchdown state and measures the rebound
and how much ``J M^-1 J^T`` moves during the contact.

Importing this module does not need MuJoCo.
"""

import math
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.mujoco_soft import LOADER

from . import uris
from .contact import MechanismContact, MechanismDrop, approach, pressing_accel
from .crossing import rebound_speed

# Margin (m) added to the pair's geometries so that MuJoCo builds their contact row at first touch.
ROW_MARGIN = 1e-3


# The engine's one import guard and install hint (its record's loader).
_mujoco = LOADER.load


def mujoco_module():
    """The ``mujoco`` module; ImportError with the install hint where it is missing."""
    return _mujoco()


def load_model(model):
    """An ``MjModel`` from a file path (MJCF or URDF), an MJCF string (starting with ``<``), or itself.

    A URDF's ``package://`` mesh URIs are resolved by ``uris`` (``--package-path``, ``ROS_PACKAGE_PATH``,
    or beside the file as PyBullet does).
    """
    mj = _mujoco()
    if isinstance(model, mj.MjModel):
        return model
    text = str(model)
    try:
        if text.lstrip().startswith("<"):
            return mj.MjModel.from_xml_string(text)
        if text.lower().endswith(".urdf") and uris.needs_resolving(text):
            return mj.MjModel.from_xml_string(uris.resolved_text(text, uris.active()))
        return mj.MjModel.from_xml_path(text)
    except ValueError as err:
        raise ValueError(
            f"model = {text[:80]!r}: MuJoCo cannot load it: {' '.join(str(err).split())}"
        ) from None


def geom_id(model, name):
    """The id of the geometry called ``name``; ValueError naming the model's geometries otherwise."""
    mj = _mujoco()
    gid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, str(name))
    if gid < 0:
        names = [mj.mj_id2name(model, mj.mjtObj.mjOBJ_GEOM, i) for i in range(model.ngeom)]
        raise ValueError(
            f"geometry {name!r} is not in the model; its named geometries: {[n for n in names if n]}"
        )
    return gid


def set_state(model, data, qpos, qvel):
    """Put ``qpos`` (default ``qpos0``) and ``qvel`` (default 0) into ``data``, checking their sizes."""
    for name, value, size in (("qpos", qpos, model.nq), ("qvel", qvel, model.nv)):
        if value is None:
            continue
        arr = np.asarray(value, dtype=float).ravel()
        if arr.size != size:
            raise ValueError(f"{name} has {arr.size} values; the model has {size}")
        getattr(data, name)[:] = arr
    if qpos is None:
        data.qpos[:] = model.qpos0


def _find_contact(data, g1, g2):
    for i in range(data.ncon):
        c = data.contact[i]
        if {int(c.geom[0]), int(c.geom[1])} == {g1, g2}:
            return i, (1.0 if int(c.geom[0]) == g1 else -1.0)
    return None, 0.0


def _gap_jacobian(model, data, g1, g2, point, normal):
    mj = _mujoco()
    rows = []
    for g in (g1, g2):
        jacp = np.zeros((3, model.nv))
        mj.mj_jac(model, data, jacp, None, np.asarray(point, dtype=float), int(model.geom_bodyid[g]))
        rows.append(jacp)
    return np.asarray(normal) @ (rows[1] - rows[0])


def mass_matrix(model, data):
    """The dense joint-space mass matrix (armature included), after ``mj_forward``."""
    mj = _mujoco()
    M = np.zeros((model.nv, model.nv))
    mj.mj_fullM(model, data, M)
    return M


def _forces_tau(model, data, forces):
    mj = _mujoco()
    tau = np.zeros(model.nv)
    for body, force in (forces or {}).items():
        bid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, str(body))
        if bid < 0:
            raise ValueError(f"forces names body {body!r}, which is not in the model")
        f = np.asarray(force, dtype=float)
        if f.shape != (3,) or not np.all(np.isfinite(f)):
            raise ValueError(f"forces[{body!r}] = {force!r} must be 3 finite numbers (N, world axes)")
        jacp = np.zeros((3, model.nv))
        mj.mj_jacBodyCom(model, data, jacp, None, bid)
        tau += jacp.T @ f
    return tau


def normal_rows(model, condim):
    """How many constraint rows carry the normal force: 2 (condim - 1) pyramid edges, else 1.

    A pyramidal contact (``mj_instantiateContact``) has no normal row: its edges ``J_n +- mu J_t``
    all sit at the contact's distance, and ``mj_makeImpedance`` gives them one common ``R``.
    Where the tangential motion is decoupled from the normal (``J_t M^-1 J_n^T = 0``) and the
    contact does not slide, the edges' forces are equal in pairs and the normal force ``F`` (their
    sum) obeys the frictionless row with ``R / (2 (condim - 1))``; so does ``diagA`` (which
    ``mj_makeImpedance`` resets to ``R imp / (1 - imp)``).
    """
    mj = _mujoco()
    if condim > 1 and model.opt.cone == mj.mjtCone.mjCONE_PYRAMIDAL:
        return 2 * (condim - 1)
    return 1


def contact_row(model, data, g1, g2):
    """``(point, normal, gap, row)`` of the pair's contact at ``data``'s configuration.

    ``row`` holds MuJoCo's ``diagA``, ``R``, ``solref``, ``solimp`` and ``condim`` of the contact;
    for a pyramidal cone ``diagA`` and ``R`` are those of the normal force's equivalent row
    (``normal_rows``: the edges' values over their number), ``cone`` and ``rows`` say which.
    ``R`` is MuJoCo's with the margin raised by ``ROW_MARGIN``: where solimp's width is at most
    that (MuJoCo's default 0.001), at the impedance ``solimp[1]``.
    Raises ValueError when MuJoCo builds no contact between the two (contype/conaffinity, an
    exclude, a parent-child filter) or when the pair is farther apart than 1 m.
    """
    mj = _mujoco()
    mj.mj_forward(model, data)
    fromto = np.zeros(6)
    gap = float(mj.mj_geomDistance(model, data, g1, g2, 1.0, fromto))
    if gap >= 1.0:
        raise ValueError(
            "the pair is more than 1 m apart at this configuration: give the configuration of touch"
        )
    saved = model.geom_margin[[g1, g2]].copy(), model.pair_margin.copy()
    margin = max(gap, 0.0) + ROW_MARGIN
    model.geom_margin[[g1, g2]] = np.maximum(saved[0], margin)
    model.pair_margin[:] = np.maximum(saved[1], margin)
    try:
        mj.mj_forward(model, data)
        i, sign = _find_contact(data, g1, g2)
        if i is None:
            raise ValueError(
                "MuJoCo builds no contact between the pair (contype/conaffinity, an exclude or a "
                "parent-child filter): add a <pair> for them to the model"
            )
        c = data.contact[i]
        adr = int(c.efc_address)
        rows = normal_rows(model, int(c.dim))
        row = {
            "diagA": float(data.efc_diagA[adr]) / rows,
            "R": float(data.efc_R[adr]) / rows,
            "cone": "pyramidal" if rows > 1 else ("elliptic" if c.dim > 1 else "frictionless"),
            "rows": rows,
            "solref": tuple(float(x) for x in c.solref),
            "solimp": tuple(float(x) for x in c.solimp),
            "condim": int(c.dim),
            "friction": tuple(float(x) for x in c.friction),
            "geom_margin": float(max(saved[0])),
            "geom_gap": float(max(model.geom_gap[[g1, g2]])),
            "timestep": float(model.opt.timestep),
            "integrator": mj.mjtIntegrator(model.opt.integrator).name.removeprefix("mjINT_").lower(),
        }
        return np.array(c.pos), sign * np.array(c.frame[:3]), gap, row
    finally:
        model.geom_margin[[g1, g2]] = saved[0]
        model.pair_margin[:] = saved[1]
        mj.mj_forward(model, data)


# MuJoCo's integrators the answer is for: semi-implicit Euler, and the implicit ones (the same
# step where no velocity-dependent force acts in the contact; measured: identical e_N).
MODELLED_INTEGRATORS = ("euler", "implicit", "implicitfast")


def unmodelled_settings(model):
    """The model's settings that change the contact's e_N and that ``tune``'s answer leaves out.

    Text, one line each: an integrator outside ``MODELLED_INTEGRATORS`` (RK4) and fluid forces
    (``density``, ``viscosity``); ``read_mujoco`` adds the joint forces of ``_joint_forces``.
    Settings under which no tuned pair acts are refused (ValueError): the override flag
    (``opt.o_solref``, ``o_solimp`` and ``o_margin`` replace every contact's, the written pair's
    too), contacts or constraints disabled.  docs/engines/mujoco.md lists what the answer assumes.
    """
    mj = _mujoco()
    opt, out = model.opt, []
    if opt.enableflags & mj.mjtEnableBit.mjENBL_OVERRIDE:
        raise ValueError(
            'the model enables override (<flag override="enable"/>): its o_solref, o_solimp and '
            "o_margin replace every contact's, a tuned pair's too; disable it to tune"
        )
    for bit in (mj.mjtDisableBit.mjDSBL_CONTACT, mj.mjtDisableBit.mjDSBL_CONSTRAINT):
        if opt.disableflags & bit:
            name = bit.name.removeprefix("mjDSBL_").lower()
            raise ValueError(f'the model disables {name} (<flag {name}="disable"/>): no pair touches')
    integrator = mj.mjtIntegrator(opt.integrator).name.removeprefix("mjINT_").lower()
    if integrator not in MODELLED_INTEGRATORS:
        out.append(f"integrator {integrator}: the answer is for {'/'.join(MODELLED_INTEGRATORS)}; "
                   f"{integrator} changes the contact's e_N")  # fmt: skip
    if opt.density > 0.0 or opt.viscosity > 0.0:
        out.append(f"fluid forces (density {opt.density:g}, viscosity {opt.viscosity:g}) act in the "
                   "contact and are not in the answer")  # fmt: skip
    return tuple(out)


def _joint_forces(model, J):
    """Joint damping, springs and friction loss on the joints the contact row moves (``J != 0``)."""
    mj = _mujoco()
    moved = np.flatnonzero(np.abs(np.asarray(J)) > 1e-12 * max(1e-300, float(np.max(np.abs(J)))))
    out = []
    off = mj.mjtDisableBit
    kinds = (("damping", model.dof_damping, off.mjDSBL_DAMPER),
             ("frictionloss", model.dof_frictionloss, off.mjDSBL_FRICTIONLOSS),
             ("stiffness", model.jnt_stiffness[model.dof_jntid], off.mjDSBL_SPRING))  # fmt: skip
    for what, values, bit in kinds:
        if model.opt.disableflags & bit:
            continue
        for dof in moved:
            if values[dof] > 0.0:
                joint = model.joint(int(model.dof_jntid[dof])).name or f"#{int(model.dof_jntid[dof])}"
                out.append(f"joint {joint!r} {what} {float(values[dof]):g} acts in the contact and is not "
                           "in the answer")  # fmt: skip
    return tuple(out)


def other_contacts(model, data, g1, g2, margin=ROW_MARGIN):
    """The contacts other than the pair's active at ``data``'s configuration, and the pair's points.

    Returns ``(("a/b", ...), n)``: ``n`` is how many points the pair itself touches at (a flat
    box on the floor: 4).

    Every geometry's margin is raised by ``margin`` (m) in memory for the look, so that a body
    resting exactly on another (the stack's lower sphere on the floor) is found.
    """
    mj = _mujoco()
    saved = model.geom_margin.copy(), model.pair_margin.copy()
    model.geom_margin[:] = saved[0] + margin
    model.pair_margin[:] = saved[1] + margin
    try:
        mj.mj_forward(model, data)
        found, points = [], 0
        for i in range(data.ncon):
            a, b = (int(x) for x in data.contact[i].geom)
            if {a, b} == {g1, g2}:
                points += 1
                continue
            names = [mj.mj_id2name(model, mj.mjtObj.mjOBJ_GEOM, g) or f"geom {g}" for g in (a, b)]
            found.append("/".join(names))
        return tuple(dict.fromkeys(found)), points
    finally:
        model.geom_margin[:] = saved[0]
        model.pair_margin[:] = saved[1]
        mj.mj_forward(model, data)


# How far (m) above the lowest point ``pair_heights`` looks for the pair's other points.
HEIGHT_LOOK = 0.05


def pair_heights(model, data, g1, g2, look=HEIGHT_LOOK):
    """The signed distances (m, ascending) of the pair's contact points within ``look`` of touch.

    A box over a floor gives its corners' heights (a flat box: four equal values); a single
    point one value.  The two geometries' margins are raised by ``look`` in memory for the look.
    """
    mj = _mujoco()
    saved = model.geom_margin.copy(), model.pair_margin.copy()
    model.geom_margin[[g1, g2]] = saved[0][[g1, g2]] + look
    model.pair_margin[:] = saved[1] + look
    try:
        mj.mj_forward(model, data)
        out = [float(data.contact[i].dist) for i in range(data.ncon)
               if {int(x) for x in data.contact[i].geom} == {g1, g2}]  # fmt: skip
        return tuple(sorted(out))
    finally:
        model.geom_margin[:] = saved[0]
        model.pair_margin[:] = saved[1]
        mj.mj_forward(model, data)


def read_mujoco(model_path, pair, qpos=None, qvel=None, speed=None, forces=None):
    """``MechanismContact`` of ``pair`` in the MJCF/URDF ``model_path`` (see the module doc)."""
    mj = _mujoco()
    model = load_model(model_path)
    unmodelled = unmodelled_settings(model)
    data = mj.MjData(model)
    g1, g2 = (geom_id(model, name) for name in pair)
    if g1 == g2:
        raise ValueError(f"pair = {tuple(pair)!r} names one geometry twice")
    set_state(model, data, qpos, None)
    point, normal, gap, row = contact_row(model, data, g1, g2)
    row["other_contacts"], row["pair_points"] = other_contacts(model, data, g1, g2)
    row["pair_heights"] = pair_heights(model, data, g1, g2)
    J = _gap_jacobian(model, data, g1, g2, point, normal)
    M = mass_matrix(model, data)
    m_eff, v, qv = approach(J, M, qvel, speed)
    unmodelled += _joint_forces(model, J)
    tau_g = -np.array(data.qfrc_bias)  # at zero velocity: gravity only
    tau_f = _forces_tau(model, data, forces)
    data.qvel[:] = qv
    mj.mj_forward(model, data)
    tau_v = -(np.array(data.qfrc_bias) + tau_g)
    parts = [pressing_accel(J, M, tau) for tau in (tau_g, tau_f, tau_v)]
    return MechanismContact(
        engine="mujoco", model=str(model_path), pair=tuple(pair), point=point, normal=normal, gap=gap,
        jacobian=J, effective_mass=m_eff, accel=float(sum(parts)), gravity_accel=parts[0],
        forces_accel=parts[1], velocity_accel=parts[2], approach_speed=v, qpos=np.array(data.qpos),
        qvel=np.array(qv), forces=dict(forces or {}),
        engine_row={**row, "JMinvJT": 1.0 / m_eff, "unmodelled": unmodelled},
    )  # fmt: skip


def mujoco_drop(
    model, pair, qpos, qvel, *, timestep=None, duration=1.0, forces=None, pair_solref=None, phase=0.0
):
    """Run MuJoCo from the touchdown state ``(qpos, qvel)`` until the pair separates.

    Parameters
    ----------
    model : path, MJCF string, or an ``MjModel`` (used as it is: ``pair_solref`` and ``timestep``
        change it in place; ``engine_loop`` drops one loaded model at many phases).
    pair : (geometry 1, geometry 2).
    qpos, qvel : touchdown configuration and joint velocity.
    timestep : s (default the model's).
    duration : longest time run, s.
    forces : {body: (fx, fy, fz)} constant forces at the bodies' centres of mass, N, world axes.
    pair_solref : (2,) solref put on the model's ``<pair>`` of the two geometries (in memory).
    phase : in [0, 1): the first step starts ``phase`` of a step before touchdown, on the free
        motion (``stepping.flight.touchdown_state``'s convention: the stored velocity is that of
        half a step earlier, as semi-implicit Euler stores it).
    """
    mj = _mujoco()
    m = load_model(model)
    g1, g2 = (geom_id(m, name) for name in pair)
    if pair_solref is not None:
        rows = [i for i in range(m.npair) if {int(m.pair_geom1[i]), int(m.pair_geom2[i])} == {g1, g2}]
        if not rows:
            raise ValueError("pair_solref needs a <pair> of the two geometries in the model")
        m.pair_solref[rows] = np.asarray(pair_solref, dtype=float)
    if timestep is not None:
        m.opt.timestep = float(timestep)
    td = touchdown(m, g1, g2, qpos, qvel, forces)
    d, speed0 = start_state(m, td, phase), td.speed
    h = float(m.opt.timestep)
    nmax = int(math.ceil(duration / h))
    gaps, inv_masses = [], []
    inv_touch = math.nan
    for _ in range(nmax):
        mj.mj_step1(m, d)  # positions and velocities of this step's start: the sample
        gap = float(mj.mj_geomDistance(m, d, g1, g2, 1.0, None))
        gaps.append(gap)
        i, sign = _find_contact(d, g1, g2)
        if i is not None:
            c = d.contact[i]
            J = _gap_jacobian(m, d, g1, g2, c.pos, sign * np.array(c.frame[:3]))
            inv = float(J @ np.linalg.solve(mass_matrix(m, d), J))
            inv_touch = inv if math.isnan(inv_touch) else inv_touch
            inv_masses.append(inv)
        if len(gaps) > 3 and gap > 0.0 and min(gaps) < 0.0 and gaps[-2] >= 0.0:
            break
        mj.mj_step2(m, d)
    t = np.arange(len(gaps)) * h
    exit_speed, t_exit = rebound_speed(t, gaps)
    return MechanismDrop.of(exit_speed / speed0, exit_speed, t_exit, inv_masses, h)


@dataclass(frozen=True)
class Touchdown:
    """The touchdown state of a drop and its free motion.

    ``qpos``, ``qvel``, ``qacc`` (the mechanism's acceleration with every constraint but the
    pair's contact), ``speed`` (the gap's closing rate) and ``xfrc`` (the constant forces,
    MuJoCo's ``xfrc_applied``).
    """

    qpos: np.ndarray
    qvel: np.ndarray
    qacc: np.ndarray
    speed: float
    xfrc: np.ndarray


def touchdown(m, g1, g2, qpos, qvel, forces=None):
    """``Touchdown`` of the pair ``g1``, ``g2`` at ``(qpos, qvel)`` with constant ``forces``.

    The free motion keeps a body resting on a support (the stack's lower sphere) on it: the
    pair's ``<pair>`` rows are switched off by a margin of -1 m for the look; where the model has
    none, the pair's own contact at touch carries no force.
    """
    mj = _mujoco()
    d = mj.MjData(m)
    set_state(m, d, qpos, qvel)
    for body, force in (forces or {}).items():
        d.xfrc_applied[mj.mj_name2id(m, mj.mjtObj.mjOBJ_BODY, str(body))] = (*force, 0.0, 0.0, 0.0)
    speed = -float(_gap_rate_at_start(m, d.qpos, d.qvel, g1, g2))
    rows = [i for i in range(m.npair) if {int(m.pair_geom1[i]), int(m.pair_geom2[i])} == {g1, g2}]
    saved = m.pair_margin[rows].copy()
    m.pair_margin[rows] = -1.0
    try:
        mj.mj_forward(m, d)
        qacc = np.array(d.qacc)
    finally:
        m.pair_margin[rows] = saved
    return Touchdown(np.array(d.qpos), np.array(d.qvel), qacc, speed, np.array(d.xfrc_applied))


def start_state(m, td, phase=0.0):
    """A drop's first ``MjData``: ``phase`` of a step before touchdown ``td`` on its free motion.

    Semi-implicit Euler (``qvel += h qacc``, then the positions with the new ``qvel``) keeps its
    positions on the free motion when the stored velocity is the one half a step before the
    stored position's time (``stepping.flight.touchdown_state``).
    """
    mj = _mujoco()
    h = float(m.opt.timestep)
    tc = float(phase) * h
    d = mj.MjData(m)
    d.xfrc_applied[:] = td.xfrc
    mean = td.qvel - 0.5 * tc * td.qacc
    qpos = np.array(td.qpos)
    mj.mj_integratePos(m, qpos, mean, -tc)
    d.qpos[:] = qpos
    d.qvel[:] = td.qvel - (tc + 0.5 * h) * td.qacc
    return d


def _gap_rate_at_start(m, qpos, qvel, g1, g2):
    mj = _mujoco()
    d = mj.MjData(m)
    set_state(m, d, qpos, qvel)
    point, normal, _, _ = contact_row(m, d, g1, g2)
    return float(_gap_jacobian(m, d, g1, g2, point, normal) @ d.qvel)


def reader_joint_names(contact) -> list[str] | None:
    """The joints of the reader's coordinates, by name (MuJoCo's reader; None for Drake's: URDF order)."""
    if contact.engine != "mujoco":
        return None
    m = load_model(contact.model)
    return [m.joint(i).name for i in range(m.njnt)]
