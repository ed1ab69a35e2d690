"""Every registered engine adapter keeps the contract, and the check catches one that does not."""

import importlib.util
import inspect
from dataclasses import replace

import numpy as np
import pytest

from contactalpha.adapters.contract import (
    DATA_PARTS,
    METHOD_PARTS,
    DropScene,
    EngineAdapter,
    array_problem,
    check_adapter,
    missing_parts,
    signature_differs,
)
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.record import (
    PARTS,
    Engine,
    ModelFile,
    Ref,
    Tuner,
    check_engine,
    record_problems,
    resolved,
)
from contactalpha.adapters.registry import (
    ADAPTERS,
    ENGINE_NAMES,
    ENGINES,
    adapter,
    batched_blocks,
    engine,
    model_readers,
    tuners,
)
from contactalpha.laws import LAWS, get_law
from contactalpha.stepping.registry import STEPPERS, stepper

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


class _MathSqrtMuJoCo(type(adapter("mujoco"))):
    """MuJoCo's adapter with ``parameters`` written with ``math.sqrt``: it breaks on arrays."""

    def parameters(self, damping, scene, settings=None):
        import math

        omega = math.sqrt(scene.stiffness / scene.mass)
        return {"damping": 2.0 * damping * omega}


class _BatchMeanMuJoCo(type(adapter("mujoco"))):
    """An adapter whose batch is not each scene's own (one shared mean)."""

    def parameters(self, damping, scene, settings=None):
        return {"damping": np.mean(2.0 * np.asarray(damping) * np.sqrt(scene.stiffness / scene.mass))}


@pytest.mark.parametrize("broken", [_MathSqrtMuJoCo, _BatchMeanMuJoCo], ids=["math.sqrt", "batch mean"])
def test_parameters_that_do_not_take_arrays_are_refused(broken):
    """The batched front door passes arrays of scenes: ``parameters`` must answer each row as alone."""
    assert array_problem(broken())
    assert missing_parts(broken()) == ["parameters"]
    with pytest.raises(TypeError, match=r"parameters.*(numpy arrays|not each scene's own)"):
        check_adapter(broken())


@pytest.mark.parametrize("e", ENGINES, ids=ENGINE_NAMES)
def test_every_record_keeps_its_contract_and_its_refs_resolve(e):
    assert check_engine(e) is e and record_problems(e) == []
    assert e.adapter.module == e.loader.module and e.units == dict(e.adapter.units)
    if e.step_map is not None:
        assert stepper(e.name) is e.step_map  # the built-in maps are stepping's own entries
    if e.model_file is not None:
        if e.model_file.reader is not None:
            assert callable(resolved(e.model_file.reader))
        if e.model_file.tuner is not None:
            tuner = resolved(e.model_file.tuner)
            assert isinstance(tuner, Tuner) and tuner.name == e.name
    for block in (e.batched or {}).values():
        if isinstance(block, Ref) and importlib.util.find_spec("jax") is None:
            continue  # xla's blocks need JAX to import
        assert callable(resolved(block))


def test_the_tables_keyed_by_engine_are_the_records():
    """tune's readers and tuners, stepping's maps and xla's blocks: each one the records say."""
    reading = importlib.import_module("contactalpha.mechanism.reading")
    tuning = importlib.import_module("contactalpha.mechanism.tuners")
    files = importlib.import_module("contactalpha.mechanism.robot_files")
    loops = importlib.import_module("contactalpha.mechanism.loops")

    assert [r.name for r in reading.READERS] == [
        e.name for e in ENGINES if e.model_file is not None and e.model_file.reader is not None
    ]
    assert [r.suffixes for r in reading.READERS] == [model_readers()[r.name][1] for r in reading.READERS]
    assert {row[0]: row[1:] for row in files.ENGINE_ORDER} == {
        e.name: (e.loader.module, e.model_file.opens, e.model_file.refused_meshes)
        for e in ENGINES
        if e.model_file is not None and e.model_file.tuner is not None
    }
    assert set(loops.LOOPS) == set(tuners())  # every engine tune writes for has its loop's record
    assert (
        tuning.TUNER_NAMES
        == tuple(tuners())
        == tuple(e.name for e in ENGINES if e.model_file is not None and e.model_file.tuner is not None)
    )
    assert {s.name for s in STEPPERS} == {e.name for e in ENGINES if e.step_map is not None}
    try:
        from contactalpha.xla import engines
    except ImportError:  # the batched blocks are JAX's: checked where JAX is installed
        return
    assert set(batched_blocks()) == {name for e in ENGINES for name in (e.batched or {})}
    assert engines.BLOCKS == {n: b for n, (law, b) in batched_blocks().items() if law == engines.LAW}


@pytest.mark.parametrize("part", PARTS)
def test_a_record_without_a_part_names_it(part):
    given = {p: getattr(ENGINES[0], p) for p in PARTS if p != part}
    with pytest.raises(TypeError, match=part):
        Engine(**given)


def test_a_record_with_a_wrong_part_names_it():
    e = engine("mujoco")
    with pytest.raises(TypeError, match="step_map"):
        check_engine(replace(e, step_map=stepper("drake")))
    with pytest.raises(TypeError, match="loader"):
        check_engine(replace(e, loader=engine("drake").loader))
    with pytest.raises(TypeError, match="model_file"):
        check_engine(replace(e, model_file=ModelFile(suffixes=(), reader=e.model_file.reader, tuner=None)))
    with pytest.raises(TypeError, match="batched"):
        check_engine(replace(e, batched={"mjx": 1.0}))
    with pytest.raises(TypeError, match=r"adapter: .*parameters"):
        check_engine(replace(e, adapter=_MathSqrtMuJoCo()))
    with pytest.raises(ImportError, match="no 'read_nothing'"):
        Ref("contactalpha.mechanism.mujoco_model:read_nothing").get()


def test_a_missing_engine_says_the_one_install_hint():
    missing = Loader("Nothing", ("contactalpha_no_such_engine",), "no-such-engine")
    assert not missing.installed()
    with pytest.raises(ImportError, match=r"Nothing is an optional engine: pip install no-such-engine"):
        missing.load()
    for e in ENGINES:
        assert e.loader.hint.startswith(
            f"{e.loader.label} is an optional engine: pip install {e.loader.package} "
        )
