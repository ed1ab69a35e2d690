"""A sphere dropped on a plane in MuJoCo, with the soft contact in its direct mode.

**The law** (``mujoco_soft``).  With ``solref = (-stiffness, -damping)`` (direct mode, both in
acceleration units: s^-2 and s^-1, per unit mass) and a constant impedance ``solimp = (d, d,
...)``, MuJoCo's constraint solver gives the contact acceleration ``(1 - d) a0 + d a_ref`` with
``a_ref = -(damping/d) v - (stiffness/d^2) d r`` (``mj_makeImpedance``: ``K = -solref[0]/d^2``,
``B = -solref[1]/d``; ``a_ref = -B v - K imp r``).  In the penetration δ:

    δ'' = a - max(0, d a + damping δ' + stiffness δ),

so the spring-dashpot carries (1 - d) of the load and its floor is shifted by d a.  Checked in
the engine: a ball at rest sits at δ = (1 - d) a / stiffness (``static_penetration``).  The mass
enters through MuJoCo's regulariser ``R = (1 - d)/d * diagApprox``; for one body on a slide joint
``diagApprox`` is exactly 1/m, which is what makes the law mass-free ("per unit mass").

**Parameters.**  A scene's linear stiffness k (N/m) and mass m give ``stiffness = k/m`` and the law's
damping ratio zeta gives ``damping = 2 zeta sqrt(k/m)``.  The same values go on both geoms: for two
geoms of equal priority MuJoCo takes the element-wise *minimum* of two direct-mode solrefs and the
``solmix``-weighted mean of the solimps (``mj_contactParam``).  Where it exists the default
(timeconst, dampratio) form is ``(1/(zeta omega), zeta)``: MuJoCo's "refsafe" raises any timeconst
below 2 timestep, so the form exists only for ``1/(zeta omega) >= 2 timestep``.

**The drop.**  One body with a sphere on a vertical slide joint (``condim = 1``: no friction), gravity
``g`` and a motor on the joint pushing with ``-F``.  ``mujoco.rollout`` runs every touchdown phase in
one call; ``contactalpha.adapters.stepped`` measures the rebound and refines the damping.

Importing this module does not need MuJoCo.
"""

import math
import time
from dataclasses import dataclass

import numpy as np

from contactalpha.adapters.contract import Samples, law_damping
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.record import Engine, ModelFile, Ref
from contactalpha.adapters.stepped import SteppingAdapter, float_or_array, touchdown_state
from contactalpha.laws import get_law
from contactalpha.laws.law import MUJOCO_IMPEDANCE
from contactalpha.stepping.mujoco_map import TIMESTEP
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_range

# The one import guard of MuJoCo (its adapter, its model-file reader and drop, MJX's drop).
LOADER = Loader("MuJoCo", ("mujoco", "mujoco.rollout"), "mujoco")
# The law's default impedance (MuJoCo's default solimp[0]); MuJoCo's default step is the map's.
IMPEDANCE = MUJOCO_IMPEDANCE
# solimp's width, midpoint and power: MuJoCo's defaults; with solimp[0] = solimp[1] = d they do
# not matter (the impedance is d at every penetration).
SOLIMP_TAIL = (0.001, 0.5, 2.0)


def per_unit_mass(zeta, stiffness, mass, xp=np):
    """``(s, omega, b)``: the law's direct-mode pair per unit mass for the damping ratio ``zeta``.

    ``s = k/m`` (1/s^2), ``omega = sqrt(s)`` (1/s) and ``b = 2 zeta omega`` (1/s): ``solref = (-s,
    -b)`` on a free body.  The one home of the mapping: the adapter, a mechanism's row
    (``mechanism.mujoco_row``) and the JAX blocks (``xla.engines``) call it.  ``xp`` is the
    array module (NumPy, ``math`` for floats, or ``jax.numpy``).
    """
    s = stiffness / mass
    omega = xp.sqrt(s)
    return s, omega, 2.0 * zeta * omega


def direct_mode(stiffness, damping, impedance):
    """``solref = (-stiffness, -damping)`` (per unit mass) and ``solimp`` with the constant ``impedance``."""
    return (-stiffness, -damping), (impedance, impedance, *SOLIMP_TAIL)


def timeconst_form(zeta, omega, timestep, xp=np):
    """MuJoCo's ``solref = (timeconst, dampratio)`` of damping ratio ``zeta`` at ``omega = sqrt(stiffness)``.

    ``(1/(zeta omega), zeta)`` where MuJoCo's refsafe keeps it (timeconst >= 2 ``timestep``), NaN
    elsewhere: there only the direct mode delivers the law.  ``xp`` is the array module (NumPy, or
    ``jax.numpy`` for the JAX front door).
    """
    safe = xp.where(zeta > 0.0, zeta, 1.0)
    tc = xp.where(zeta > 0.0, 1.0 / (safe * omega), xp.inf)
    ok = tc >= 2.0 * timestep
    return xp.where(ok, tc, xp.nan), xp.where(ok, zeta, xp.nan)


_mujoco = LOADER.load


@dataclass(frozen=True)
class MuJoCoSettings:
    """Settings of a MuJoCo drop.

    ``timestep`` (s; MuJoCo's default), ``impedance`` d (constant solimp), ``phases`` touchdown
    phases averaged, ``window`` length of a run in undamped contact periods 2 pi / omega,
    ``tol`` on the delivered e_N (refinement and warnings), ``integrator`` MuJoCo's name.
    """

    timestep: float = TIMESTEP
    impedance: float = IMPEDANCE
    phases: int = 8
    window: float = 3.0
    tol: float = 1e-3
    integrator: str = "Euler"


def drop_xml(scene, settings):
    """MJCF of the drop: a sphere on a vertical slide joint over a plane, both geoms direct-mode."""
    _, solimp = direct_mode(1.0, 1.0, settings.impedance)
    imp = f'solimp="{" ".join(map(repr, solimp))}"'
    return f"""<mujoco model="contactalpha_drop">
  <option timestep="{settings.timestep!r}" gravity="0 0 {-scene.gravity!r}"
          integrator="{settings.integrator}"/>
  <worldbody>
    <geom name="ground" type="plane" size="1 1 0.1" condim="1" solref="-1 -1" {imp}/>
    <body name="ball" pos="0 0 {scene.radius!r}">
      <joint name="z" type="slide" axis="0 0 1"/>
      <geom name="ball" type="sphere" size="{scene.radius!r}" mass="{scene.mass!r}" condim="1"
            solref="-1 -1" {imp}/>
    </body>
  </worldbody>
  <actuator><motor joint="z" gear="1" ctrllimited="false"/></actuator>
</mujoco>"""


@dataclass
class _Drop:
    model: object
    data: object
    states: np.ndarray
    push: float
    nstep: int


class MuJoCoAdapter(SteppingAdapter):
    """MuJoCo's soft contact in direct mode: the engine adapter (``adapters.contract``)."""

    name = "mujoco"
    law = get_law("mujoco_soft", impedance=IMPEDANCE)
    module = LOADER.module
    settings = MuJoCoSettings()
    # Units of ``parameters``: per unit mass (MuJoCo's solref in direct mode).
    units = {
        "stiffness": "1/s^2",
        "damping": "1/s",
        "solref": "(1/s^2, 1/s)",
        "solimp": "1, 1, m, 1, 1",
        "timeconst": "s",
        "dampratio": "1",
    }

    def version(self):
        """MuJoCo's version string."""
        return _mujoco().__version__

    def parameters(self, damping, scene, settings=None):
        """``solref`` (direct), ``solimp`` and, where it exists, ``solref`` as (timeconst, dampratio).

        ``damping`` is the law's damping ratio zeta (>= 0); arrays go through.  One scene's
        ``solref`` and ``solimp`` are tuples; a batch's are arrays of shape ``(*batch, 2)`` and
        ``(*batch, 5)``, a row per world (MJX's and MuJoCo Warp's ``geom_solref``/``geom_solimp``).
        """
        settings = self.settings if settings is None else settings
        zeta = np.asarray(check_range("damping", damping, 0.0, math.inf, hi_open=True))
        omega2, omega, b = per_unit_mass(zeta, scene.stiffness, scene.mass)
        stiffness = np.broadcast_to(omega2, b.shape)
        tc, dr = timeconst_form(zeta, omega, settings.timestep)
        solref, solimp = direct_mode(float_or_array(stiffness), float_or_array(b), settings.impedance)
        if b.ndim:  # a batch: one row per world, the shape MJX and MuJoCo Warp take ((..., 2), (..., 5))
            solref = np.stack(solref, axis=-1)
            solimp = np.stack(np.broadcast_arrays(*solimp, b), axis=-1)[..., :-1]
        return {
            "stiffness": float_or_array(stiffness),
            "damping": float_or_array(b),
            "solref": solref,
            "solimp": solimp,
            "timeconst": float_or_array(tc),
            "dampratio": float_or_array(dr),
        }

    def build_drop(self, scene, params, settings):
        """The model with ``params["solref"]`` on both geoms; one initial state per touchdown phase."""
        mj = _mujoco()
        model = mj.MjModel.from_xml_string(drop_xml(scene, settings))
        k, b = (float(x) for x in params["solref"])
        model.geom_solref[:] = (k, b)
        h = settings.timestep
        phases = np.arange(settings.phases) / settings.phases
        states = np.array([[0.0, *touchdown_state(scene.approach_speed, scene.accel, h, p)] for p in phases])
        omega = math.sqrt(-k)
        nstep = int(math.ceil(settings.window * 2.0 * math.pi / omega / h)) + 4
        return _Drop(model, mj.MjData(model), states, -scene.force, nstep)

    def run(self, model, scene, settings):
        """Every phase in one ``mujoco.rollout`` call: ``Samples`` of the first phase, all in ``extra``."""
        mj = _mujoco()
        control = np.full((len(model.states), model.nstep, 1), model.push)
        start = time.perf_counter()
        out, _ = mj.rollout.rollout(model.model, model.data, model.states, control)
        seconds = time.perf_counter() - start
        states = np.concatenate([model.states[:, None, :], out], axis=1)
        z, v = states[:, :, 1], states[:, :, 2]
        h = settings.timestep
        t = np.arange(z.shape[1]) * h
        return Samples(t, -z[0], -v[0], seconds, {"z": z, "v": v, "timestep": h})

    def static_penetration(self, scene, params=None, settings=None):
        """Deformation (m) at rest, read after the engine settles (``damping`` critical by default)."""
        mj = _mujoco()
        settings = self.settings if settings is None else settings
        omega2 = scene.stiffness / scene.mass
        params = params or {"solref": (-omega2, -2.0 * math.sqrt(omega2))}
        model = mj.MjModel.from_xml_string(drop_xml(scene, settings))
        model.geom_solref[:] = tuple(float(x) for x in params["solref"])
        data = mj.MjData(model)
        data.qpos[0] = -(1.0 - settings.impedance) * scene.accel / omega2
        data.ctrl[0] = -scene.force
        nstep = int(math.ceil(40.0 * 2.0 * math.pi / math.sqrt(omega2) / settings.timestep))
        for _ in range(nstep):
            mj.mj_step(model, data)
        return -float(data.qpos[0])

    def timestep(self, settings):
        """MuJoCo's fixed step, s."""
        return settings.timestep

    def law_damping(self, scene, target, restitution="kinematic", settings=None):
        """``(solution, xi)``: the law's exact damping for the target e_N (``contract.law_damping``)."""
        settings = self.settings if settings is None else settings
        law = get_law("mujoco_soft", impedance=settings.impedance)
        return law_damping(law, scene, target, restitution, per_unit_mass=True)


ADAPTER = MuJoCoAdapter()
# The JAX block of MuJoCo's soft contact: MuJoCo, MJX and MuJoCo Warp take the same solref rows.
_SOFT_BLOCK = Ref("contactalpha.xla.engines:mujoco_block")
ENGINE = Engine(
    adapter=ADAPTER,
    loader=LOADER,
    step_map=stepper("mujoco"),
    model_file=ModelFile(
        suffixes=(".xml", ".mjcf", ".urdf"),
        reader=Ref("contactalpha.mechanism.mujoco_model:read_mujoco"),
        tuner=Ref("contactalpha.mechanism.tuners:MUJOCO_TUNER"),
    ),
    # The batched engines that run MuJoCo's soft contact (Genesis and Newton's MuJoCo solver too).
    batched={
        "mujoco": _SOFT_BLOCK,
        "mjx": _SOFT_BLOCK,
        "mujoco_warp": _SOFT_BLOCK,
        "genesis": Ref("contactalpha.xla.engines:genesis_block"),
        "newton": Ref("contactalpha.xla.engines:newton_block"),
    },
)
