"""MuJoCo's soft contact inside a mechanism: the solref and solimp that deliver a target there.

**What MuJoCo builds.**  For a frictionless contact row (``condim = 1``; the normal row of an
elliptic cone is the same) MuJoCo's solver gives the row's acceleration

    a1 = a0 + A f,    f = max(0, (a_ref - a0) / (A + R)),

with ``A = J M^-1 J^T`` (exact, 1/m_eff), ``a0`` the free acceleration of the gap, the reference
``a_ref = -B v - K imp r`` (``r`` the gap, ``v`` its rate) and, from ``mj_makeImpedance``,

    R = (1 - imp)/imp * diagA,    K = -solref[0]/d^2,    B = -solref[1]/d        (direct mode),

where ``d = solimp[1]`` and ``imp`` the impedance (``d`` itself for a constant solimp).  ``diagA``
is not ``A``: ``mj_diagApprox`` sums the two bodies' translational ``body_invweight0``, fixed at
``qpos0``.  So

    a1 = (1 - d_e) a0 + d_e a_ref,    d_e = A / (A + R) = d A / (d A + (1 - d) diagA):

the *effective* impedance ``d_e`` replaces ``d``.  In the penetration ``delta = -r`` with the
pressing load ``a = -a0``:

    delta'' = a - max(0, d_e a + (d_e B) delta' + (d_e d K) delta),

MuJoCo's direct-mode law (``laws``' ``mujoco_soft``) with impedance ``d_e``, stiffness
``k_s = d_e d K`` and damping ``b_s = d_e B`` per unit mass.  For a free body ``diagA = A``,
``d_e = d`` and ``solref = (-k_s, -b_s)``: the package's free-body mapping.  In a mechanism the
target needs the law solved at impedance ``d_e`` and

    solref = (-k_s d / d_e, -b_s d / d_e),    solimp = (d, d, ...),

with ``k_s = k / m_eff`` for the contact stiffness k (N/m) and ``b_s = 2 zeta sqrt(k_s)``.

**The step.**  The same substitution holds step by step: the row's force at a step is
``A f = d_e (a_ref - a0)``, which is the free body's with impedance ``d_e`` and ``solref
(-k_s, -b_s)``; so a discrete (phase-mean) answer for a free body with impedance ``d_e`` carries
over with the same ``d / d_e`` scaling.
"""

import math
from dataclasses import dataclass

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.mujoco_soft import IMPEDANCE, direct_mode, per_unit_mass
from contactalpha.laws import get_law
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.stepping.registry import stepper

from .contact import MechanismContact
from .discrete import DiscreteAnswer, step_answer

# The law MuJoCo's soft contact applies (``adapters.mujoco_soft``).
MUJOCO_LAW = "mujoco_soft"
# |phase mean - target| of the continuous answer at the model's step above which ``tune`` gives
# the discrete answer (the step's own phase-mean inverse) instead.
DISCRETE_TOL = 1e-3


def effective_impedance(impedance: float, inv_mass: float, diag_approx: float) -> float:
    """``d_e = A / (A + R)`` with ``R = (1 - d)/d diagA`` and ``A = J M^-1 J^T`` (``inv_mass``)."""
    d = float(impedance)
    if not 0.0 < d < 1.0:
        raise ValueError(f"impedance = {d!r} is outside the valid range (0, 1)")
    return inv_mass / (inv_mass + (1.0 - d) / d * diag_approx)


@dataclass(frozen=True)
class MuJoCoTuning:
    """MuJoCo's parameters for one contact of a mechanism.

    ``solref``/``solimp`` deliver the target through MuJoCo's own row (``diagA``); ``free_body``
    holds the solref the free-body mapping gives (exact only where ``diagA = J M^-1 J^T``).
    ``impedance`` is solimp's d, ``effective_impedance`` d_e, ``zeta`` the law's damping ratio at
    d_e, ``xi`` the load factor, ``stiffness`` k (N/m), ``seen`` (k_s, b_s) per unit mass;
    ``discrete`` the ``DiscreteAnswer`` at MuJoCo's step (set by ``tune``), or None.
    """

    solref: tuple
    solimp: tuple
    free_body: dict
    impedance: float
    effective_impedance: float
    zeta: float
    xi: float
    stiffness: float
    seen: tuple
    discrete: DiscreteAnswer | None = None


def law_scene(contact: MechanismContact, stiffness: float) -> DropScene:
    """The contact as the drop scene of the engine laws: ``m_eff``, k, approach speed, load."""
    accel = contact.accel
    if accel < 0.0:
        if accel < -1e-9 * max(1.0, abs(contact.gravity_accel)):
            raise ValueError(
                f"the free acceleration pulls the pair apart (accel = {accel!r} m/s^2); the laws "
                "need a load that presses (>= 0)"
            )
        accel = 0.0
    return DropScene(contact.effective_mass, stiffness, contact.approach_speed, gravity=accel)


def mujoco_tuning(
    contact: MechanismContact, target: float, stiffness: float, impedance: float = IMPEDANCE
) -> MuJoCoTuning:
    """Corrected and free-body MuJoCo parameters for Newton's e_N ``target`` (see the module doc).

    The law's damping ratio comes from the front door (``contact_parameters`` with MuJoCo's law
    at the impedance that acts: d_e for the corrected parameters, d for the free-body ones).

    Parameters
    ----------
    contact : MechanismContact
        Read with MuJoCo (``engine_row["diagA"]``).
    target : float
        Newton's e_N.
    stiffness : float
        Contact stiffness along the normal, N/m.
    impedance : float
        solimp's constant d, in (0, 1).
    """
    scene = law_scene(contact, stiffness)
    d_e = effective_impedance(impedance, 1.0 / contact.effective_mass, contact.engine_row["diagA"])

    def solved(d):
        cp = contact_parameters(e_N=target, mass=scene.mass, stiffness=scene.stiffness,
                                approach_speed=scene.approach_speed, accel=scene.accel,
                                law=get_law(MUJOCO_LAW).with_impedance(d))  # fmt: skip
        zeta = float(cp.damping)
        return zeta, float(cp.xi), *per_unit_mass(zeta, scene.stiffness, scene.mass, xp=math)

    zeta, xi, k_s, _, b_s = solved(d_e)
    scale = impedance / d_e
    solref, solimp = direct_mode(k_s * scale, b_s * scale, impedance)
    zeta_free, _, _, _, b_free = solved(impedance)
    free_ref, free_imp = direct_mode(k_s, b_free, impedance)
    return MuJoCoTuning(
        solref=solref, solimp=solimp, free_body={"solref": free_ref, "solimp": free_imp, "zeta": zeta_free},
        impedance=float(impedance), effective_impedance=d_e, zeta=zeta, xi=xi,
        stiffness=float(stiffness), seen=(k_s, b_s),
    )  # fmt: skip


def solref_for(tuning: MuJoCoTuning, zeta: float) -> tuple[float, float]:
    """The corrected solref of ``tuning``'s stiffness and contact with the law's damping ratio ``zeta``."""
    k_s = tuning.seen[0]
    scale = tuning.impedance / tuning.effective_impedance
    # ``k_s**0.5``, not ``per_unit_mass``'s sqrt: the two differ in the last bit for about 1 in
    # 1,200 values, and the refined solref that ``tune`` writes stays as it was.
    return (-k_s * scale, -2.0 * float(zeta) * k_s**0.5 * scale)


def current_stiffness(contact: MechanismContact) -> float:
    """The contact stiffness (N/m) the model's own solref and solimp give through its row.

    ``k = m_eff d_e d K`` with ``d = solimp[1]`` (the impedance reached beyond solimp's width) and
    ``K`` from solref in either form (``mj_makeImpedance``).
    """
    row = contact.engine_row
    ref, imp = row["solref"], row["solimp"]
    d = imp[1]
    K = -ref[0] / (d * d) if ref[0] <= 0.0 else 1.0 / (d * d * ref[0] ** 2 * ref[1] ** 2)
    d_e = effective_impedance(d, 1.0 / contact.effective_mass, row["diagA"])
    return contact.effective_mass * d_e * d * K


def discrete_answer(
    contact: MechanismContact, tuning: MuJoCoTuning, target: float, timestep: float
) -> DiscreteAnswer | None:
    """``discrete.DiscreteAnswer``: the phase-mean inverse of MuJoCo's step map for the contact, or None.

    The map is a body on a plane with the row's ``diag_ratio = diagA m_eff``; the stiffness and
    impedance stay those of ``tuning``.  None where the map does not apply: no pressing load (the
    map needs one), or an integrator it does not reproduce (``contact.engine_row["integrator"]``).
    """
    s = stepper("mujoco")
    integrator = contact.engine_row.get("integrator", "euler")
    if contact.accel <= 0.0 or integrator not in tuple(i.lower() for i in s.integrators):
        return None
    ratio = contact.engine_row["diagA"] * contact.effective_mass
    p = s.pack(stiffness=-tuning.solref[0], damping=-tuning.solref[1], impedance=tuning.impedance,
               diag_ratio=ratio)  # fmt: skip
    return step_answer("mujoco", p, contact, target, timestep, ratio)
