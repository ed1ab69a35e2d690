"""Each input is checked once, where it enters a public function (issue 32, item 6).

The inner layers (the law's scales, the adapters' blocks, the batch rows) take the checked
values.  Counted here: calls of ``contactalpha.validation``'s checks (and the batch's
``check_rows``), the outermost call only, keyed by the argument's name.  A bad value still
gets an error naming the argument, its value and the valid range from every public entry.
"""

import collections
import functools
import sys

import numpy as np
import pytest

from contactalpha import validation
from contactalpha.adapters.registry import ENGINE_NAMES
from contactalpha.cli import main
from contactalpha.laws import get_law
from contactalpha.parameters import checks as batch_checks
from contactalpha.parameters.front_door import contact_parameters
from contactalpha.parameters.impulse import is_impulse

SCENE = {"e_N": 0.5, "mass": 0.5, "stiffness": 2e4, "approach_speed": 0.5, "accel": 9.81}
INPUTS = ("approach_speed", "mass", "stiffness", "e_N", "accel")
# The checks' own names for an argument they do not take by name.
FIXED_NAMES = {
    "check_eps": "eps",
    "check_xi": "xi",
    "check_alpha": "alpha",
    "check_restitution": "restitution",
}
# Every public way to ask: the default law, each engine, a law by name.
# The impulse engines are left out: their door (parameters.impulse) checks the scene again when it
# solves the loaded contact's critical speed, and a batch row by row (a known deviation).
ROUTES = [{}] + [{"engine": e} for e in ENGINE_NAMES if not is_impulse(e)] + [{"law": "mujoco_soft"}]


def _route_id(route):
    return "default" if not route else "=".join(*route.items())


@pytest.fixture
def counted(monkeypatch):
    """A Counter of checks per argument name, filled while the test runs."""
    counts = collections.Counter()
    depth = [0]

    def counting(fn, fixed):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            # The stepping layer's public entry points check their own inputs: the front door's
            # statement at an engine's step calls them (``params --engine`` prints it).
            caller = sys._getframe(1).f_globals.get("__name__", "")
            if depth[0] == 0 and not caller.startswith("contactalpha.stepping"):
                counts[fixed or (args[0] if args and isinstance(args[0], str) else fn.__name__)] += 1
            depth[0] += 1
            try:
                return fn(*args, **kwargs)
            finally:
                depth[0] -= 1

        return wrapper

    checks = {
        fn: counting(fn, FIXED_NAMES.get(name))
        for name, fn in vars(validation).items()
        if callable(fn) and (name.startswith("check_") or name in ("plain_in", "as_real"))
    }
    checks[batch_checks.check_rows] = counting(batch_checks.check_rows, None)
    for module in [m for name, m in sys.modules.items() if name.startswith("contactalpha")]:
        for attr, value in list(vars(module).items()):
            if callable(value) and value in checks:
                monkeypatch.setattr(module, attr, checks[value])
    return counts


def _read_every_field(cp):
    """Read the batch's deferred fields too: what they compute belongs to the call."""
    for field in ("eps", "e_n", "end_state", "e_n_half_speed", "e_n_twice_speed"):
        getattr(cp, field)


@pytest.mark.parametrize("route", ROUTES, ids=_route_id)
def test_scalar_call_checks_each_input_once(counted, route):
    contact_parameters(**SCENE, **route)
    assert {name: counted[name] for name in INPUTS} == dict.fromkeys(INPUTS, 1)
    assert counted["xi"] == counted["A"] == 0  # derived inside: never re-checked


@pytest.mark.parametrize("route", ROUTES, ids=_route_id)
def test_batch_checks_each_input_once(counted, route):
    rng = np.random.default_rng(3)
    scenes = dict(SCENE, e_N=rng.uniform(0.3, 0.9, 100), mass=rng.uniform(0.1, 1.0, 100))
    _read_every_field(contact_parameters(**scenes, **route))
    assert {name: counted[name] for name in INPUTS} == dict.fromkeys(INPUTS, 1)
    assert counted["xi"] == counted["A"] == 0


@pytest.mark.parametrize("batch", [False, True], ids=["scalar", "batch"])
def test_force_and_eps_are_checked_once(counted, batch):
    scene = {"eps": 0.5, "mass": 0.5, "stiffness": 2e4, "approach_speed": 0.5, "force": 4.0}
    if batch:
        scene["mass"] = np.full(10, 0.5)
    _read_every_field(contact_parameters(**scene, engine="mujoco"))
    names = ("approach_speed", "mass", "stiffness", "eps", "force")
    assert {name: counted[name] for name in names} == dict.fromkeys(names, 1)
    assert counted["accel"] == 0  # derived from the checked force and mass: not checked again


BAD = [("mass", -1.0, r"\(0\.0, inf\)"), ("approach_speed", 0.0, r"\(0\.0, inf\)"),
       ("stiffness", float("inf"), r"\(0\.0, inf\)"), ("accel", -2.0, r"\[0\.0, inf\)"),
       ("e_N", 1.5, r"\[0\.0, 1\.0\]")]  # fmt: skip


@pytest.mark.parametrize(("name", "bad", "valid"), BAD, ids=[b[0] for b in BAD])
@pytest.mark.parametrize("route", ROUTES, ids=_route_id)
def test_a_bad_input_is_named_with_its_range(route, name, bad, valid):
    with pytest.raises(ValueError, match=rf"^{name} = {bad!r} is outside the valid range {valid}"):
        contact_parameters(**dict(SCENE, **{name: bad}), **route)


@pytest.mark.parametrize(("name", "bad", "valid"), BAD, ids=[b[0] for b in BAD])
def test_a_bad_row_is_named_with_its_index(name, bad, valid):
    rows = np.full(3, SCENE[name])
    rows[1] = bad
    with pytest.raises(ValueError, match=rf"^{name}\[1\] = {bad!r} is outside the valid range"):
        contact_parameters(**dict(SCENE, **{name: rows}), engine="mujoco")


@pytest.mark.parametrize(("name", "bad", "valid"), BAD[:3], ids=[b[0] for b in BAD[:3]])
def test_the_law_methods_still_check(name, bad, valid):
    law = get_law("mujoco_soft")
    scene = {"mass": 0.5, "stiffness": 2e4, "approach_speed": 0.5, name: bad}
    message = rf"^{name} = {bad!r} is outside the valid range {valid}"
    for call in (
        lambda: law.length_scale(**scene),
        lambda: law.load(**scene, accel=9.81),
        lambda: law.scene_load_factor(**scene, accel=9.81),
        lambda: law.physical_damping(0.2, **scene),
        lambda: law.damping_from_physical(0.2, **scene),
    ):
        with pytest.raises(ValueError, match=message):
            call()
    with pytest.raises(ValueError, match=r"^accel = -1\.0 is outside the valid range \[0\.0, inf\)"):
        law.load(0.5, 2e4, 0.5, -1.0)


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_cli_names_a_bad_speed(engine, capsys):
    argv = ["params", "--engine", engine, "--e-n", "0.5", "--mass", "0.5", "--stiffness", "2e4",
            "--speed=-0.5", "--accel", "9.81"]  # fmt: skip
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and "approach_speed = -0.5 is outside the valid range (0.0, inf)" in err[0]


def test_critical_speed_of_a_law_checks_each_input_once(counted):
    from contactalpha.scene.threshold import critical_speed

    critical_speed(np.array([0.4, 0.7]), 0.5, 2e4, 9.81, law="mujoco_soft")
    names = ("eps", "mass", "stiffness", "accel", "check_tolerances", "check_max_steps")
    assert {name: counted[name] for name in names} == dict.fromkeys(names, 1)


def test_advise_on_a_law_checks_the_scene_once(counted):
    from contactalpha.scene.advisor import advise

    advise(0.5, 0.5, 2e4, 0.5, accel=9.81, law="mujoco_soft")
    names = ("approach_speed", "mass", "stiffness", "accel")
    assert {name: counted[name] for name in names} == dict.fromkeys(names, 1)


@pytest.mark.parametrize("load", [("--accel", "accel"), ("--force", "force")], ids=["accel", "force"])
def test_cli_params_engine_checks_each_input_once(counted, load, capsys):
    option, name = load
    argv = ["params", "--engine", "mujoco", "--e-n", "0.5", "--mass", "0.5", "--stiffness", "2e4",
            "--speed", "0.5", option, "4.3"]  # fmt: skip
    assert main(argv) == 0
    names = ("approach_speed", "mass", "stiffness", "e_N", name)
    assert {n: counted[n] for n in names} == dict.fromkeys(names, 1)
    assert "solref" in capsys.readouterr().out
