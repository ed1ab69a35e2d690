"""Every registered engine adapter keeps the contract, and the check catches one that does not."""

import inspect

import pytest

from contactalpha.adapters.contract import (
    DATA_PARTS,
    METHOD_PARTS,
    DropScene,
    EngineAdapter,
    check_adapter,
    missing_parts,
    signature_differs,
)
from contactalpha.adapters.registry import ADAPTERS, ENGINE_NAMES, adapter
from contactalpha.laws import LAWS, get_law

SCENE = DropScene(0.5, 1.0e4, 0.5, force=5.1)


@pytest.mark.parametrize("a", ADAPTERS, ids=ENGINE_NAMES)
def test_registered_adapter_keeps_the_contract(a):
    assert isinstance(a, EngineAdapter)
    assert missing_parts(a) == []
    assert a.law in LAWS or a.law.name == "mujoco_soft"
    assert get_law(a.law.name).exponent == a.law.exponent


@pytest.mark.parametrize("a", ADAPTERS, ids=ENGINE_NAMES)
def test_parameters_are_numbers_in_the_engines_names(a):
    params = a.parameters(0.3, SCENE)
    assert params and all(isinstance(k, str) for k in params)
    flat = [v for x in params.values() for v in (x if isinstance(x, tuple) else (x,))]
    assert all(isinstance(v, (int, float)) for v in flat)


@pytest.mark.parametrize("part", DATA_PARTS + METHOD_PARTS)
def test_an_adapter_missing_any_part_is_refused(part):
    class Partial:
        pass

    full = ADAPTERS[0]
    for name in DATA_PARTS + METHOD_PARTS:
        if name != part:
            setattr(Partial, name, getattr(full, name))
    assert missing_parts(Partial()) == [part]
    with pytest.raises(TypeError, match=part):
        check_adapter(Partial())


def test_registry_names_are_unique_and_looked_up():
    assert len(set(ENGINE_NAMES)) == len(ENGINE_NAMES) == len(ADAPTERS)
    for a in ADAPTERS:
        assert adapter(a.name) is a
    with pytest.raises(ValueError, match="valid choices"):
        adapter("no_such_engine")


def test_the_protocol_holds_every_part_callers_use():
    """``delivered`` and ``calibrate`` (the engines study, ``params --refine``) are in the contract."""
    assert {"delivered", "calibrate", "parameters", "law_damping"} <= set(METHOD_PARTS)
    protocol = {n for n in vars(EngineAdapter) if not n.startswith("_")}
    assert set(METHOD_PARTS) == protocol - set(DATA_PARTS)


@pytest.mark.parametrize("a", ADAPTERS, ids=ENGINE_NAMES)
@pytest.mark.parametrize("part", METHOD_PARTS)
def test_registered_methods_take_the_protocols_arguments(a, part):
    want = list(inspect.signature(getattr(EngineAdapter, part)).parameters)[1:]
    have = list(inspect.signature(getattr(a, part)).parameters)
    assert have[: len(want)] == want
    assert not signature_differs(getattr(a, part), part)


@pytest.mark.parametrize(
    "wrong",
    [
        "def calibrate(self, scene, target): pass",  # start and settings missing
        "def calibrate(self, target, scene, start=None, settings=None): pass",  # order swapped
        "def calibrate(self, scene, target, start, settings=None): pass",  # no default for start
        "def calibrate(self, scene, target, start=None, settings=None, *, tol): pass",  # a required extra
    ],
)
def test_a_method_with_another_signature_is_refused(wrong):
    namespace = {}
    exec(wrong, namespace)  # noqa: S102 - the test's own source

    class Wrong(type(ADAPTERS[0])):
        calibrate = namespace["calibrate"]

    assert missing_parts(Wrong()) == ["calibrate"]
    with pytest.raises(TypeError, match="calibrate"):
        check_adapter(Wrong())


def test_parameters_convert_as_documented():
    """The conversions, each against its engine's stated rule (not the adapter's code path)."""
    m, k, v, zeta, alpha = SCENE.mass, SCENE.stiffness, SCENE.approach_speed, 0.3, 0.7
    mj = adapter("mujoco").parameters(zeta, SCENE)
    assert mj["solref"] == pytest.approx((-k / m, -2 * zeta * (k / m) ** 0.5), rel=1e-15)
    assert mj["timeconst"] == pytest.approx(1 / (zeta * (k / m) ** 0.5), rel=1e-15)
    dk = adapter("drake").parameters(alpha, SCENE)
    k1 = k2 = dk["point_contact_stiffness"]
    d1 = d2 = dk["hunt_crossley_dissipation"]
    assert k1 * k2 / (k1 + k2) == pytest.approx(k, rel=1e-15)
    assert (k2 * d1 + k1 * d2) / (k1 + k2) == pytest.approx(alpha / v, rel=1e-15)
    pb = adapter("pybullet").parameters(zeta, SCENE)
    s = pb["contactStiffness"]
    assert 1 / (1 / s + 1 / s) == pytest.approx(k, rel=1e-15)
    assert 2 * pb["contactDamping"] == pytest.approx(2 * zeta * (k * m) ** 0.5, rel=1e-15)
