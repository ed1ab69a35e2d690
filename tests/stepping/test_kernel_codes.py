"""An engine's kernel code selects its own map, compiled apart; an unknown code is refused, never run."""

import math

import numpy as np
import pytest
from numba import njit
from numba.core.caching import FunctionCache
from numba.core.registry import CPUDispatcher

from contactalpha.stepping import drake_map, drop, kernels, mujoco_map, pybullet_map
from contactalpha.stepping.affine_phase import phase_mean_affine_kernel
from contactalpha.stepping.batch_inverse import rows_kernel, solve_rows
from contactalpha.stepping.codes import D_EN, D_STATUS, NON_FINITE
from contactalpha.stepping.registry import STEPPERS, stepper

UNKNOWN = max(kernels.MAPS) + 1
# Every engine's own map functions, by engine (the functions a copy for another engine must not reach).
MAP_FUNCTIONS = {
    "mujoco": {mujoco_map.step_mujoco, mujoco_map.branches_mujoco, mujoco_map.branch_mujoco},
    "pybullet": {pybullet_map.step_pybullet, pybullet_map.branches_pybullet, pybullet_map.branch_pybullet,
                 pybullet_map.surface_pybullet},
    "drake": {drake_map.step_drake},
}  # fmt: skip


def _reached(dispatcher, seen=None):
    """Every function a kernel's source can call: its globals' dispatchers, transitively."""
    seen = set() if seen is None else seen
    fn = getattr(dispatcher, "py_func", dispatcher)
    for name in fn.__code__.co_names:
        value = fn.__globals__.get(name)
        if isinstance(value, CPUDispatcher) and value not in seen:
            seen.add(value)
            _reached(value, seen)
    return seen


def test_the_map_table_and_the_registry_agree():
    assert {s.code for s in STEPPERS} == set(kernels.MAPS)
    for s in STEPPERS:
        assert kernels.MAPS[s.code].name == s.name
        assert s.affine == kernels.MAPS[s.code].affine


@pytest.mark.parametrize(
    "call",
    [
        lambda c, p: drop.run_drop(c, p, 0.002, 0.3, 0.5, 9.81, 1000),
        lambda c, p: drop.run_drops(c, p, 0.002, np.array([0.3]), 0.5, 9.81, 1000),
        lambda c, p: drop.trajectory(c, p, 0.002, 0.3, 0.5, 9.81, 10),
        lambda c, p: kernels.step_map(c, -1e-3, -0.5, p, 0.002, 9.81),
        lambda c, p: kernels.surface(c, p),
    ],
)
def test_an_unknown_code_is_refused_naming_the_valid_ones(call):
    p = stepper("mujoco").pack(stiffness=4e4, damping=80.0, impedance=0.9)
    valid = r"0 \(mujoco\), 1 \(pybullet\), 2 \(drake\)"
    with pytest.raises(
        ValueError, match=rf"kernel code = {UNKNOWN} is not an engine's map; the valid codes are {valid}"
    ):
        call(UNKNOWN, p)


def test_a_map_without_branches_is_refused_by_the_affine_kernels():
    """Drake's step is not piecewise affine: its code never reaches another engine's branches."""
    s = stepper("drake")
    p = np.ones(len(s.slots))
    forms, maps = np.zeros((kernels.MAX_FORMS, 3)), np.zeros((kernels.MAX_BRANCHES, 6))
    with pytest.raises(
        ValueError, match=r"kernel code = 2 \(drake\) has no piecewise-affine map; valid: 0 \(mujoco\), 1"
    ):
        kernels.branches(s.code, p, 1e-3, 9.81, forms, maps)
    with pytest.raises(ValueError, match="has no piecewise-affine map"):
        kernels.branch_of(s.code, np.zeros(kernels.MAX_FORMS))
    args = (np.ones((1, len(s.slots))), np.array([2]), 1e-3, *(np.ones(1),) * 5, np.array([1000]))
    with pytest.raises(ValueError, match="has no piecewise-affine map"):
        solve_rows(s.code, *args)


def test_a_copy_given_another_code_fails_with_nan_never_runs_that_map():
    """Inside compiled code a copy checks the code: MuJoCo's drop kernel given PyBullet's code is a
    non-finite failure, not MuJoCo's (or PyBullet's) e_N."""
    p = stepper("mujoco").pack(stiffness=4e4, damping=80.0, impedance=0.9)
    own = kernels.for_engine(kernels.MUJOCO, drop.drop_kernel)
    assert math.isfinite(own(kernels.MUJOCO, p, 0.002, 0.3, 0.5, 9.81, 1000)[D_EN])
    row = own(kernels.PYBULLET, p, 0.002, 0.3, 0.5, 9.81, 1000)
    assert math.isnan(row[D_EN]) and row[D_STATUS] == NON_FINITE


@pytest.mark.parametrize("template", [drop.drop_kernel, rows_kernel, phase_mean_affine_kernel])
@pytest.mark.parametrize("engine", [s.name for s in STEPPERS])
def test_each_engines_kernel_reaches_its_own_map_only(engine, template):
    """A first call compiles what its source can call: the copy for one engine never names another's map."""
    s = stepper(engine)
    if template is not drop.drop_kernel and not s.affine:
        return
    reached = _reached(kernels.for_engine(s.code, template))
    assert reached & MAP_FUNCTIONS[engine]
    for other, functions in MAP_FUNCTIONS.items():
        if other != engine:
            assert not reached & functions, f"{engine}'s {template.__name__} reaches {other}'s map"


def test_the_engines_drops_are_their_own_copies():
    """``drop_<engine>`` is one compiled kernel per engine, cached apart under its own name."""
    names = {stepper(n).drop.py_func.__qualname__ for n in ("mujoco", "pybullet", "drake")}
    assert names == {"engine_drop__mujoco", "engine_drop__pybullet", "engine_drop__drake"}
    assert all(isinstance(stepper(n).drop._cache, FunctionCache) for n in ("mujoco", "pybullet", "drake"))


@njit(cache=True)
def step_spring(z, w, p, h, accel):
    """A map registered here: a linear spring ``p[0] = k / m`` below z = 0, semi-implicit Euler."""
    w1 = w + h * ((-p[0] * z if z < 0.0 else 0.0) - accel)
    return z + h * w1, w1


@pytest.fixture
def maps_restored(monkeypatch):
    """This process's map table, restored after the test (the codes handed out stay used)."""
    monkeypatch.setattr(kernels, "MAPS", dict(kernels.MAPS))
    monkeypatch.setattr(kernels, "AFFINE", dict(kernels.AFFINE))


def test_a_registered_map_runs_on_a_fresh_code_in_its_own_copies(maps_restored):
    before = dict(kernels.MAPS)
    m = kernels.register_map("spring", step_spring)
    other = kernels.register_map("spring_two", step_spring)
    assert m.code not in before and m.code > max(before) and other.code > m.code
    assert kernels.engine_map(m.code) is m and not m.affine and m.cached
    assert m.tag.startswith(f"spring_{m.code}_")
    p, h, a = np.array([4e4]), 1e-3, 9.81
    for z, w in [(-1e-3, -0.3), (2e-3, 0.1)]:
        assert kernels.step_map(m.code, z, w, p, h, a) == step_spring(z, w, p, h, a)
    # The drop kernel's copy: the registered map only, and the rebound of a drop stepped here.
    copy = kernels.for_engine(m.code, drop.drop_kernel)
    reached = _reached(copy)
    assert step_spring in reached and not reached & set().union(*MAP_FUNCTIONS.values())
    row = drop.run_drop(m.code, p, h, 0.0, 0.5, a, 10_000)
    z, w = 0.0, -0.5 + 0.5 * a * h  # touchdown at phase 0: z = 0, the stored velocity the step's mean
    touched = False
    while not (touched and z > 0.0):
        w += h * ((-p[0] * z if z < 0.0 else 0.0) - a)
        z += h * w
        touched |= z < 0.0
    s = w - 0.5 * a * h
    assert row[D_EN] == pytest.approx(math.sqrt(s * s + 2.0 * a * z) / 0.5, rel=1e-12)
    # Given another code the copy fails with NaN; the built-in maps keep their own steps.
    assert math.isnan(copy(kernels.MUJOCO, p, h, 0.0, 0.5, a, 10_000)[D_EN])
    q = stepper("mujoco").pack(stiffness=4e4, damping=80.0, impedance=0.9)
    z, w = -1e-3, -0.3
    assert kernels.step_map(kernels.MUJOCO, z, w, q, h, a) == mujoco_map.step_mujoco(z, w, q, h, a)


def test_an_unregistered_code_stays_refused_after_registrations(maps_restored):
    m = kernels.register_map("spring", step_spring)
    unknown = max(kernels.MAPS) + 1
    refused = rf"kernel code = {unknown} is not an engine's map.*{m.code} \(spring\)"
    with pytest.raises(ValueError, match=refused):
        kernels.step_map(unknown, 0.0, 0.0, np.ones(1), 1e-3, 9.81)
    with pytest.raises(ValueError, match=rf"kernel code = {m.code} \(spring\) has no piecewise-affine map"):
        kernels.branch_of(m.code, np.zeros(kernels.MAX_FORMS))


@pytest.mark.parametrize(
    ("name", "extra", "why"),
    [
        ("mujoco", {}, "'mujoco' is registered already, with kernel code 0"),
        ("two words", {}, "is not an identifier"),
        ("spring", {"branches": step_spring}, "an affine map needs branches, branch"),
        ("spring", {"branches": step_spring, "branch": step_spring, "n_forms": 99, "n_branches": 2},
         "n_forms = 99.*at most"),
    ],
)  # fmt: skip
def test_register_map_refuses_a_name_taken_or_a_map_the_kernels_cannot_hold(maps_restored, name, extra, why):
    before = dict(kernels.MAPS)
    with pytest.raises(ValueError, match=why):
        kernels.register_map(name, step_spring, **extra)
    assert kernels.MAPS == before
