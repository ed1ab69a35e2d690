"""What users trip on, said by the front door: Hertz's k, a damping held at one speed, units, the CLI."""

import json
import math

import pytest
from scipy.integrate import solve_ivp

import contactalpha as ca
from contactalpha import cli

FOOT = {"mass": 2.0, "stiffness": 2.51e6, "approach_speed": 0.5, "accel": 9.81}


def test_hertz_stiffness_steel_ball_on_steel_plate():
    # By hand: E* = 210e9 / (2 (1 - 0.09)) = 115.3846 GPa, k = (4/3) E* sqrt(0.01) = 15.3846e9.
    assert ca.hertz_stiffness(210e9, 0.3, 0.01) == pytest.approx(15.384615384615e9, rel=1e-12)


@pytest.mark.parametrize(
    ("e1", "nu1", "r1", "e2", "nu2", "r2"),
    [
        (70e9, 0.33, 0.02, 210e9, 0.3, math.inf),
        (1e6, 0.49, 0.05, 3e9, 0.35, 0.1),
        (5e9, 0.2, 0.004, 5e9, 0.2, 0.004),
    ],
)
def test_hertz_stiffness_matches_johnsons_compression(e1, nu1, r1, e2, nu2, r2):
    """Johnson (1985) Eq. 4.23: delta = (9 F^2 / (16 R E*^2))^(1/3) at a load F, so k = F / delta^1.5."""
    e_star = 1.0 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)
    r_star = 1.0 / (1.0 / r1 + (0.0 if r2 == math.inf else 1.0 / r2))
    force = 123.0
    delta = (9 * force**2 / (16 * r_star * e_star**2)) ** (1 / 3)
    k = ca.hertz_stiffness(e1, nu1, r1, modulus_2=e2, poisson_2=nu2, radius_2=r2)
    assert k == pytest.approx(force / delta**1.5, rel=1e-12)


def test_hertz_stiffness_rigid_plate_and_bad_input():
    assert ca.hertz_stiffness(210e9, 0.3, 0.01, modulus_2=math.inf) == pytest.approx(
        4 / 3 * 210e9 / 0.91 * 0.1, rel=1e-12
    )
    with pytest.raises(ValueError, match=r"poisson = 0\.6 .*\(-1\.0, 0\.5\]"):
        ca.hertz_stiffness(210e9, 0.6, 0.01)
    with pytest.raises(ValueError, match="radius"):
        ca.hertz_stiffness(210e9, 0.3, -0.01)
    with pytest.raises(ValueError, match="two flats"):
        ca.hertz_stiffness(210e9, 0.3, math.inf)


def _e_n_with_fixed_damping(mu, speed):
    """Newton's e_N of the foot with the law f = k x^1.5 + mu x^1.5 x', by SciPy (independent)."""
    m, k, a = FOOT["mass"], FOOT["stiffness"], FOOT["accel"]

    def rhs(t, y):
        x = max(y[0], 0.0)
        return [y[1], a - (k * x**1.5 + mu * x**1.5 * y[1]) / m]

    def separation(t, y):
        return y[0]

    separation.terminal, separation.direction = True, -1
    sol = solve_ivp(rhs, (0, 1.0), [0.0, speed], "DOP853", rtol=1e-12, atol=1e-15, events=separation)
    return -sol.y_events[0][0][1] / speed


def test_the_same_damping_at_half_and_twice_the_speed():
    cp = ca.contact_parameters(0.5, **FOOT)
    mu = cp.physical_damping * FOOT["stiffness"]  # mu = k d, N s/m^2.5
    assert cp.e_n_half_speed == pytest.approx(_e_n_with_fixed_damping(mu, 0.25), abs=1e-7)
    assert cp.e_n_twice_speed == pytest.approx(_e_n_with_fixed_damping(mu, 1.0), abs=1e-7)
    assert cp.e_n == pytest.approx(_e_n_with_fixed_damping(mu, 0.5), abs=1e-7)
    # Hunt-Crossley's trap: slower is bouncier, faster is deader, with the same mu.
    assert cp.e_n_half_speed > cp.e_n + 0.05 and cp.e_n_twice_speed < cp.e_n - 0.05


def test_text_output_names_the_trap_and_the_units(capsys):
    args = [
        "params",
        "--eps",
        "0.5",
        "--mass",
        "2",
        "--stiffness",
        "2.51e6",
        "--speed",
        "0.5",
        "--accel",
        "9.81",
    ]
    assert cli.main([*args, "--radius", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "at half and" in out and "this approach speed only" in out
    assert "2^1.5 E*" in out and "neither Young's modulus nor E*" in out  # OpenSim's stiffness
    assert cli.main([*args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["e_n_half_speed"] > data["e_n"] and "Simbody" in data["unit_notes"]["opensim"]


def test_version_and_options_after_the_subcommand(capsys):
    with pytest.raises(SystemExit) as stop:
        cli.main(["--version"])
    assert stop.value.code == 0 and capsys.readouterr().out.strip() == f"contactalpha {ca.__version__}"
    assert cli.main(["alpha", "0.5", "0.2", "--rtol", "1e-10", "--atol", "1e-13"]) == 0
    after = capsys.readouterr().out
    assert cli.main(["--rtol", "1e-10", "--atol", "1e-13", "alpha", "0.5", "0.2"]) == 0
    assert capsys.readouterr().out == after


def test_restitution_is_given_the_same_way_everywhere(capsys):
    scene = ["--mass", "0.5", "--stiffness", "1.4e8", "--speed", "0.5", "--accel", "9.81"]
    for command in (["alpha", "--xi", "0.2"], ["scene", *scene, "--json"], ["params", *scene, "--json"]):
        outputs = []
        for target in (["--e-n", "0.6"], ["--eps", "0.6", "--kinematic"]):
            assert cli.main([*command, *target]) == 0
            outputs.append(capsys.readouterr().out)
        assert outputs[0] == outputs[1]
        assert cli.main([*command, "--eps", "0.6"]) == 0
        assert capsys.readouterr().out != outputs[0]  # energetic differs from kinematic under a load
    assert cli.main(["alpha", "--e-n", "0.6", "--xi", "0.0"]) == 0
    assert "e_N reached  0.6" in capsys.readouterr().out
    with pytest.raises(SystemExit) as stop:
        cli.main(["alpha", "0.5", "--eps", "0.4", "--xi", "0.2"])
    assert stop.value.code == 2 and "give the restitution once" in capsys.readouterr().err


def test_every_subcommand_has_examples_and_force_states_gravity():
    parser = cli.build_parser()
    subs = next(a for a in parser._actions if a.dest == "command").choices
    for name, sub in subs.items():
        assert f"contactalpha {name}" in sub.format_help().split("examples:")[1], name
    for name in ("scene", "params"):
        force = next(a for a in subs[name]._actions if a.dest == "force")
        assert "gravity is NOT added" in force.help


def test_hertz_command(capsys):
    assert cli.main(["hertz", "--modulus", "210e9", "--poisson", "0.3", "--radius", "0.01"]) == 0
    assert capsys.readouterr().out.split()[1] == f"{ca.hertz_stiffness(210e9, 0.3, 0.01):.15g}"
    assert cli.main(["hertz", "--modulus", "210e9", "--poisson", "0.7", "--radius", "0.01"]) == 2
    assert "poisson" in capsys.readouterr().err


def test_warmup_command_runs_every_entry_point(monkeypatch, capsys):
    from contactalpha import warmup

    called = []
    monkeypatch.setitem(warmup.ENTRY_POINTS, "impact", lambda: called.append("impact"))
    monkeypatch.setattr(warmup, "ENTRY_POINTS", {"impact": warmup.ENTRY_POINTS["impact"]})
    assert cli.main(["warmup"]) == 0
    captured = capsys.readouterr()
    assert called == ["impact"] and "impact" in captured.err and captured.out.startswith("ready")


def test_check_config_without_the_workflow_extra_says_what_to_install(monkeypatch, capsys):
    import sys

    monkeypatch.setitem(sys.modules, "contactalpha.config", None)  # as if PyYAML were not installed
    assert cli.main(["check-config", "config.yaml"]) == 2
    assert 'pip install "contactalpha[workflow]"' in capsys.readouterr().err
