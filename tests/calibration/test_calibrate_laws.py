"""The laws' contacts and sequences against independent integrations and the package's prediction."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from contactalpha.calibration import hypotheses, sequence
from contactalpha.engine.exact import alpha_exact
from contactalpha.scene.ball import Scene, simulate
from contactalpha.scene.bounces import predict_bounces

M, K, A = 0.05, 1e8, 9.81


def _ivp_contact(alpha, v, loaded):
    """Physical contact m x'' = m a - k x^1.5 (1 + alpha x'/v) from x = 0, x' = v, to separation."""

    def rhs(_, s):
        x, u = s
        f = K * max(x, 0.0) ** 1.5 * (1.0 + alpha * u / v)
        return [u, (A if loaded else 0.0) - f / M]

    def lift(_, s):
        return s[0] if _ > 1e-9 else 1.0

    lift.terminal, lift.direction = True, -1
    sol = solve_ivp(rhs, (0, 1.0), [0.0, v], events=lift, rtol=1e-12, atol=1e-16, method="DOP853")
    return -sol.y_events[0][0][1], sol.t_events[0][0]


@pytest.mark.parametrize(
    ("name", "values", "alpha", "loaded"),
    [
        ("hc_damping", {"damping": 0.2, "stiffness": K}, 0.2 * 0.3, True),
        ("constant_e", {"e": 0.7, "stiffness": K}, float(alpha_exact(0.7)), False),
    ],
)
def test_contact_matches_solve_ivp(name, values, alpha, loaded):
    v = 0.3
    c = hypotheses.HYPOTHESES[name].contact(values, M, A, v)
    v_out, duration = _ivp_contact(alpha, v, loaded)
    assert c.separated
    assert c.v_out == pytest.approx(v_out, rel=1e-7)
    assert c.duration == pytest.approx(duration, rel=1e-7)


def test_constant_e_has_that_restitution_at_every_speed():
    law = hypotheses.HYPOTHESES["constant_e"]
    for v in (0.01, 0.3, 3.0):
        c = law.contact({"e": 0.7, "stiffness": K}, M, A, v)
        assert c.v_out / v == pytest.approx(0.7, abs=1e-9)


def test_hc_eps_sequence_is_the_package_prediction():
    scene = Scene(mass=M, stiffness=K, approach_speed=2.0, force=0.0, eps=0.8)
    p = predict_bounces(scene, "exact")
    s = sequence.simulate(
        hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": K}, M, scene.accel, 2.0, 0.0, 100
    )
    np.testing.assert_array_equal(s.v_in, p.approach_speeds)
    np.testing.assert_allclose(s.durations, p.contact_durations, rtol=1e-14)
    assert s.ended and s.v_in.size == p.contacts
    # Gravity makes e_N fall at the slow last bounces.
    assert s.e_n[-2] < 0.5 * s.e_n[0]


def test_touchdowns_and_heights_agree_with_the_time_stepped_ball():
    scene = Scene(mass=M, stiffness=K, approach_speed=1.0, force=0.0, eps=0.8, t_end=0.6)
    run = simulate(scene, "exact")
    s = sequence.simulate(hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": K}, M, A, 1.0, 0.0, 100)
    n = run.count
    np.testing.assert_allclose(s.touchdowns[:n], run.collisions["t_start"], rtol=1e-9, atol=1e-12)
    flight = run.phase == 0
    z = sequence.height_at(s, run.t[flight])
    np.testing.assert_allclose(z, -run.delta[flight], atol=1e-9)


def test_the_hypotheses_have_one_name(tmp_path):
    """ "Law" names a contact law only: the hypotheses' old names (before 0.1.0) are gone."""
    import contactalpha as ca
    from contactalpha.cli import main

    t = sequence.simulate(
        hypotheses.HYPOTHESES["constant_e"], {"e": 0.8, "stiffness": K}, M, 9.81, 2.0, 0.0, 12
    )
    cal = ca.calibrate(t.touchdowns, kind="times", mass=M, hypotheses=["constant_e"], intervals=False)
    assert list(cal.fits) == ["constant_e"]
    with pytest.raises(TypeError, match="laws"):
        ca.calibrate(t.touchdowns, kind="times", mass=M, laws=["constant_e"], intervals=False)
    for old in ("LAWS", "DEFAULT_LAW", "Law", "check_law"):
        assert not hasattr(hypotheses, old)
    with pytest.raises(ImportError):
        __import__("contactalpha.calibration.laws")
    path = tmp_path / "t.csv"
    path.write_text("t\n" + "\n".join(repr(float(x)) for x in t.touchdowns) + "\n")
    assert main(["calibrate", str(path), "--mass", str(M), "--law", "constant_e", "--quiet"]) == 0
