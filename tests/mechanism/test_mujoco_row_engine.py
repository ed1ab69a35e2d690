"""MuJoCo's contact row in a mechanism, measured in MuJoCo: the stiffness it sees, its d_e.

The pendulum (``tests/data/models/pendulum.xml``) has ``diagA`` (from ``body_invweight0``) far
from ``J M^-1 J^T``: the effective impedance ``d_e = A / (A + R)`` is not solimp's d.  Both
checks read MuJoCo's own constraint quantities (``efc_force``, ``efc_pos``, ``efc_R``, ``efc_J``
with ``mj_solveM``), never the package's row algebra: with gravity off and the joint at rest the
row's force is ``f = d_e (a_ref - 0) / A`` with ``a_ref = -K imp r``, so ``f / depth`` is the
contact stiffness (N/m) MuJoCo applies.
"""

import math
import warnings

import numpy as np
import pytest
from hand import MODELS

from contactalpha.mechanism import UnmodelledSettingWarning, read_contact, tune
from contactalpha.mechanism.mujoco_row import current_stiffness

PENDULUM = str(MODELS / "pendulum.xml")
PAIR = ("wall", "tip")
L = 0.5  # the tip's distance from the hinge (pendulum.xml)
DEPTHS = (2e-3, 3e-3)  # beyond solimp's default width 1e-3: the impedance is solimp[1]


def _row_at_depth(model_source, depth):
    """``(efc_force, -efc_pos, A, efc_R)`` of the pair's row with the tip ``depth`` into the wall, at rest."""
    import mujoco

    m = mujoco.MjModel.from_xml_path(str(model_source))
    m.opt.gravity[:] = 0.0
    d = mujoco.MjData(m)
    d.qpos[0] = math.asin(depth / L)  # about +y: the tip moves along -x, into the wall
    mujoco.mj_forward(m, d)
    assert d.ncon == 1 and d.nefc == 1
    J = np.array(d.efc_J[: m.nv], dtype=float).reshape(1, m.nv)
    minv_jt = np.zeros((1, m.nv))
    mujoco.mj_solveM(m, d, minv_jt, J)
    return float(d.efc_force[0]), -float(d.efc_pos[0]), float(J[0] @ minv_jt[0]), float(d.efc_R[0])


def _measured_stiffness(model_source):
    rows = [_row_at_depth(model_source, x) for x in DEPTHS]
    (f1, x1, *_), (f2, x2, *_) = rows
    return (f2 - f1) / (x2 - x1), rows


def test_current_stiffness_is_what_mujoco_applies(mujoco):
    """The model's own solref (0.02, 1), solimp (0.9, 0.95, 0.001): k through its row, as MuJoCo's force."""
    k_mujoco, rows = _measured_stiffness(PENDULUM)
    contact = read_contact(PENDULUM, PAIR, qvel=[1.6])
    assert current_stiffness(contact) == pytest.approx(k_mujoco, rel=1e-3)
    # The row's force goes through the origin (no free acceleration): f = k depth at each depth.
    assert rows[0][0] == pytest.approx(k_mujoco * rows[0][1], rel=1e-3)
    result = tune(PENDULUM, PAIR, 0.5, qvel=[1.6])  # no stiffness: the model's own
    assert result.details.stiffness == pytest.approx(k_mujoco, rel=1e-3)


def test_tuned_row_has_mujocos_effective_impedance(mujoco, tmp_path):
    """The tuned file's row: d_e = A / (A + efc_R) from MuJoCo, and the stiffness asked for in N/m."""
    k = 1e4
    result = tune(PENDULUM, PAIR, 0.5, qvel=[1.6], stiffness=k, output=tmp_path / "t.xml")
    force, depth, A, R = _row_at_depth(result.output, DEPTHS[0])
    d_e = A / (A + R)
    assert abs(d_e - result.details.impedance) > 0.03  # the pendulum's row is far from a free body's
    assert result.details.effective_impedance == pytest.approx(d_e, rel=1e-6)
    assert force / depth == pytest.approx(k, rel=1e-3)


@pytest.mark.parametrize(
    "option, words",
    [
        ('integrator="RK4"/>', "integrator rk4"),
        ('integrator="Euler" density="1.2"/>', "fluid forces (density 1.2"),
        ('integrator="Euler"/><default><joint damping="0.05"/></default>', "joint 'hinge' damping 0.05"),
        ('integrator="Euler"/><default><joint frictionloss="0.2"/></default>', "'hinge' frictionloss 0.2"),
        ('integrator="Euler"/><default><joint stiffness="3"/></default>', "joint 'hinge' stiffness 3"),
    ],
)
def test_tune_warns_on_settings_the_answer_leaves_out(mujoco, tmp_path, option, words):
    """Each setting the answer does not model gives one warning naming it; the plain model none."""
    text = (MODELS / "pendulum.xml").read_text()
    model = tmp_path / "m.xml"
    model.write_text(text.replace('integrator="Euler"/>', option))
    with pytest.warns(UnmodelledSettingWarning) as caught:
        tune(model, PAIR, 0.5, qvel=[1.6], stiffness=1e4)  # no engine loop: the reduced model's answer
    assert [w for w in caught if words in str(w.message)] and len(caught) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnmodelledSettingWarning)
        tune(PENDULUM, PAIR, 0.5, qvel=[1.6], stiffness=1e4)


@pytest.mark.parametrize("flag, words", [('override="enable"', "enables override"),
                                         ('contact="disable"', "disables contact")])  # fmt: skip
def test_tune_refuses_settings_under_which_no_pair_acts(mujoco, tmp_path, flag, words):
    model = tmp_path / "m.xml"
    text = (MODELS / "pendulum.xml").read_text()
    model.write_text(text.replace('integrator="Euler"/>', f'integrator="Euler"><flag {flag}/></option>'))
    with pytest.raises(ValueError, match=words):
        tune(model, PAIR, 0.5, qvel=[1.6], stiffness=1e4)
