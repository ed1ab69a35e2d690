"""m_eff and the free acceleration read from the model files against hand-derived values (1e-9)."""

import hand
import pytest
from cases import CASES

from contactalpha.mechanism import read_contact

HAND = {
    "pendulum": lambda: hand.pendulum(20.0),
    "capsule": hand.capsule,
    "leg": hand.leg,
    "box": hand.box,
}
TOL = 1e-9


def _check(contact, case):
    m_eff, accel = HAND[case.name]()
    assert contact.effective_mass == pytest.approx(m_eff, rel=TOL, abs=0)
    assert contact.accel == pytest.approx(accel, rel=TOL, abs=TOL)
    assert contact.approach_speed == pytest.approx(0.8, rel=1e-12)
    assert abs(contact.gap) < 1e-12
    assert abs(contact.velocity_accel) < 1e-12  # no Coriolis term along these approaches
    assert contact.point == pytest.approx(hand.contact_points()[case.name], abs=1e-12)
    normal = [1.0, 0.0, 0.0] if case.name == "pendulum" else [0.0, 0.0, 1.0]
    assert contact.normal == pytest.approx(normal, abs=1e-12)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_mujoco_reads_hand_values(mujoco, case):
    contact = read_contact(case.path(".xml"), case.pair, qvel=case.qvel_mujoco, forces=case.forces)
    assert contact.engine == "mujoco"
    _check(contact, case)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_drake_reads_hand_values(pydrake, case):
    contact = read_contact(case.path(".sdf"), case.pair, qvel=case.qvel_drake, forces=case.forces)
    assert contact.engine == "drake"
    _check(contact, case)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_drake_reads_a_pair_in_either_order(pydrake, case):
    """Drake returns a pair's closest points in its own order; the reader follows geometry 1 to 2."""
    ahead = read_contact(case.path(".sdf"), case.pair, qvel=case.qvel_drake, forces=case.forces)
    back = read_contact(case.path(".sdf"), case.pair[::-1], qvel=case.qvel_drake, forces=case.forces)
    assert back.normal == pytest.approx(-ahead.normal, abs=1e-12)
    assert back.point == pytest.approx(ahead.point, abs=1e-12)
    assert back.effective_mass == pytest.approx(ahead.effective_mass, rel=1e-12)
    assert back.accel == pytest.approx(ahead.accel, rel=1e-12)
    assert back.approach_speed == pytest.approx(ahead.approach_speed, rel=1e-12)


def test_leg_push_and_contact_point(mujoco):
    """A named force on the hip adds J M^-1 J_hip^T F; the contact point is the foot's lowest point."""
    case = CASES[2]
    contact = read_contact(case.path(".xml"), case.pair, qvel=case.qvel_mujoco, forces={"hip": (0, 0, -30.0)})
    m_eff, accel = hand.leg(30.0)
    assert contact.accel == pytest.approx(accel, rel=TOL)
    assert contact.forces_accel == pytest.approx(accel - hand.leg()[1], rel=1e-9)
    g = hand.LEG
    import math

    x = -g["l1"] * math.sin(g["q1"]) - g["l2"] * math.sin(g["q1"] + g["q2"])
    assert contact.point == pytest.approx([x, 0.0, 0.0], abs=1e-12)
    assert contact.normal == pytest.approx([0.0, 0.0, 1.0], abs=1e-12)


def test_velocity_term_agrees_between_engines(mujoco, pydrake):
    """The Coriolis part at a swinging leg: MuJoCo's and Drake's dynamics give the same value."""
    case = CASES[2]
    qvel = (-0.8, 1.0, -2.0)
    a = read_contact(case.path(".xml"), case.pair, qvel=qvel)
    b = read_contact(case.path(".sdf"), case.pair, qvel=qvel)
    assert abs(a.velocity_accel) > 0.1
    assert a.velocity_accel == pytest.approx(b.velocity_accel, rel=1e-9)


def test_speed_gives_least_energy_velocity(mujoco):
    """Given a contact-point speed, the joint velocity is -v m_eff M^-1 J^T: closing at v."""
    case = CASES[3]
    contact = read_contact(case.path(".xml"), case.pair, speed=1.25)
    assert contact.approach_speed == 1.25
    assert -(contact.jacobian @ contact.qvel) == pytest.approx(1.25, rel=1e-12)


@pytest.mark.parametrize("reader", ["mujoco", "drake"])
def test_urdf_leg_reads_hand_values(mujoco, pydrake, reader):
    """The same leg in URDF, through MuJoCo's compiler and through Drake's parser."""
    case = CASES[2]
    contact = read_contact(case.path(".urdf"), case.pair, reader=reader, qvel=case.qvel_mujoco)
    assert contact.engine == reader
    _check(contact, case)


def test_urdf_tuned_for_mujoco_is_the_compiled_mjcf_with_the_pair(mujoco, tmp_path):
    from contactalpha.mechanism.tune import tune

    case = CASES[2]
    out = tmp_path / "leg_tuned.xml"
    got = tune(
        case.path(".urdf"),
        case.pair,
        0.6,
        engine="mujoco",
        qvel=case.qvel_mujoco,
        stiffness=1e6,
        output=out,
        discrete=False,  # the file's form; at MuJoCo's 2 ms this stiffness is out of reach
    )
    text = out.read_text()
    assert text.startswith("<mujoco") and text.count("<pair") == 1
    again = read_contact(out, case.pair, qvel=case.qvel_mujoco)
    # MuJoCo writes its compiled MJCF with 6 significant digits (poses, masses): m_eff to ~1e-6
    assert again.effective_mass == pytest.approx(hand.leg()[0], rel=1e-5)
    assert again.engine_row["solref"] == pytest.approx(got.parameters["solref"], rel=1e-12)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_mujoco_row_is_built_as_its_source_says(mujoco, case):
    """diagA = the bodies' translational body_invweight0 (mj_diagApprox), R = (1 - imp)/imp diagA
    (mj_makeImpedance; the row is read with the margin raised past solimp's width: imp = solimp[1])."""
    contact = read_contact(case.path(".xml"), case.pair, qvel=case.qvel_mujoco)
    m = mujoco.MjModel.from_xml_path(case.path(".xml"))
    bodies = [m.geom_bodyid[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, g)] for g in case.pair]
    row = contact.engine_row
    assert row["diagA"] == pytest.approx(sum(m.body_invweight0[b, 0] for b in bodies), rel=1e-15)
    imp = row["solimp"][1]
    assert row["R"] == pytest.approx((1 - imp) / imp * row["diagA"], rel=1e-12)
    assert abs(row["diagA"] * contact.effective_mass - 1.0) > 0.1  # a mechanism: diagA is not 1/m_eff
