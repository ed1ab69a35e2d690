"""``tune`` at the engines' coarse steps for a mechanism: Drake's discrete plant and PyBullet.

The case: ``arm.urdf``, a hinged arm falling horizontally onto the floor, its tip sphere touching
down at 0.8 m/s under gravity (m_eff and the load by hand below).  ``tune`` gives the phase-mean
inverse of the engine's step map at the contact's m_eff and load; the engine's own drops of the
tuned model (Drake: the tuned URDF; PyBullet: the URDF with the written script's
``changeDynamics``) at 16 or 32 touchdown phases follow the map phase by phase, and their mean is
the target.  The engines run the mechanism, not the map's free body.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from contactalpha.mechanism.discrete import COMPOUND_BREAKING, drake_p, pybullet_p, step_answer
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.stepping import drake_map, kernels, pybullet_map
from contactalpha.stepping.drop import run_drop

ARM = Path(__file__).resolve().parents[1] / "data" / "models" / "arm.urdf"
PAIR = ("floor", "tip")
QVEL = (1.6,)  # rad/s: the tip closes at 0.8 m/s
# The arm's numbers (arm.urdf): mass, COM distance from the hinge, inertia about the COM, tip.
MASS, D, IYY, L, G = 1.5, 1.0 / 3.0, 0.04, 0.5, 9.81
I_HINGE = IYY + MASS * D * D
M_EFF = I_HINGE / L**2
ACCEL = L * MASS * G * D / I_HINGE
SPEED = 0.8


class _Contact:
    """The arm's contact as the maps read it (no engine)."""

    effective_mass = M_EFF
    accel = ACCEL
    approach_speed = SPEED


def _stiffness(steps, h):
    """k = m_eff (pi / (steps h))^2: an undamped contact of ``steps`` steps."""
    return M_EFF * (math.pi / (steps * h)) ** 2


@pytest.mark.parametrize("engine", ["drake", "pybullet"])
def test_mechanism_step_answer_is_the_front_doors_at_m_eff(engine):
    """The mechanism's discrete answer is the front door's stepped answer for a free body of m_eff.

    Independent path: ``contact_parameters(..., timestep=h)`` (parameters.at_step); PyBullet's needs a
    sphere radius, so that side is compared at the same breaking threshold through the map.
    """
    h = {"drake": 1e-3, "pybullet": pybullet_map.TIMESTEP}[engine]
    k = _stiffness(16, h)
    cp = contact_parameters(e_N=0.6, mass=M_EFF, stiffness=k, approach_speed=SPEED, accel=ACCEL,
                            engine=engine)  # fmt: skip
    p = {"drake": drake_p, "pybullet": pybullet_p}[engine](cp.engines[engine], _Contact)
    step = step_answer(engine, p, _Contact, 0.6, h)
    assert step.inverse.status == "ok"
    assert step.inverse.stats.mean == pytest.approx(0.6, abs=1e-6)
    assert abs(step.continuous.mean - 0.6) > 1e-2  # the step matters here
    if engine == "drake":
        front = contact_parameters(e_N=0.6, mass=M_EFF, stiffness=k, approach_speed=SPEED, accel=ACCEL,
                                   engine="drake", timestep=h)  # fmt: skip
        assert step.inverse.damping == pytest.approx(front.stepped.damping, rel=1e-9)
        assert p[drake_map.MASS] == M_EFF
    else:
        assert p[pybullet_map.BREAKING] == COMPOUND_BREAKING and p[pybullet_map.MASS] == M_EFF
        # the phase mean of the inverse's damping, drop by drop through the generic loop
        phases = (np.arange(400) + 0.5) / 400
        e = [run_drop(kernels.PYBULLET, step.inverse.p, h, f, SPEED, ACCEL, 10**6)[0] for f in phases]
        assert np.mean(e) == pytest.approx(0.6, abs=2e-4)


def test_tune_pybullet_writes_the_discrete_answer(mujoco, tmp_path):
    """PyBullet's default step: the script carries the inverse's damping; discrete=False the law's."""
    h = pybullet_map.TIMESTEP
    from contactalpha.mechanism.tune import tune

    out = tmp_path / "arm_tuned.py"
    got = tune(ARM, PAIR, 0.6, engine="pybullet", qvel=QVEL, stiffness=_stiffness(24, h), output=out)
    assert got.timestep == h and got.discrete is not None
    assert got.contact.effective_mass == pytest.approx(M_EFF, rel=1e-12)
    assert got.contact.accel == pytest.approx(ACCEL, rel=1e-12)
    assert got.parameters["contactDamping"] == pytest.approx(got.discrete.inverse.damping, rel=1e-12)
    assert any("discrete answer" in n for n in got.notes)
    text = out.read_text()
    assert "LINKS = ('ground', 'arm')" in text and repr(got.parameters["contactDamping"]) in text
    law = tune(ARM, PAIR, 0.6, engine="pybullet", qvel=QVEL, stiffness=_stiffness(24, h), discrete=False)
    assert law.discrete is None
    assert law.parameters["contactDamping"] != pytest.approx(got.parameters["contactDamping"], rel=1e-3)


def test_tune_pybullet_out_of_reach_keeps_the_law(mujoco, tmp_path):
    """e_N 0.9 at 1/240 s: no damping reaches it (zero damping gives a phase mean of 0.66): tune
    writes nothing (reached False); with force_write the continuous answer is written and the notes say so."""
    from contactalpha.mechanism.tune import tune

    k = _stiffness(24, pybullet_map.TIMESTEP)
    miss = tune(ARM, PAIR, 0.9, engine="pybullet", qvel=QVEL, stiffness=k, output=tmp_path / "t.py")
    assert miss.output is None and not (tmp_path / "t.py").exists()
    assert "no damping reaches e_N 0.9 at pybullet's step" in miss.unreachable
    got = tune(ARM, PAIR, 0.9, engine="pybullet", qvel=QVEL, stiffness=k, output=tmp_path / "t.py",
               force_write=True)  # fmt: skip
    assert got.output.exists() and not got.reached and got.discrete.inverse.status == "unreachable"
    assert got.discrete.inverse.nearest < 0.7
    law = tune(ARM, PAIR, 0.9, engine="pybullet", qvel=QVEL, stiffness=_stiffness(24, pybullet_map.TIMESTEP),
               discrete=False)  # fmt: skip
    assert got.parameters == law.parameters
    assert any("no damping reaches e_N 0.9" in n for n in got.notes)


def test_cli_tune_pybullet_at_a_step(mujoco, tmp_path, capsys):
    from contactalpha.cli import main

    out = tmp_path / "arm.py"
    # The reduced model's choice of map (the engine loop would end both at one answer).
    argv = ["tune", str(ARM), "--pair", *PAIR, "--e-n", "0.6", "--qvel", "1.6", "--engine", "pybullet",
            "--stiffness", "3e4", "--timestep", "1e-3", "-o", str(out), "--no-engine-loop"]  # fmt: skip
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "pybullet's step 0.001 s" in text and out.is_file()
    stepped = float(text.split("pybullet.contactDamping")[1].split()[0])
    assert main([*argv, "--discrete", "never"]) == 0
    law = float(capsys.readouterr().out.split("pybullet.contactDamping")[1].split()[0])
    assert law != pytest.approx(stepped, rel=1e-3)
    with pytest.raises(SystemExit) as stop:
        main([*argv, "--discrete", "sometimes"])
    assert stop.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def _phases(n):
    return (np.arange(n) + 0.5) / n


@pytest.mark.parametrize(("target", "steps"), [(0.3, 16), (0.6, 16), (0.9, 128)])
def test_drake_discrete_plant_delivers_the_phase_mean(pydrake, tmp_path, target, steps):
    """Drake's discrete plant (lagged, 1 ms), 16 phases; e_N 0.9 needs about 100 steps per contact."""
    import warnings

    from contactalpha.mechanism import MassChangeWarning, tune
    from contactalpha.mechanism.drake_model import drake_drop

    h = 1e-3
    out = tmp_path / "arm_tuned.urdf"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MassChangeWarning)  # 128 steps: m_eff moves by 1.3 %
        got = tune(ARM, PAIR, target, engine="drake", qvel=QVEL, stiffness=_stiffness(steps, h), output=out,
                   timestep=h, check=True)  # fmt: skip
    assert got.mass_change < 0.02
    inv = got.discrete.inverse
    assert inv.status == "ok"
    assert got.parameters["hunt_crossley_dissipation"] == pytest.approx(inv.damping, rel=1e-12)
    c = got.contact
    engine = np.array([drake_drop(out, PAIR, c.qpos, c.qvel, time_step=h, phase=f).e_n for f in _phases(16)])
    by_map = [run_drop(kernels.DRAKE, inv.p, h, f, SPEED, ACCEL, 10**6)[0] for f in _phases(16)]
    # measured 4e-6 at 16 steps; 2.5e-4 at 128 (the arm turns by 0.1 rad over that contact)
    assert np.max(np.abs(engine - by_map)) < 5e-4
    assert engine.mean() == pytest.approx(target, abs=1e-3)
    assert inv.stats.minimum - 5e-4 <= engine.min() and engine.max() <= inv.stats.maximum + 5e-4
    at_zero = run_drop(kernels.DRAKE, inv.p, h, 0.0, SPEED, ACCEL, 10**6)[0]
    assert got.delivered == pytest.approx(at_zero, abs=5e-4)  # the check's drop starts at touchdown


@pytest.mark.parametrize("target", [0.3, 0.6])
def test_pybullet_runs_the_written_script(pybullet, mujoco, tmp_path, target):
    """PyBullet at 1/240 s, 24 steps per undamped contact: the URDF with the script ``tune`` wrote."""
    from contactalpha.mechanism.pybullet_model import pybullet_drop
    from contactalpha.mechanism.tune import tune

    h = pybullet_map.TIMESTEP
    out = tmp_path / "arm_tuned.py"
    got = tune(ARM, PAIR, target, engine="pybullet", qvel=QVEL, stiffness=_stiffness(24, h), output=out,
               check=True)  # fmt: skip
    inv = got.discrete.inverse
    assert inv.status == "ok" and math.isfinite(got.delivered)
    c = got.contact
    engine = np.array([
        pybullet_drop(ARM, PAIR, c.qpos, c.qvel, script=out, timestep=h, phase=f, speed=SPEED).e_n
        for f in _phases(32)
    ])  # fmt: skip
    by_map = [run_drop(kernels.PYBULLET, inv.p, h, f, SPEED, ACCEL, 10**6)[0] for f in _phases(32)]
    assert np.max(np.abs(engine - by_map)) < 1e-3  # measured 2.7e-4 at 0.6
    assert engine.mean() == pytest.approx(target, abs=1e-3)
    assert inv.stats.minimum - 1e-3 <= engine.min() and engine.max() <= inv.stats.maximum + 1e-3


def test_pybullet_row_uses_the_exact_effective_mass(pybullet):
    """PyBullet's own mass matrix and Jacobian give the m_eff the readers give (URDF inertias)."""
    pb = pybullet
    client = pb.connect(pb.DIRECT)
    try:
        flags = pb.URDF_USE_INERTIA_FROM_FILE
        body = pb.loadURDF(str(ARM), useFixedBase=True, flags=flags, physicsClientId=client)
        M = np.array(pb.calculateMassMatrix(body, [0.0], physicsClientId=client))
        # the tip's centre in the arm link's frame (PyBullet's localPosition)
        lin, _ = pb.calculateJacobian(body, 1, [L, 0.0, 0.0], [0.0], [0.0], [0.0], physicsClientId=client)
        J = np.array(lin)[2]
        assert 1.0 / (J @ np.linalg.solve(M, J)) == pytest.approx(M_EFF, rel=1e-12)
    finally:
        pb.disconnect(client)


def test_pybullet_compound_links_touch_only_when_penetrating(pybullet):
    """``COMPOUND_BREAKING``: URDF links get a manifold point below zero gap only (none at +1e-7 m)."""
    pb = pybullet
    client = pb.connect(pb.DIRECT)
    try:
        flags = pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_INERTIA_FROM_FILE
        body = pb.loadURDF(str(ARM), useFixedBase=True, flags=flags, physicsClientId=client)
        counts = []
        for gap in (1e-3, 1e-7, -1e-7):
            pb.resetJointState(body, 1, -math.asin(gap / L), physicsClientId=client)  # tip up by gap
            pb.performCollisionDetection(physicsClientId=client)
            counts.append(len(pb.getContactPoints(body, body, 0, 1, physicsClientId=client)))
        assert counts == [0, 0, 1]
    finally:
        pb.disconnect(client)


def test_drake_values_in_a_urdf_are_value_attributes(tmp_path):
    """Drake's URDF parser reads ``<drake:...>`` values from a ``value`` attribute (an SDF's from text)."""
    import xml.etree.ElementTree as ET

    from contactalpha.mechanism.write import DRAKE_NS, write_drake

    out = write_drake(ARM, tmp_path / "a.urdf", PAIR, {"hunt_crossley_dissipation": 0.25})
    root = ET.parse(out).getroot()
    for col in root.iter("collision"):
        props = col.find(f"{{{DRAKE_NS}}}proximity_properties")
        elem = props.find(f"{{{DRAKE_NS}}}hunt_crossley_dissipation")
        assert elem.get("value") == "0.25" and not (elem.text or "").strip()
        assert props.find(f"{{{DRAKE_NS}}}mu_dynamic").get("value") == "0"  # the file's own stay


def test_mujoco_phase_drop_follows_the_map_at_its_default_step(mujoco, tmp_path):
    """A free ball at MuJoCo's 2 ms step, 12 steps per contact, 8 phases: ``mujoco_drop(phase=)``
    starts on the free motion with semi-implicit Euler's stored velocity (half a step earlier),
    so it follows MuJoCo's map exactly.  With the velocity of half a step later it was 0.016 off.
    """
    from contactalpha.mechanism.mujoco_model import mujoco_drop
    from contactalpha.mechanism.tune import tune

    model = tmp_path / "ball.xml"
    model.write_text(
        '<mujoco><option timestep="0.002" integrator="Euler"/><worldbody>'
        '<geom name="floor" type="plane" size="1 1 0.1" condim="1"/>'
        '<body name="ball" pos="0 0 0.05"><freejoint/>'
        '<inertial pos="0 0 0" mass="0.5" diaginertia="0.0005 0.0005 0.0005"/>'
        '<geom name="b" type="sphere" size="0.05" condim="1"/></body></worldbody></mujoco>'
    )
    h, out = 0.002, tmp_path / "t.xml"
    k = 0.5 * (math.pi / (12 * h)) ** 2
    got = tune(model, ("floor", "b"), 0.6, qvel=(0, 0, -0.8, 0, 0, 0), stiffness=k,
               output=out, discrete=True)  # fmt: skip
    inv, c = got.discrete.inverse, got.contact
    engine = [mujoco_drop(out, ("floor", "b"), c.qpos, c.qvel, phase=f).e_n for f in _phases(8)]
    by_map = [run_drop(kernels.MUJOCO, inv.p, h, f, c.approach_speed, c.accel, 10**6)[0] for f in _phases(8)]
    assert np.max(np.abs(np.array(engine) - by_map)) < 1e-9


def test_pybullet_check_measures_the_leg_folding(pybullet, mujoco, tmp_path):
    """The leg over a 2 ms contact at a fine step: PyBullet's check reads J M^-1 J^T at every step in
    contact; m_eff moves by as much as in MuJoCo's drop of the same leg (1.5 %), above the warning."""
    import warnings

    from contactalpha.mechanism import MassChangeWarning, tune

    models = ARM.parent
    omega, h = 1571.0, 1e-5
    k = 0.7295062926358623 * omega**2
    kw = dict(qvel=(-0.8, 0.0, 0.0), stiffness=k, check=True, timestep=h)
    with pytest.warns(MassChangeWarning):
        bullet = tune(
            models / "leg.urdf", ("floor", "foot"), 0.6, engine="pybullet", output=tmp_path / "l.py", **kw
        )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MassChangeWarning)
        mj = tune(models / "leg.xml", ("floor", "foot"), 0.6, output=tmp_path / "l.xml", **kw)
    assert 0.01 < bullet.mass_change == pytest.approx(mj.mass_change, rel=0.1)
    # each with its step answer (200 steps per contact); the same miss from the folding, 0.008
    assert bullet.delivered == pytest.approx(mj.delivered, abs=3e-3)


def test_drake_check_reads_the_arm_mass_change(pydrake, tmp_path):
    """The arm over a 16 ms contact in Drake's discrete plant: m_eff moves by under 1 %, no warning."""
    import warnings

    from contactalpha.mechanism.tune import tune

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = tune(ARM, PAIR, 0.6, engine="drake", qvel=QVEL, stiffness=_stiffness(16, 1e-3), timestep=1e-3,
                   output=tmp_path / "a.urdf", check=True)  # fmt: skip
    # the tip turns by at most ~2 depth / L: m_eff = I / (L cos theta)^2 moves by ~theta^2
    assert 0.0 < got.mass_change < 1e-3
    assert got.drop.steps > 10


@pytest.mark.parametrize("approximation", ["similar", "tamsi"])
def test_drake_other_approximations_follow_the_same_map(pydrake, tmp_path, approximation):
    """``similar`` and ``tamsi`` solve the same frictionless impulse as ``lagged``: the tuned arm's drops
    at 8 phases follow the map as closely (TAMSI is deprecated in Drake: its warning is silenced)."""
    import warnings

    from contactalpha.mechanism.drake_model import drake_drop
    from contactalpha.mechanism.tune import tune

    h, out = 1e-3, tmp_path / "arm.urdf"
    got = tune(ARM, PAIR, 0.6, engine="drake", qvel=QVEL, stiffness=_stiffness(16, h), output=out, timestep=h)
    inv, c = got.discrete.inverse, got.contact
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        engine = [drake_drop(out, PAIR, c.qpos, c.qvel, time_step=h, phase=f, approximation=approximation).e_n
                  for f in _phases(8)]  # fmt: skip
    by_map = [run_drop(kernels.DRAKE, inv.p, h, f, SPEED, ACCEL, 10**6)[0] for f in _phases(8)]
    assert np.max(np.abs(np.array(engine) - by_map)) < 1e-4


def test_pybullet_check_applies_the_named_forces(pybullet, mujoco, tmp_path):
    """A 5 N push down on the arm's centre of mass raises the load to 15.9 m/s^2: the check and the
    drops apply it before every step (without it the same parameters give 0.55, not 0.40)."""
    from contactalpha.mechanism.pybullet_model import pybullet_drop
    from contactalpha.mechanism.tune import tune

    h, out, push = pybullet_map.TIMESTEP, tmp_path / "arm.py", {"arm": (0.0, 0.0, -5.0)}
    got = tune(ARM, PAIR, 0.4, engine="pybullet", qvel=QVEL, stiffness=_stiffness(24, h), forces=push,
               output=out, check=True)  # fmt: skip
    c, inv = got.contact, got.discrete.inverse
    assert c.accel == pytest.approx(L * (MASS * G + 5.0) * D / I_HINGE, rel=1e-12)
    # The check drops from touchdown, on the geometric surface where the links' compound contact
    # starts: PyBullet counts it in contact, the map's limit from phase 1 (at phase 0 e_N jumps).
    at_zero = run_drop(kernels.PYBULLET, inv.p, h, np.nextafter(1.0, 0.0), SPEED, c.accel, 10**6)[0]
    assert got.delivered == pytest.approx(at_zero, abs=1e-3)
    kw = dict(script=out, timestep=h, speed=SPEED)
    pushed = [pybullet_drop(ARM, PAIR, c.qpos, c.qvel, phase=f, forces=push, **kw).e_n for f in _phases(16)]
    assert np.mean(pushed) == pytest.approx(0.4, abs=1e-3)
    free = [pybullet_drop(ARM, PAIR, c.qpos, c.qvel, phase=f, **kw).e_n for f in _phases(4)]
    assert np.mean(free) > 0.5
