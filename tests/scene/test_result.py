"""One result type from the front door, keyed by engine, for every law, one scene or a batch (issue 32)."""

import dataclasses
import json
import math

import numpy as np
import pytest

import contactalpha as ca
from contactalpha import cli
from contactalpha.adapters.registry import ADAPTERS, check_radius_used
from contactalpha.laws import LAWS, get_law
from contactalpha.parameters.result import ContactParameters

G = 9.81


def scene_of(law, rng, n=None):
    """A random scene in the law's physical units (N/m^1.5 for n = 3/2, N/m for n = 1)."""
    hertz = law.exponent != 1.0
    draw = {
        "mass": (0.1, 2.0),
        "stiffness": (6.0, 9.0) if hertz else (3.0, 6.0),
        "approach_speed": (0.2, 3.0),
        "accel": (0.0, 30.0),
        "e_N": (0.1, 0.95),
        "radius": (0.01, 0.1),
    }
    s = {k: rng.uniform(*lim, n) for k, lim in draw.items()}
    s["stiffness"] = 10.0 ** s["stiffness"]
    try:
        check_radius_used(law, 0.05)
    except ValueError:  # none of the law's engines reads a radius: give none
        del s["radius"]
    return s if n is not None else {k: float(v) for k, v in s.items()}


def engines_of(law):
    # an impulse engine (``impulse`` set) has no continuous block: it is answered at its step only
    return sorted(a.name for a in ADAPTERS if a.law.name == law.name and getattr(a, "impulse", None) is None)


# The engines with a continuous block (the impulse engines' answer is at their step: tests/impulse).
CONTINUOUS = [a.name for a in ADAPTERS if getattr(a, "impulse", None) is None]


@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
def test_one_type_the_same_fields_and_keys_for_every_law_scalar_and_batch(law):
    rng = np.random.default_rng(7)
    one = ca.contact_parameters(**scene_of(law, rng), law=law.name)
    many = ca.contact_parameters(**scene_of(law, rng, 5), law=law.name)
    for cp in (one, many):
        assert type(cp) is ContactParameters
        assert cp.law == law.name and cp.damping_name == law.damping and cp.physical_unit == law.physical_unit
        assert sorted(cp.engines) == engines_of(law)  # keyed by engine, never by law
    for engine in one.engines:
        assert one.engines[engine].keys() == many.engines[engine].keys()
    # One rule: plain Python values for one scene, arrays of the batch's shape for a batch.
    for field in ("xi", "damping", "physical_damping", "eps", "e_n", "accel", "delta_star", "e_n_half_speed"):
        assert type(getattr(one, field)) is float, field
        assert getattr(many, field).shape == (5,), field
    assert type(one.end_state) is str and one.ok is True and one.reason == ""
    assert many.ok.all() and many.end_state.shape == (5,) and list(many.reason) == [""] * 5


@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
def test_scalar_and_batched_paths_give_the_same_numbers(law):
    rng = np.random.default_rng(11)
    s = scene_of(law, rng, 8)
    many = ca.contact_parameters(**s, law=law.name)
    # Hunt-Crossley n = 3/2: the same table and xi on both paths (bit for bit); the other laws:
    # the law's table (batch) against its exact inverse (scalar), the table's stated 1e-7.
    rel = 0.0 if law.name == "hunt_crossley" else 1e-7
    for i in range(8):
        one = ca.contact_parameters(**{k: float(v[i]) for k, v in s.items()}, law=law.name)
        for field in ("xi", "damping", "physical_damping"):
            assert getattr(many, field)[i] == pytest.approx(getattr(one, field), rel=rel, abs=0.0), field
        for field in ("eps", "e_n", "e_n_half_speed", "e_n_twice_speed"):  # each path integrates its impact
            assert getattr(many, field)[i] == pytest.approx(getattr(one, field), rel=max(rel, 1e-14)), field
        assert many.end_state[i] == one.end_state
        for engine, block in one.engines.items():
            for name, value in block.items():
                batched = many.engines[engine][name]
                if isinstance(value, tuple) and isinstance(batched, np.ndarray):  # a row per world
                    got = batched[i]
                elif isinstance(value, tuple):  # a tuple of arrays: entry j of row i
                    got = np.array([np.broadcast_to(x, (8,))[i] for x in batched])
                else:
                    got = np.broadcast_to(batched, (8,))[i]
                np.testing.assert_allclose(got, value, rtol=max(rel, 1e-14), err_msg=f"{engine}.{name}")


def test_the_physical_damping_is_the_laws_in_its_unit_checked_by_hand():
    m, k, v = 0.5, 1e4, 0.5
    cp = ca.contact_parameters(e_N=0.5, mass=m, stiffness=k, approach_speed=v, accel=G, law="kelvin_voigt")
    assert cp.physical_damping == pytest.approx(2.0 * cp.damping * math.sqrt(k * m), rel=1e-15)
    assert cp.physical_unit == "N s/m"
    hc = ca.contact_parameters(e_N=0.5, mass=m, stiffness=1.4e8, approach_speed=v, accel=G)
    assert hc.physical_damping == pytest.approx(hc.damping / v, rel=1e-15) and hc.physical_unit == "s/m"


@pytest.mark.parametrize("engine", CONTINUOUS)
def test_engine_picks_its_law_and_returns_its_block(engine):
    law = next(a.law for a in ADAPTERS if a.name == engine)
    s = scene_of(law, np.random.default_rng(3))
    cp = ca.contact_parameters(**s, engine=engine)
    by_law = ca.contact_parameters(**s, law=law.name)
    assert cp.law == law.name and cp.engine == engine and list(cp.engines) == [engine]
    assert cp.block == by_law.engines[engine] and cp.damping == by_law.damping
    batch = ca.contact_parameters(**scene_of(law, np.random.default_rng(3), 4), engine=engine)
    assert list(batch.engines) == [engine] and batch.block.keys() == cp.block.keys()


def test_law_and_engine_must_agree():
    s = scene_of(get_law("mujoco_soft"), np.random.default_rng(1))
    with pytest.raises(ValueError, match="law = 'kelvin_voigt' is not engine 'mujoco'"):
        ca.contact_parameters(**s, engine="mujoco", law="kelvin_voigt")
    assert ca.contact_parameters(**s, engine="mujoco", law="mujoco_soft").engine == "mujoco"


def _cli_block(engine, s, capsys):
    args = ["params", "--e-n", repr(s["e_N"]), "--mass", repr(s["mass"]), "--stiffness", repr(s["stiffness"])]
    args += ["--speed", repr(s["approach_speed"]), "--accel", repr(s["accel"])]
    args += ["--radius", repr(s["radius"])] if "radius" in s else []
    assert cli.main([*args, "--engine", engine, "--json"]) == 0
    return json.loads(capsys.readouterr().out)["parameters"]


@pytest.mark.parametrize("engine", CONTINUOUS)  # the impulse engines' CLI: tests/impulse
def test_cli_engine_and_python_engine_give_the_same_numbers_at_20_random_scenes(engine, capsys):
    law = next(a.law for a in ADAPTERS if a.name == engine)
    rng = np.random.default_rng(2032)
    for _ in range(20):
        s = scene_of(law, rng)
        block = ca.contact_parameters(**s, engine=engine).block
        printed = _cli_block(engine, s, capsys)
        assert printed.keys() == block.keys()
        for name, value in block.items():
            want = np.asarray(value, dtype=float)
            np.testing.assert_array_equal(np.asarray(printed[name], dtype=float), want, err_msg=name)


def _help_of(option):
    """The help text of a ``params`` option, as argparse holds it."""
    parser = cli.build_parser()
    sub = parser._subparsers._group_actions[0].choices["params"]
    return " ".join(next(a.help for a in sub._actions if option in a.option_strings).split())


def test_the_helps_stiffness_is_physical_for_every_law_and_the_code_agrees(capsys):
    text = _help_of("--stiffness")
    assert "never per unit mass" in text and "per unit mass for" not in _help_of("--law")
    reading = {}  # unit -> what the help says takes it
    for part in text.split(": ", 1)[1].split("; "):
        unit, _, rest = part.partition(" for ")
        reading[unit] = rest
    for law in LAWS:
        assert law.name in reading[law.stiffness_unit], law.name
    for a in ADAPTERS:  # an engine's stiffness is its law's (the help names laws, the registry engines)
        assert a.law.name in reading[a.law.stiffness_unit], a.name
    # The code reads it so: MuJoCo's law with m = 0.5 kg and k = 1e4 N/m is the engine's scene, and
    # its solref is k/m, 2 zeta sqrt(k/m); zeta is the law's inverse at A = a / (omega v),
    # omega = sqrt(k/m).
    m, k, v, a = 0.5, 1e4, 0.5, 5.0 / 0.5  # --force 5 with no gravity added
    common = ["params", "--e-n", "0.5", "--mass", "0.5", "--stiffness", "1e4", "--speed", "0.5"]
    common += ["--force", "5"]
    assert cli.main([*common, "--law", "mujoco_soft", "--json"]) == 0
    by_law = json.loads(capsys.readouterr().out)
    assert cli.main([*common, "--engine", "mujoco", "--json"]) == 0
    by_engine = json.loads(capsys.readouterr().out)["parameters"]
    omega = math.sqrt(k / m)
    law = get_law("mujoco_soft")
    zeta = float(law.damping_for(0.5, float(law.load_factor(a / (omega * v))), "kinematic").damping)
    assert by_law["damping"] == pytest.approx(zeta, rel=1e-12)
    for block in (by_law["engines"]["mujoco"], by_engine):
        assert block["solref"][0] == pytest.approx(-k / m, rel=1e-15)
        assert block["solref"][1] == pytest.approx(-2.0 * zeta * omega, rel=1e-12)


def test_printed_labels_carry_the_right_units(capsys):
    common = ["params", "--e-n", "0.5", "--mass", "0.5", "--stiffness", "1e4", "--speed", "0.5"]
    common += ["--accel", "9.81"]
    assert cli.main([*common, "--law", "mujoco_soft"]) == 0
    lines = {line.split()[0]: line.split() for line in capsys.readouterr().out.splitlines() if line.strip()}
    zeta = float(lines["zeta"][1])
    c = 2.0 * zeta * math.sqrt(1e4 * 0.5)
    assert float(lines["damping"][1]) == pytest.approx(c, rel=1e-12) and lines["damping"][2:4] == ["N", "s/m"]
    assert float(lines["mujoco.damping"][1]) == pytest.approx(c / 0.5, rel=1e-12)
    assert lines["mujoco.damping"][2] == "1/s" and lines["mujoco.stiffness"][2] == "1/s^2"
    assert cli.main([*common, "--engine", "drake", "--json"]) == 0  # JSON carries the units too
    units = json.loads(capsys.readouterr().out)["units"]
    assert units["point_contact_stiffness"] == "N/m" and units["hunt_crossley_dissipation"] == "s/m"
    assert cli.main([*common, "--engine", "pybullet"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("pybullet.pair_damping"))
    assert line.endswith("N s/m")


def test_result_is_frozen_and_plain_data_for_json():
    from contactalpha.parameters.result import as_plain_data

    cp = ca.contact_parameters(e_N=0.5, mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=G)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cp.damping = 1.0  # type: ignore[misc]
    data = json.loads(json.dumps(as_plain_data(ca.contact_parameters(
        e_N=[0.5, 0.6], mass=0.5, stiffness=1.4e8, approach_speed=0.5, accel=G))))  # fmt: skip
    assert data["ok"] == [True, True] and len(data["engines"]["exudyn"]["restitutionCoefficient"]) == 2


def test_batch_integrates_its_impacts_only_when_read():
    # The damping and the engine blocks come at the table's speed; each row's impact is integrated
    # on the first read of a field that needs it, and gives what one scene's call gives.
    import numpy as np

    import contactalpha as ca
    from contactalpha.parameters.result import Deferred

    e = np.array([0.3, 0.6, 0.9])
    cp = ca.contact_parameters(
        e_N=e, mass=0.5, stiffness=1e4, approach_speed=1.0, accel=9.81, engine="mujoco"
    )
    lazy = ("eps", "e_n", "end_state", "e_n_half_speed", "e_n_twice_speed")
    assert all(type(object.__getattribute__(cp, name)) is Deferred for name in lazy)
    assert cp.block["solref"].shape == (3, 2)  # the engine's block does not need them
    assert all(type(object.__getattribute__(cp, name)) is Deferred for name in lazy)
    for i, target in enumerate(e):
        one = ca.contact_parameters(e_N=float(target), mass=0.5, stiffness=1e4, approach_speed=1.0,
                                    accel=9.81, engine="mujoco")  # fmt: skip
        assert cp.e_n[i] == pytest.approx(one.e_n, abs=1e-8)
        assert cp.eps[i] == pytest.approx(one.eps, abs=1e-8)
        assert cp.end_state[i] == one.end_state
        assert cp.e_n_half_speed[i] == pytest.approx(one.e_n_half_speed, abs=1e-7)
    assert type(object.__getattribute__(cp, "eps")) is not Deferred
