"""The engine in the loop: a contact of the user's whole model tuned on the engine's own drops.

The reduced model (``read_contact``: the effective mass, the free load, the engine's one-contact
map) leaves out what the whole model does during the contact: joint damping, a leg folding (the
effective mass moving), friction, joint limits, servo gains, other contacts.  Here MuJoCo itself
runs the tuned model from touchdown at many touchdown phases, and the damping is solved on what
it delivers.

**The contact's e_N in a mechanism** is what a user measures in the engine: the rate of the pair's
signed gap (the contact point's relative normal speed) where it first comes back through zero
after touchdown, read off the parabola through the samples around the crossing
(``crossing.rebound_speed``), over the gap's closing speed at the start of the drop.

**Phases.** A drop starts ``phase`` of a step before touchdown on the free motion
(``mujoco_model.mujoco_drop``); the phase is periodic (phase 1 is phase 0 one step earlier).  The
mean over a uniform phase is sampled at the midpoints ``(i + 1/2) / N``: a rectangle rule on a
periodic function, exact to rounding for a smooth e_N(phase) and off by at most about the jumps'
sizes over N where one drop's step count changes.  Its error is estimated as half the difference
of the two interleaved half-samples' means (each a rectangle rule of N/2 points, shifted by half
their spacing), and N doubles from ``PHASES`` until that estimate is within ``PHASE_TOL``.

**The solve.** Secant steps on the damping slot of the pair's ``solref`` (the stiffness kept) from
the reduced model's answer (``adapters.base.refine``), each step one N-phase mean, to within
``SOLVE_TOL`` of the target; the delivered mean at the root is then resampled to ``PHASE_TOL``.

``explain`` names what the reduced model leaves out, with the share of each that can be switched
off in the engine: the phase mean at the reduced model's parameters with it, minus without it.
"""

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from contactalpha.adapters.base import refine
from contactalpha.parameters.verify import phase_mean_error

from .crossing import rebound_speed
from .mujoco_model import geom_id, load_model, mujoco_drop, mujoco_module, start_state, touchdown

# Threads of MuJoCo's rollout (the machine's two cores); each phase is its own rollout, so the
# bits do not depend on the count.
ROLLOUT_THREADS = 2

# Touchdown phases of the first sample; doubled until the mean's error estimate is within PHASE_TOL.
PHASES = 64
MAX_PHASES = 4096
# Error estimate of a phase mean at which its sampling stops (half the answer's 2e-4 budget).
PHASE_TOL = 1e-4
# |phase mean - target| at which the secant on the damping stops.
SOLVE_TOL = 2e-5


@dataclass(frozen=True)
class PhaseMean:
    """The engine's e_N over ``phases`` touchdown phases.

    ``mean``, ``minimum``, ``maximum``, ``error`` (the estimate above), ``values`` (one per
    phase), ``mass_change`` (the largest relative change of the effective mass over any drop's
    contact) and ``failed`` (drops with no rebound: the mean is NaN).
    """

    mean: float
    minimum: float
    maximum: float
    error: float
    phases: int
    values: np.ndarray = field(repr=False)
    mass_change: float = math.nan
    failed: int = 0


def phase_grid(n):
    """The ``n`` midpoint phases ``(i + 1/2) / n`` in [0, 1)."""
    if int(n) < 2 or int(n) % 2:
        raise ValueError(f"phases = {n!r} must be an even number >= 2")
    return (np.arange(int(n)) + 0.5) / int(n)


class PhaseSampler:
    """The phase means of an engine loop; a subclass gives ``e_n_values(params, phases)``.

    ``e_n_values`` returns ``(e_N of each phase, the largest relative change of the effective mass
    over a drop's contact)``; ``damping(params)`` and ``with_damping(params, b)`` read and set the
    engine's damping (``b`` >= 0, the engine's own unit); ``check_start(params)`` refuses a start
    the loop cannot solve from.  ``engine`` names the engine in notes, ``damping_name`` its
    damping parameter.
    """

    engine = ""
    damping_name = ""
    drops = 0

    def e_n_values(self, params, phases):  # pragma: no cover - every loop has its own
        """``(e_N of each phase, the effective mass's relative change over a drop)``."""
        raise NotImplementedError

    def damping(self, params) -> float:
        """The damping (>= 0) of ``params``."""
        return float(params[1])

    def with_damping(self, params, b) -> tuple:
        """``params`` with the damping ``b``."""
        return (float(params[0]), float(b))

    def check_start(self, params) -> tuple:
        """``params`` as a start of the secant; ValueError where the loop cannot start there."""
        start = (float(params[0]), float(params[1]))
        if not (start[0] > 0.0 and start[1] >= 0.0):
            raise ValueError(f"params = {start!r}: the engine loop needs a stiffness > 0 and a damping >= 0")
        return start

    def phase_mean(self, params, phases=None):
        """``PhaseMean`` of the pair's e_N with ``params`` at ``phases`` midpoint phases.

        A drop that touched and did not come back through the surface within its second is
        captured, e_N = 0, as a user measures it (so is a mechanism that fell over on the pair); a
        drop that never touched makes the mean NaN: ``failed`` counts them.
        """
        phases = PHASES if phases is None else int(phases)
        values, change = self.e_n_values(params, phase_grid(phases))
        failed = int(np.sum(~np.isfinite(values)))
        if failed:
            return PhaseMean(math.nan, math.nan, math.nan, math.nan, int(phases), values, change, failed)
        half = phase_mean_error(values)
        return PhaseMean(float(values.mean()), float(values.min()), float(values.max()), float(half),
                         int(phases), values, float(change))  # fmt: skip

    def converged_mean(self, params, phases=PHASES, tol=PHASE_TOL):
        """``phase_mean`` with N doubled from ``phases`` until its error estimate is within ``tol``."""
        n = int(phases)
        while True:
            pm = self.phase_mean(params, n)
            if not math.isfinite(pm.mean) or pm.error <= tol or n >= MAX_PHASES:
                return pm
            n *= 2


def _with_gap_sensor(model, pair):
    """The model (path or MJCF text) compiled with a geometry-distance sensor on the pair, last."""
    mj = mujoco_module()
    text = str(model)
    spec = mj.MjSpec.from_string(text) if text.lstrip().startswith("<") else mj.MjSpec.from_file(text)
    spec.add_sensor(type=mj.mjtSensor.mjSENS_GEOMDIST, objtype=mj.mjtObj.mjOBJ_GEOM, objname=pair[0],
                    reftype=mj.mjtObj.mjOBJ_GEOM, refname=pair[1], cutoff=1.0)  # fmt: skip
    try:
        return spec.compile()
    except ValueError as err:
        raise ValueError(
            f"model = {text[:80]!r}: MuJoCo cannot load it: {' '.join(str(err).split())}"
        ) from None


def _pair_rows(m, pair):
    g1, g2 = (geom_id(m, name) for name in pair)
    rows = [i for i in range(m.npair) if {int(m.pair_geom1[i]), int(m.pair_geom2[i])} == {g1, g2}]
    if not rows:
        raise ValueError(
            f"the engine loop needs a <pair> of {pair[0]!r} and {pair[1]!r} in the model "
            "(the file tune writes has one)"
        )
    return rows


class DropLoop(PhaseSampler):
    """A loop that drops the model one phase at a time: a subclass gives ``drop(params, phase, mass)``.

    ``drop`` returns ``(e_N, the effective mass's relative change)`` of one drop (the change only
    where ``mass`` is asked, NaN otherwise); ``read_drop`` makes both from its gap samples.
    """

    speed = math.nan  # the contact point's approach speed, m/s (set by the subclass)

    def drop(self, params, phase, mass=False) -> tuple[float, float]:  # pragma: no cover
        """``(e_N, m_eff's relative change)`` of the drop touching down at ``phase``."""
        raise NotImplementedError

    def read_drop(self, gaps, inverse_masses, h) -> tuple[float, float]:
        """``(e_N, m_eff's relative change)`` from a drop's gaps at step ``h`` (0 when captured)."""
        self.drops += 1
        inv = inverse_masses
        change = (max(inv) - min(inv)) / min(inv) if len(inv) > 1 else math.nan
        speed, _ = rebound_speed(np.arange(len(gaps)) * h, gaps)
        if math.isfinite(speed):
            return speed / self.speed, change
        return (0.0 if min(gaps) < 0.0 else math.nan), change

    def e_n_values(self, params, phases):
        """``(e_N of each phase, m_eff's relative change over the drop at phase 1/2)``."""
        _, change = self.drop(params, 0.5, mass=True)
        return np.array([self.drop(params, ph)[0] for ph in phases]), change

    def values_at(self, params, phases) -> np.ndarray:
        """e_N of each of ``phases`` (any phases in [0, 1); a captured drop is 0)."""
        return np.array([self.drop(params, ph)[0] for ph in phases])


class MujocoLoop(PhaseSampler):
    """The user's tuned MJCF loaded once in MuJoCo, dropped at many phases with any pair solref.

    Parameters
    ----------
    model : the tuned MJCF (path or string) with a ``<pair>`` of the two geometries.
    pair : (geometry 1, geometry 2).
    qpos, qvel : the touchdown configuration and joint velocity.
    timestep : the engine's step, s (default the model's).
    forces : {body: (fx, fy, fz)} constant forces, N, world axes.
    edit : a callable ``edit(MjModel)`` applied once after loading (``explain`` switches parts off).
    """

    def __init__(self, model, pair, qpos, qvel, *, timestep=None, forces=None, edit=None):
        self.source = model
        self.pair = tuple(pair)
        self.model = _with_gap_sensor(model, self.pair)
        if edit is not None:
            edit(self.model)
        self.rows = _pair_rows(self.model, self.pair)
        self.sensor = int(self.model.sensor_adr[self.model.nsensor - 1])
        self.qpos = np.asarray(qpos, dtype=float)
        self.qvel = np.asarray(qvel, dtype=float)
        self.timestep = float(self.model.opt.timestep) if timestep is None else float(timestep)
        self.forces = dict(forces or {})
        self.solref = tuple(float(x) for x in self.model.pair_solref[self.rows[0]])
        self.drops = 0

    engine = "MuJoCo"
    damping_name = "solref[1]"

    def drops_at(self, solref, phases):
        """The ``MechanismDrop`` of each phase with the pair's ``solref`` (``mujoco_drop``, one by one)."""
        self.model.pair_solref[self.rows] = np.asarray(solref, dtype=float)
        out = []
        for phase in phases:
            out.append(mujoco_drop(self.model, self.pair, self.qpos, self.qvel, timestep=self.timestep,
                                   forces=self.forces, phase=float(phase)))  # fmt: skip
        self.drops += len(out)
        return out

    def values_at(self, solref, phases) -> np.ndarray:
        """e_N of each of ``phases`` (``drops_at``, one by one; a captured drop is 0)."""
        return np.array([d.e_n if math.isfinite(d.e_n) else 0.0 for d in self.drops_at(solref, phases)])

    def e_n_at(self, solref, phases):
        """``(e_N of each phase, the drop at phase 1/2)`` with ``solref``: one ``rollout`` of all phases.

        The drop at phase 1/2 (``mujoco_drop``) sizes the rollout and gives the effective mass's
        change over the contact.  Each drop's gap is the model's geometry-distance sensor, sampled
        at every step's start as ``mujoco_drop`` samples it, and read the same way
        (``crossing.rebound_speed``).  A phase whose gap has not come back within the rollout's
        steps is run by ``mujoco_drop`` (up to its second), so that it is counted as captured only
        when it is.  NaN: never touched.
        """
        mj = mujoco_module()
        from mujoco import rollout

        self.model.pair_solref[self.rows] = np.asarray(solref, dtype=float)
        self.model.opt.timestep = self.timestep
        g1, g2 = (geom_id(self.model, name) for name in self.pair)
        probe = mujoco_drop(self.model, self.pair, self.qpos, self.qvel, forces=self.forces, phase=0.5)
        nstep = (
            2 * int(round(probe.contact_time / self.timestep if math.isfinite(probe.contact_time) else 0))
            + 20
        )
        states = []
        spec = mj.mjtState.mjSTATE_FULLPHYSICS
        td = touchdown(self.model, g1, g2, self.qpos, self.qvel, self.forces)
        speed0 = td.speed
        for phase in phases:
            d = start_state(self.model, td, float(phase))
            state = np.empty(mj.mj_stateSize(self.model, spec))
            mj.mj_getState(self.model, d, state, spec)
            states.append(state)
        extra = {}
        if self.forces:  # constant forces ride on xfrc_applied, the rollout's "control"
            extra = {"control": td.xfrc.ravel()[None, None, :],
                     "control_spec": mj.mjtState.mjSTATE_XFRC_APPLIED}  # fmt: skip
        datas = [mj.MjData(self.model) for _ in range(ROLLOUT_THREADS)]
        _, sensors = rollout.rollout(self.model, datas, np.array(states), nstep=nstep, **extra)
        t = np.arange(nstep) * self.timestep
        out = np.empty(len(states))
        for i, phase in enumerate(phases):
            gaps = sensors[i, :, self.sensor]
            speed, _ = rebound_speed(t, gaps)
            if math.isfinite(speed):
                out[i] = speed / speed0
                continue
            slow = mujoco_drop(
                self.model, self.pair, self.qpos, self.qvel, forces=self.forces, phase=float(phase)
            )
            out[i] = slow.e_n if math.isfinite(slow.e_n) or not slow.steps else 0.0
        self.drops += len(states)
        return out, probe

    def e_n_values(self, params, phases):
        """``(e_N of each phase, the effective mass's change over the drop at phase 1/2)``."""
        values, probe = self.e_n_at(params, phases)
        return values, (probe.mass_change if probe.steps else math.nan)

    def damping(self, params) -> float:
        """The damping ``b`` >= 0 of a direct-form solref ``(-k, -b)``."""
        return -float(params[1])

    def with_damping(self, params, b) -> tuple:
        """The solref with damping ``b``."""
        return (float(params[0]), -float(b))

    def check_start(self, params) -> tuple:
        """The solref; ValueError unless it is the direct form (both slots <= 0)."""
        start = (float(params[0]), float(params[1]))
        if not (start[0] < 0.0 and start[1] <= 0.0):
            raise ValueError(f"solref = {start!r}: the engine loop solves the direct form (both slots <= 0)")
        return start


@dataclass(frozen=True)
class LoopAnswer:
    """The damping solved on the engine's drops.

    ``solref`` the answer; ``delivered`` its ``PhaseMean``; ``reduced_solref`` and ``reduced`` the
    reduced model's answer and what the engine delivers with it; ``status`` "ok", "unreachable"
    (no damping >= 0 reaches the target: the nearest is ``delivered``), "not_converged" or
    "failed" (drops without a rebound); ``iterations`` phase means of the secant; ``drops`` run;
    ``seconds`` of CPU.
    """

    solref: tuple
    delivered: PhaseMean
    reduced_solref: tuple
    reduced: PhaseMean
    status: str
    iterations: int
    drops: int
    seconds: float


def solve_damping(loop, target, start, *, phases=PHASES, tol=PHASE_TOL, solve_tol=SOLVE_TOL):
    """``LoopAnswer``: the pair's damping whose engine phase mean is ``target``.

    Parameters
    ----------
    loop : a ``PhaseSampler`` (``MujocoLoop``, ``pybullet_loop.PybulletLoop``,
        ``drake_loop.DrakeLoop``).
    target : e_N in (0, 1).
    start : the reduced model's parameters in the loop's form (MuJoCo: the solref, direct form,
        both slots <= 0; PyBullet: each link's contactStiffness and contactDamping; Drake: each
        geometry's point_contact_stiffness and hunt_crossley_dissipation).
    phases, tol : the phase sampling (``PhaseSampler.converged_mean``).
    solve_tol : |phase mean - target| at which the secant stops.
    """
    clock = time.process_time()
    start = loop.check_start(start)
    reduced = loop.converged_mean(start, phases, tol)
    if not math.isfinite(reduced.mean):
        return LoopAnswer(start, reduced, start, reduced, "failed", 0, loop.drops,
                          time.process_time() - clock)  # fmt: skip
    n = reduced.phases
    means = {loop.damping(start): reduced}

    def e_n_of(b):
        if b not in means:
            means[b] = loop.phase_mean(loop.with_damping(start, b), n)
        return means[b].mean

    ref = refine(e_n_of, target, loop.damping(start), solve_tol, refine_tol=solve_tol)
    b = ref.damping if math.isfinite(ref.damping) else 0.0
    delivered = loop.converged_mean(loop.with_damping(start, b), n, tol)
    if delivered.phases > n and ref.status in ("ok", "unchanged"):  # the root needs more phases
        n = delivered.phases
        means = {}
        ref = refine(e_n_of, target, b, solve_tol, refine_tol=solve_tol)
        b = ref.damping if math.isfinite(ref.damping) else 0.0
        delivered = loop.converged_mean(loop.with_damping(start, b), n, tol)
    status = "ok" if ref.status == "unchanged" else ref.status  # the start already delivered
    if status == "ok" and not abs(delivered.mean - target) <= solve_tol + tol:
        status = "not_converged"
    return LoopAnswer(loop.with_damping(start, b), delivered, start, reduced, status, len(means),
                      loop.drops, time.process_time() - clock)  # fmt: skip


@dataclass(frozen=True)
class Part:
    """A part of the whole model the reduced model leaves out, and how to switch it off in MuJoCo."""

    name: str
    present: Callable[[Any, list], str]  # (MjModel, pair rows) -> a description, "" when absent
    switch_off: Callable[[Any, list], None]  # (MjModel, pair rows), in place


def _damping(m, rows):
    on = np.flatnonzero(np.asarray(m.dof_damping) > 0.0)
    return f"{on.size} joints, up to {float(np.max(m.dof_damping)):.3g} N s/m" if on.size else ""


def _friction(m, rows):
    dims = sorted({int(m.pair_dim[r]) for r in rows})
    return f"condim {dims[0]}" if dims[0] > 1 else ""


def _limits(m, rows):
    n = int(np.sum(np.asarray(m.jnt_limited) > 0))
    return f"{n} limited joints" if n else ""


def _actuators(m, rows):
    servo = int(np.sum(np.any(np.asarray(m.actuator_biasprm) != 0.0, axis=1))) if m.nu else 0
    return f"{servo} of {m.nu} actuators with gains at zero control" if servo else ""


def _springs(m, rows):
    n = int(np.sum(np.asarray(m.jnt_stiffness) > 0.0))
    return f"{n} joints with springs" if n else ""


def _others(m, rows):
    n = int(np.sum((np.asarray(m.geom_contype) | np.asarray(m.geom_conaffinity)) > 0))
    extra = m.npair - len(rows)
    return f"{n} colliding geometries, {extra} other <pair>s" if n or extra else ""


def _set(name, value):
    def off(m, rows):
        getattr(m, name)[:] = value

    return off


def _both(first, second):
    def off(m, rows):
        first(m, rows)
        second(m, rows)

    return off


PARTS = (
    Part("joint damping", _damping, _set("dof_damping", 0.0)),
    Part("friction and the cone", _friction, lambda m, rows: m.pair_dim.__setitem__(rows, 1)),
    Part("joint limits", _limits, _set("jnt_limited", 0)),
    Part("actuators", _actuators, _both(_set("actuator_biasprm", 0.0), _set("actuator_gainprm", 0.0))),
    Part("joint springs", _springs, _set("jnt_stiffness", 0.0)),
    Part("other contacts", _others, _both(_set("geom_contype", 0), _set("geom_conaffinity", 0))),
)


@dataclass(frozen=True)
class Share:
    """A part's share of the gap.

    ``part``: what the model has of it (``present``), and ``share``, the phase mean at the
    reduced model's answer with it minus without it (NaN where switching it off loses the rebound).
    """

    part: str
    present: str
    share: float


def explain(loop, solref, full):
    """The ``Share`` of each of ``PARTS`` ``loop``'s model has, at the reduced model's ``solref``.

    ``full`` is the ``PhaseMean`` with everything on (its phase count is used for each part); each
    part is switched off in a fresh load of ``loop``'s model, dropped from the same touchdown.
    The parts' shares need not add up to the whole gap: the rest is the effective mass moving over
    the contact, the step and the parts' interactions.
    """
    out = []
    for part in PARTS:
        present = part.present(loop.model, loop.rows)
        if not present:
            continue
        off = MujocoLoop(loop.source, loop.pair, loop.qpos, loop.qvel, timestep=loop.timestep,
                         forces=loop.forces, edit=lambda m, p=part: p.switch_off(m, loop.rows))  # fmt: skip
        pm = off.phase_mean(solref, full.phases)
        out.append(Share(part.name, present, float(full.mean - pm.mean)))
    return tuple(out)


def base_of(model, geom):
    """How the body of ``geom`` hangs from the world: "fixed", "floating (free joint)" or its root joints."""
    m = load_model(model)
    root = int(m.body_rootid[int(m.geom_bodyid[int(geom)])])
    if root == 0:
        return "fixed (the world)"
    n = int(m.body_jntnum[root])
    if n == 0:
        return "fixed (the root body is welded to the world)"
    kinds = [int(m.jnt_type[int(m.body_jntadr[root]) + i]) for i in range(n)]
    if 0 in kinds:  # mjJNT_FREE
        return "floating (free joint)"
    if 2 in kinds:  # mjJNT_SLIDE: a planar robot's root
        return f"floating on {n} root joints (slide and hinge)"
    return f"fixed (its root body turns on {n} hinge or ball joint(s) to the world)"


def loop_notes(answer, shares, target, timestep, bases, engine="MuJoCo", damping_name="solref[1]"):
    """Text lines of an engine loop's answer and of what the reduced model leaves out.

    ``answer.solref`` is the loop's parameters (``solve_damping``'s ``start`` form): slot 1 is
    ``damping_name``'s value.
    """
    d, r = answer.delivered, answer.reduced
    lines = [
        f"engine loop ({engine}, the whole model at its step {timestep:g} s, {d.phases} touchdown phases): "
        f"{answer.status}; {damping_name} = {answer.solref[1]:.9g}; mean e_N {d.mean:.6g} (sampling error "
        f"estimate {d.error:.2g}), one drop {d.minimum:.6g} to {d.maximum:.6g}; {answer.iterations} phase "
        f"means, {answer.drops} drops, {answer.seconds:.1f} s of CPU",
        f"reduced model (m_eff, free load, the one-contact map) {damping_name} = "
        f"{answer.reduced_solref[1]:.9g} for {target:g}: {engine} delivers {r.mean:.6g} with it "
        f"(gap {r.mean - target:+.4f})",
        f"base: {' / '.join(dict.fromkeys(bases))}",
    ]
    if shares:
        parts = "; ".join(f"{s.part} ({s.present}) {s.share:+.4f}" for s in shares)
        rest = (r.mean - target) - sum(s.share for s in shares)
        lines.append(
            f"what the reduced model leaves out (phase mean with the part minus without): {parts}; "
            f"the rest {rest:+.4f} (the effective mass moving by up to {r.mass_change:.3g} over the "
            "contact, the parts' interactions)"
        )
    if answer.status == "unreachable":
        lines.append(f"no damping >= 0 reaches e_N {target:g} in {engine}: the nearest mean is {d.mean:.6g}")
    elif answer.status != "ok":
        lines.append(f"the engine loop did not converge ({answer.status}): the reduced model's answer kept")
    return lines
