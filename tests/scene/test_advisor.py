"""The scene advisor: xi and its level, what each model delivers, adequacy, the cheapest model."""

import json
import math

import numpy as np
import pytest

from contactalpha import cli, models
from contactalpha.engine.driver import impact
from contactalpha.engine.exact import alpha_exact
from contactalpha.scene import advisor as adv

# The paper's ball at F = 60 N (xi = 0.2325): docs' check values.
SCENE = {"mass": 0.5, "stiffness": 1.4e8, "approach_speed": 0.5}
# Fixed costs (s) so that the recommendation does not depend on this machine's timings.
COSTS = {name: 1e-6 for name in models.MODELS} | {"exact_solve": 1e-4, "exact": 2e-6}


def test_levels_follow_the_paper():
    assert [adv.xi_level(x) for x in (0.0, 0.0999, 0.1, 0.4999, 0.5, 0.99)] == [
        "small", "small", "moderate", "moderate", "large", "large"
    ]  # fmt: skip
    with pytest.raises(ValueError, match="xi"):
        adv.xi_level(1.0)


def test_moderate_load_scene():
    a = adv.advise(0.5, accel=129.81, tol=0.01, costs=COSTS, **SCENE)
    assert a.xi == pytest.approx(0.2325, abs=1e-4) and a.xi_level == "moderate"
    assert a.exact_state == "separation"
    by = {m.name: m for m in a.models}
    assert set(by) == set(models.MODELS)  # every registered model, new ones included
    # Delivered eps is one impact with the model's alpha at this xi.
    hc = by["hunt_crossley"]
    assert hc.alpha == 0.75 and hc.delivered_eps == pytest.approx(float(impact(0.75, a.xi).eps), abs=1e-14)
    assert not hc.adequate and hc.delivered_eps == pytest.approx(0.6624, abs=1e-4)
    assert by["exact"].adequate and abs(by["exact"].delivered_eps - 0.5) < 1e-6
    # alpha at xi = 0 gives eps = 0.519 here: the load may not be ignored at tol 0.01, may at 0.05.
    assert not a.ignore_load and a.ignore_load_eps == pytest.approx(0.5194, abs=1e-4)
    assert adv.advise(0.5, accel=129.81, tol=0.05, costs=COSTS, **SCENE).ignore_load
    # Cheapest: the 1 us models that are adequate and use the load (it matters), the most accurate.
    cheap = [m for m in a.models if m.adequate and m.uses_xi and COSTS[m.name] == 1e-6]
    assert a.cheapest == min(cheap, key=lambda m: m.error).name
    # Judged over the exact bounce sequence: 0.5 m/s, then e_N times each speed.
    assert a.speeds_from == "bounces" and a.speeds[0] == 0.5 and len(a.speeds) >= 2
    assert a.speeds[1] == pytest.approx(0.5 * a.exact_e_n, rel=1e-9)


def test_force_is_accel_times_mass_and_exactly_one_is_needed():
    a = adv.advise(0.5, accel=129.81, costs=COSTS, **SCENE)
    b = adv.advise(0.5, force=129.81 * 0.5, costs=COSTS, **SCENE)
    assert a.xi == b.xi
    for kw in ({}, {"accel": 1.0, "force": 1.0}):
        with pytest.raises(ValueError, match="exactly one"):
            adv.advise(0.5, costs=COSTS, **SCENE, **kw)
    with pytest.raises(ValueError, match="restitution"):
        adv.advise(0.5, accel=1.0, restitution="newton", costs=COSTS, **SCENE)


def test_small_eps_needs_the_load():
    # eps = 0.05 on the ball under gravity only: xi = 0.02 is "small", yet the exact impact creeps
    # to rest and every model that ignores the load separates: none of them is adequate.
    a = adv.advise(0.05, accel=9.81, costs=COSTS, **SCENE)
    assert a.xi_level == "small" and a.exact_state == "creep" and not a.ignore_load
    assert not any(m.adequate for m in a.models if not m.uses_xi)


def test_adequacy_rule_and_recommendation():
    states = ["separation"] * 3 + ["creep"]
    ok = adv.is_adequate([0.501, 0.519, np.nan, 0.51], states, 0.51, "separation", 0.01)
    assert ok.tolist() == [True, True, False, False]
    names = ["a", "b", "c"]
    costs = {"a": 1.0, "b": 1.4, "c": 10.0}
    assert adv.cheapest(names, [True, True, True], costs, [0.009, 0.001, 0.0]) == "b"  # tied on cost
    assert adv.cheapest(names, [True, False, True], costs, [0.009, 0.001, 0.0]) == "a"
    assert adv.cheapest(names, [False] * 3, costs, [0.0] * 3) is None


def test_cost_model_is_fixed_and_checked():
    costs = adv.model_costs()
    assert set(costs) == set(models.MODELS)  # every registered model has a cost
    assert costs["hunt_crossley"] < costs["exact"] < costs["exact_solve"]
    with pytest.raises(ValueError, match=r"no cost for model\(s\) \['hunt_crossley'"):
        adv.advise(0.5, accel=129.81, costs={}, **SCENE)
    with pytest.raises(ValueError, match="cost of model 'flores' = -1.0 is outside the valid range"):
        adv.advise(0.5, accel=129.81, costs=COSTS | {"flores": -1.0}, **SCENE)
    with pytest.raises(ValueError, match="costs must be a mapping"):
        adv.advise(0.5, accel=129.81, costs=[1.0], **SCENE)
    with pytest.raises(ValueError, match="speeds"):
        adv.advise(0.5, accel=129.81, speeds=(1.0,), **SCENE)
    with pytest.raises(ValueError, match="low must not exceed high"):
        adv.advise(0.5, accel=129.81, speeds=(1.0, 0.5), **SCENE)


def test_same_input_same_advice_byte_for_byte():
    """The issue's scene: "exact" twice and "flores" twice in four calls before (timed costs)."""
    from contactalpha.io import json_text

    scene = {"mass": 5, "stiffness": 1e9, "approach_speed": 0.5, "accel": 129.81, "tol": 0.01}
    texts = {json_text(adv.advise(0.5, **scene).to_dict()) for _ in range(4)}
    assert len(texts) == 1
    assert adv.format_advice(adv.advise(0.5, **scene)) == adv.format_advice(adv.advise(0.5, **scene))


# The robot foot of issue 25: m = 2 kg, k = 2.51e6 N/m^1.5, eps = 0.3, 600 N plus its weight.
FOOT = {"mass": 2.0, "stiffness": 2.51e6, "approach_speed": 0.5, "force": 600.0 + 2.0 * 9.81, "tol": 0.01}


def _hunt_crossley_eps_by_scipy(speed):
    """Stronge's eps of the foot with Hunt-Crossley's alpha (1.05), from the work of the contact force.

    Independent of the package: SciPy's DOP853 on m x'' = m a - k x^1.5 (1 + alpha x'/v0), the
    contact force's work integrated beside it; restitution ends at separation or where the outward
    motion stops.
    """
    from scipy.integrate import solve_ivp

    m, k, a, alpha = FOOT["mass"], FOOT["stiffness"], FOOT["force"] / FOOT["mass"], 1.5 * (1 - 0.3)

    def rhs(t, y):
        force = k * max(y[0], 0.0) ** 1.5 * (1 + alpha * y[1] / speed)
        return [y[1], a - force / m, force * y[1]]

    def separation(t, y):
        return y[0]

    def turn(t, y):
        return y[1]

    separation.terminal, separation.direction = True, -1
    turn.direction = -1
    ends = lambda t, y: y[1]  # noqa: E731
    ends.terminal, ends.direction = True, 1
    sol = solve_ivp(rhs, (0, 2.0), [0, speed, 0], "DOP853", rtol=1e-12, atol=1e-15,
                    events=[separation, turn, ends], dense_output=True)  # fmt: skip
    absorbed = sol.sol(sol.t_events[1][0])[2]
    return math.sqrt(max(absorbed - sol.y[2, -1], 0.0) / absorbed)


def test_robot_foot_is_not_advised_hunt_crossley():
    """Adequate at 0.5 m/s by coincidence (0.2913 for 0.3), Hunt-Crossley fails over 0.3-1.0 m/s."""
    speeds = (0.3, 0.4, 0.7, 1.0)
    independent = [_hunt_crossley_eps_by_scipy(v) for v in speeds]
    assert independent == pytest.approx([0.0, 0.176, 0.405, 0.497], abs=6e-4)  # the numbers
    default = adv.advise(0.3, **FOOT)
    hc = {m.name: m for m in default.models}["hunt_crossley"]
    assert hc.delivered_eps == pytest.approx(_hunt_crossley_eps_by_scipy(0.5), abs=1e-6)
    assert abs(hc.delivered_eps - 0.3) < 0.01  # the coincidence at the one speed it sees
    assert default.cheapest != "hunt_crossley" and not default.ignore_load
    assert "ignores the load" in hc.note  # and it says why
    ranged = adv.advise(0.3, speeds=(0.3, 1.0), **FOOT)
    assert ranged.speeds_from == "range" and ranged.speeds[:2] == (0.5, 1.0) and ranged.speeds[-1] == 0.3
    hc = {m.name: m for m in ranged.models}["hunt_crossley"]
    assert not hc.adequate and ranged.cheapest != "hunt_crossley"
    # Its worst speed is the slowest: 0.3 m/s, where it delivers no restitution at all.
    assert hc.worst_speed == 0.3 and hc.margin == pytest.approx(0.01 - 0.3, abs=1e-12)
    rec = {m.name: m for m in ranged.models}[ranged.cheapest]
    assert rec.adequate and rec.margin == ranged.margin >= 0.0 and rec.uses_xi


@pytest.mark.parametrize("accel", [9.81, 129.81, 600.0])
@pytest.mark.parametrize("eps", [0.2, 0.5, 0.9])
def test_load_verdict_and_recommendation_agree(eps, accel):
    a = adv.advise(eps, accel=accel, **SCENE)
    rec = {m.name: m for m in a.models}.get(a.cheapest)
    if rec is not None and not rec.uses_xi:
        assert a.ignore_load  # a load-ignoring model only where the load may be ignored
    for mv in a.models:
        assert mv.margin >= 0.0 or not mv.adequate


def test_command_line(capsys):
    args = ["scene", "0.5", "--mass", "0.5", "--stiffness", "1.4e8", "--speed", "0.5", "--accel", "129.81"]
    assert cli.main([*args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["xi_level"] == "moderate" and len(data["models"]) == len(models.MODELS)
    assert cli.main(args) == 0
    assert "recommended  " in capsys.readouterr().out
    assert cli.main([*args[:-2], "--force", "-1"]) == 2
    assert "force" in capsys.readouterr().err


def test_kinematic_request_is_judged_in_e_n():
    """e_N = 0.5 at xi = 0.2325: the exact alpha delivers it; models fed 0.5 are judged by their e_N."""
    from contactalpha.engine.solver import solve_alpha

    a = adv.advise(0.5, accel=129.81, restitution="kinematic", costs=COSTS, **SCENE)
    e = adv.advise(0.5, accel=129.81, costs=COSTS, **SCENE)
    assert a.restitution == "kinematic" and a.xi == e.xi
    assert a.exact_alpha == solve_alpha(0.5, a.xi, restitution="kinematic").alpha
    r = impact(a.exact_alpha, a.xi)
    assert abs(r.e_n - 0.5) < 1e-8 and a.exact_e_n == pytest.approx(r.e_n, abs=1e-12)
    assert a.exact_eps == pytest.approx(r.eps, abs=1e-12) and a.exact_eps > 0.6  # eps != e_N under load
    # Energetic advice: its exact impact's e_N is the kinematic one, not 0.5.
    assert e.exact_eps == pytest.approx(0.5, abs=1e-8) and abs(e.exact_e_n - 0.5) > 0.1
    by = {m.name: m for m in a.models}
    hc = by["hunt_crossley"]
    assert hc.delivered_eps == pytest.approx(float(impact(0.75, a.xi).e_n), abs=1e-14)
    # The load-aware models are formulas in Stronge's eps: fed e_N = 0.5 they miss it by > 0.2.
    assert not by["exact"].adequate and by["exact"].delivered_eps == pytest.approx(e.exact_e_n, abs=1e-6)
    assert a.ignore_load_eps == pytest.approx(float(impact(float(alpha_exact(0.5)), a.xi).e_n), abs=1e-14)
    assert a.cheapest is None and not a.ignore_load
    # At xi = 0 the definitions agree: the same alpha and every delivered number equal.
    k0 = adv.advise(0.5, accel=0.0, restitution="kinematic", costs=COSTS, **SCENE)
    e0 = adv.advise(0.5, accel=0.0, costs=COSTS, **SCENE)
    assert k0.exact_alpha == pytest.approx(e0.exact_alpha, rel=1e-9)
    for mk, me in zip(k0.models, e0.models, strict=True):
        assert mk.delivered_eps == pytest.approx(me.delivered_eps, abs=1e-12) and mk.adequate == me.adequate


def test_command_line_kinematic(capsys):
    from contactalpha.engine.solver import solve_alpha

    args = ["scene", "0.5", "--mass", "0.5", "--stiffness", "1.4e8", "--speed", "0.5", "--accel", "129.81"]
    assert cli.main([*args, "--kinematic", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["restitution"] == "kinematic"
    exact = solve_alpha(0.5, data["xi"], restitution="kinematic")
    assert data["exact_alpha"] == pytest.approx(float(exact.alpha))
    assert abs(data["exact_e_n"] - 0.5) < 1e-8
    assert cli.main([*args, "--kinematic"]) == 0
    out = capsys.readouterr().out
    assert "e_N = 0.5 (kinematic)" in out and f"{data['exact_alpha']:.10g}" in out
