"""The reduced model's answer per engine: the contact's law (or its step map) at m_eff and the load.

Each engine's ``solve(contact, target, stiffness, impedance, timestep, discrete) -> (parameters,
notes, details, step)`` (its ``Tuner``, ``tuners``): MuJoCo's law corrected for its own contact
row (``mujoco_row``), Drake's and PyBullet's blocks of the front door, and at the engine's step the
phase-mean inverse of its step map (``discrete``) where the continuous answer misses the target
by more than ``DISCRETE_TOL``.  Nothing here runs the engine.
"""

import math
from dataclasses import replace

from contactalpha.adapters.registry import adapter
from contactalpha.parameters.block_scene import BlockScene
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.stepping.registry import stepper
from contactalpha.validation import check_range

from .discrete import ENGINE_STEPS, step_answer
from .inputs import check_step_resolves
from .mujoco_row import DISCRETE_TOL, current_stiffness, discrete_answer, law_scene, mujoco_tuning


def mujoco_solve(contact, target, stiffness, impedance, timestep, discrete):
    """MuJoCo's solref and solimp: its law at the contact row's effective impedance, then its step."""
    k = current_stiffness(contact) if stiffness is None else stiffness
    t = mujoco_tuning(contact, target, k, impedance)
    h = contact.engine_row["timestep"] if timestep is None else float(timestep)
    named = "the model's timestep" if timestep is None else "timestep"
    check_step_resolves(h, contact.effective_mass, k, named)
    step = discrete_answer(contact, t, target, h) if discrete is not False else None
    row = contact.engine_row
    params = {"solref": t.solref, "solimp": t.solimp, "condim": (row["condim"],),
              "friction": row["friction"], "margin": (row["geom_margin"],),
              "gap": (row["geom_gap"],)}  # fmt: skip
    notes = [
        f"stiffness {k:.9g} N/m along the normal" + (" (the model's own)" if stiffness is None else ""),
        f"MuJoCo's row: diagA = {row['diagA']:.9g} where J M^-1 J^T = {1 / contact.effective_mass:.9g}; "
        f"solimp d = {t.impedance:.6g} acts as d_e = {t.effective_impedance:.9g}",
        f"law mujoco_soft at d_e: zeta = {t.zeta:.12g}, xi = {t.xi:.9g}",
        f"free-body mapping (exact only where diagA = J M^-1 J^T): solref = "
        f"({t.free_body['solref'][0]:.9g}, {t.free_body['solref'][1]:.9g})",
    ]
    if step is not None:
        use, lines = _step_notes("MuJoCo", step, target, discrete, f"solref[1] = {-step.inverse.damping:.9g}")
        notes += lines
        if use:
            params["solref"] = (t.solref[0], -step.inverse.damping)
    elif discrete is not False:
        notes.append(
            "MuJoCo's step map does not apply (no pressing load, or its integrator): continuous answer"
        )
    if row["condim"] > 1:
        pyramid = (f"; the {row['cone']} cone's {row['rows']} edge rows act on the normal as one row "
                   f"with their R over {row['rows']}" if row.get("rows", 1) > 1 else "")  # fmt: skip
        notes.append(
            f"condim {row['condim']}{pyramid}: exact for a contact whose tangential motion is decoupled "
            "from the normal and that does not slide; friction coupled to the normal (a contact point "
            "off the line of the normal's action) changes e_N: check with a drop"
        )
    return params, notes, (t if step is None else replace(t, discrete=step)), step


def _step_notes(engine, step, target, discrete, written):
    """``(use, notes)``: whether the step's phase-mean inverse replaces the continuous answer.

    It does where the continuous answer's phase mean at the step misses ``target`` by more than
    ``DISCRETE_TOL`` (``discrete`` None), always (True), and only where the inverse reached it.
    """
    st, inv = step.continuous, step.inverse
    notes = [
        f"at {engine}'s step {step.timestep:g} s the law's answer delivers a phase mean {st.mean:.6g} "
        f"(one drop: {st.minimum:.6g} to {st.maximum:.6g}; {st.steps_min}-{st.steps_max} steps)"
    ]
    use = _wants_step(step, target, discrete)
    if use and inv.status == "ok":
        notes.append(
            f"discrete answer (phase-mean inverse of {engine}'s step at m_eff): {written}; "
            f"one drop sees {inv.stats.minimum:.6g} to {inv.stats.maximum:.6g}"
        )
        return True, notes
    if use:
        notes.append(
            f"no damping reaches e_N {target} at this step ({inv.status}; nearest phase mean "
            f"{inv.nearest:.6g}); largest step that reaches it: {inv.timestep_reachable:.3g} s"
        )
    return False, notes


def _wants_step(step, target, discrete):
    """Whether the step's answer is wanted: always (``discrete`` True), or where the law's misses."""
    return discrete is True or abs(step.continuous.mean - target) > DISCRETE_TOL


def unreachable(step, target, discrete):
    """Why no damping reaches the target at the step where its answer is wanted (one line), else ""."""
    if step is None or not _wants_step(step, target, discrete) or step.inverse.status == "ok":
        return ""
    inv = step.inverse
    return (f"no damping reaches e_N {target} at {step.engine}'s step {step.timestep:g} s ({inv.status}; "
            f"nearest phase mean {inv.nearest:.6g}); largest step that reaches it: "
            f"{inv.timestep_reachable:.3g} s")  # fmt: skip


def _front_door(contact, target, stiffness, engine):
    """The engine's block of ``contact_parameters`` at the contact's m_eff, load and speed."""
    scene = law_scene(contact, _need(stiffness, engine))
    cp = contact_parameters(
        e_N=target, mass=scene.mass, stiffness=scene.stiffness, approach_speed=scene.approach_speed,
        accel=scene.accel, engine=engine,
    )  # fmt: skip
    return cp, cp.engines[engine]


def drake_solve(contact, target, stiffness, impedance, timestep, discrete):
    """Drake's point-contact stiffness and dissipation: its law at m_eff, then its discrete plant's step."""
    cp, params = _front_door(contact, target, stiffness, "drake")
    notes = [f"law {cp.law}: alpha = {cp.damping:.12g} at xi = {cp.xi:.9g}; each geometry gets 2k "
             "and d (Drake combines k1 k2/(k1 + k2), (k2 d1 + k1 d2)/(k1 + k2))"]  # fmt: skip
    return _engine_step(contact, "drake", cp, params, notes, target, timestep, discrete)


def _engine_step(contact, engine, cp, params, notes, target, timestep, discrete):
    """The step's answer for Drake's discrete plant or PyBullet: its map at the contact's m_eff and load.

    ``timestep`` None is the engine's ``discrete.ENGINE_STEPS`` default (None for Drake: its
    continuous plant, no step).  Returns ``(params, notes, cp, step)`` with the block rebuilt from the
    inverse's damping where ``_step_notes`` uses it.
    """
    es = ENGINE_STEPS[engine]
    h = es.default_step if timestep is None else float(timestep)
    if h is None or discrete is False:
        return params, notes, cp, None
    check_step_resolves(h, contact.effective_mass, float(params["pair_stiffness"]))
    if contact.accel <= 0.0:
        notes.append(f"{engine}'s step map needs a pressing load: the continuous answer is kept")
        return params, notes, cp, None
    s = stepper(engine)
    step = step_answer(engine, es.parameters(params, contact), contact, target, h)
    use, lines = _step_notes(
        engine, step, target, discrete, f"{es.damping} = {step.inverse.damping:.9g} each"
    )
    lines.append(es.note)
    if use:
        assert s.law_damping is not None  # every stepper tune reaches has its law's damping
        zeta = float(s.law_damping(step.inverse.p, contact.approach_speed))
        a = adapter(engine)
        settings = replace(a.settings, **{s.step_setting: h})
        k = float(params["pair_stiffness"])
        scene = BlockScene(contact.effective_mass, k, contact.approach_speed, None)
        params = a.parameters(zeta, scene, settings)
    return params, notes + lines, cp, step


def pybullet_solve(contact, target, stiffness, impedance, timestep, discrete):
    """PyBullet's contactStiffness and contactDamping: its law at m_eff, then its step."""
    cp, params = _front_door(contact, target, stiffness, "pybullet")
    notes = [f"law {cp.law}: zeta = {cp.damping:.12g} at xi = {cp.xi:.9g} (continuous law at m_eff)"]
    return _engine_step(contact, "pybullet", cp, params, notes, target, timestep, discrete)


def _need(stiffness, engine):
    if stiffness is None:
        raise ValueError(f"engine {engine!r} needs the contact stiffness: give stiffness (N/m)")
    return float(check_range("stiffness", stiffness, 0.0, math.inf, lo_open=True, hi_open=True))
