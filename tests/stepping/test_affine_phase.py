"""The exact phase mean of the piecewise-affine maps, against drop-by-drop quadrature and dense sampling."""

import math

import numpy as np
import pytest

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import adapter
from contactalpha.stepping import codes
from contactalpha.stepping.affine_phase import phase_mean_affine
from contactalpha.stepping.delivered import at_phases, over_phase, step_limit
from contactalpha.stepping.kernels import (
    AFFINE,
    DRAKE,
    MAX_BRANCHES,
    MAX_FORMS,
    MUJOCO,
    branches,
    step_map,
    surface,
)
from contactalpha.stepping.registry import STEPPERS, stepper


def _mujoco_scene(rng):
    k = 10 ** rng.uniform(2.0, 5.0)
    zeta = rng.uniform(0.0, 1.2)
    p = stepper("mujoco").pack(
        stiffness=k, damping=2.0 * zeta * math.sqrt(k), impedance=rng.uniform(0.8, 0.99)
    )
    return p, 0.002


def _pybullet_scene(rng):
    h = 1.0 / 240.0
    m = 10 ** rng.uniform(-1.5, 1.3)
    k = m * (math.pi / (rng.uniform(5.0, 80.0) * h)) ** 2
    c = 2.0 * rng.uniform(0.0, 1.0) * math.sqrt(k * m)
    values = {"mass": m, "stiffness_ball": 2 * k, "damping_ball": c / 2, "stiffness_ground": 2 * k,
              "damping_ground": c / 2, "breaking": 0.02 * math.sqrt(3) * rng.uniform(0.01, 0.2)}  # fmt: skip
    return stepper("pybullet").pack(**values), h


def _front_door_scene(engine):
    """Random scenes of any engine's map through its front door (5 to 80 steps per contact)."""

    def scene(rng):
        s = stepper(engine)
        m, h = 10 ** rng.uniform(-1.5, 1.3), s.timestep
        k = m * (math.pi / (rng.uniform(5.0, 80.0) * h)) ** 2
        block = adapter(engine).parameters(rng.uniform(0.0, 1.0), DropScene(m, k, 1.0, radius=0.05))
        return s.from_block(block, m, 0.05), h

    return scene


# Hand-made ranges for the maps that have them; any other affine map's scenes come through its
# front door.
SCENES = {"mujoco": _mujoco_scene, "pybullet": _pybullet_scene}
AFFINE_ENGINES = [s.name for s in STEPPERS if s.affine]


def _scenes(engine, n, seed):
    rng = np.random.default_rng(seed)
    make = SCENES.get(engine) or _front_door_scene(engine)
    out = []
    while len(out) < n:
        p, h = make(rng)
        v = 10 ** rng.uniform(-1.3, 0.5)
        a = 9.81 + (rng.uniform(0.0, 200.0) if rng.uniform() < 0.5 else 0.0)
        if v >= 0.5 * a * h:
            out.append((p, h, v, a))
    return out


def test_the_affine_maps_are_the_registered_ones():
    """Each piecewise-affine kernel is a registered map's (Drake's Hunt-Crossley step is not affine)."""
    assert set(AFFINE) == {s.code for s in STEPPERS if s.affine}
    assert len(AFFINE_ENGINES) == len(AFFINE) and MUJOCO in AFFINE and DRAKE not in AFFINE


@pytest.mark.parametrize("engine", AFFINE_ENGINES)
def test_each_branch_is_the_engines_step(engine):
    """At random states, the branch the forms pick, applied as its affine map, is ``step_map``
    (the forms and maps in the height above ``kernels.surface``, the map's z less it)."""
    s = stepper(engine)
    rng = np.random.default_rng(5)
    forms, maps = np.empty((MAX_FORMS, 3)), np.empty((MAX_BRANCHES, 6))
    from contactalpha.stepping.kernels import branch_of

    seen = set()
    for p, h, v, a in _scenes(engine, 40, 6):
        nf = branches(s.code, p, h, a, forms, maps)
        zs = surface(s.code, p)
        for _ in range(25):
            z = rng.uniform(-3.0, 1.0) * v * h
            w = rng.uniform(-1.5, 1.5) * v
            x = z - zs  # the height above the surface, the forms' and maps' coordinate
            vals = forms[:nf, 0] * x + forms[:nf, 1] * w + forms[:nf, 2]
            b = branch_of(s.code, vals)
            seen.add(b)
            z1, w1 = step_map(s.code, z, w, p, h, a)
            z_map = maps[b, 0] * x + maps[b, 1] * w + maps[b, 2]
            assert z_map == pytest.approx(z1 - zs, rel=1e-12, abs=1e-15 * v * h)
            assert maps[b, 3] * x + maps[b, 4] * w + maps[b, 5] == pytest.approx(w1, rel=1e-12, abs=1e-15 * v)
    assert seen == set(range(AFFINE[s.code][1]))  # every branch was exercised


@pytest.mark.parametrize("engine", AFFINE_ENGINES)
def test_the_mean_is_the_drop_by_drop_quadratures(engine):
    """Against ``phase.phase_mean`` (drops at adaptive Gauss-Lobatto nodes, jumps bisected): the mean to
    1e-11, the range one drop sees to 1e-6 (a piece's ends, jumps and kinks, are evaluated exactly; a
    smooth extremum inside a piece only at either rule's nodes), the steps in contact exactly, at 30
    random scenes (less those the next test checks).  (The
    drop-by-drop quadrature runs out of intervals in two captured scenes, on Stronge's eps, whose
    deepest penetration kinks; its e_N there is exact: 0.  A drop at rest in contact is captured when
    rounding flips its velocity's sign, so the steps of captured drops differ with the arithmetic.)"""
    assert _check_against_quadrature(engine, _scenes(engine, 30, 11), mixed=False) >= 29


@pytest.mark.integration
def test_the_mean_is_the_drop_by_drop_quadratures_where_some_phases_run_to_the_step_limit():
    """The scene of the 30 that the test above leaves to the integration run: its drops creep to the
    step limit at some phases and bounce at others, each quadrature node a drop of thousands of steps."""
    assert _check_against_quadrature("mujoco", _scenes("mujoco", 30, 11), mixed=True) == 1


def _check_against_quadrature(engine, scenes, mixed):
    """Check the scenes whose drops run to the step limit at some phases only (``mixed``) or the
    others; return how many were checked."""
    s = stepper(engine)
    checked = 0
    for p, h, v, a in scenes:
        limit = step_limit(s, p, h)
        row = phase_mean_affine(s.code, p, h, v, a, limit, 1e-12)
        if (row[codes.P_STEPS_MIN] < row[codes.P_STEPS_MAX] >= limit - 1) != mixed:
            continue
        checked += 1
        st = over_phase(engine, p, h, v, a)
        assert st.status in ("ok", "quadrature interval limit") and row[codes.P_STATUS] == 0
        assert row[codes.P_MEAN] == pytest.approx(st.mean, abs=1e-11)
        assert row[codes.P_STD] == pytest.approx(st.std, abs=1e-9)
        # The range: the ends of every piece (kinks too, which the quadrature's nodes only approach).
        assert row[codes.P_MIN] == pytest.approx(st.minimum, abs=1e-6)
        assert row[codes.P_MAX] == pytest.approx(st.maximum, abs=1e-6)
        if st.minimum > 0.0:  # a capture's step count is when rounding stops the creep: compare bounces
            assert (row[codes.P_STEPS_MIN], row[codes.P_STEPS_MAX]) == (st.steps_min, st.steps_max)
        assert np.isnan(row[codes.P_EPS_MEAN])  # not computed here
    return checked


@pytest.mark.parametrize("engine", AFFINE_ENGINES)
def test_the_mean_is_dense_samplings(engine):
    """Against 16,384 evenly spaced drops: agreement within the sample's own error at the jumps
    (each jump can move the sample's mean by its size over the count)."""
    s = stepper(engine)
    n = 16_384
    phases = (np.arange(n) + 0.5) / n
    for p, h, v, a in _scenes(engine, 6, 3):
        row = phase_mean_affine(s.code, p, h, v, a, step_limit(s, p, h), 1e-12)
        e = at_phases(engine, p, h, phases, v, a)["e_n"]
        jumps = np.abs(np.diff(e)).max()
        assert abs(row[codes.P_MEAN] - e.mean()) <= max(2.0 * jumps * row[codes.P_EVALS] / n, 1e-9)
        assert row[codes.P_MIN] <= e.min() + 1e-12 and row[codes.P_MAX] >= e.max() - 1e-12


def test_a_quadrature_that_cannot_converge_gives_nan_and_its_status():
    """At omega h = 20 (an unstable explicit step, e_N up to 400) the quadrature runs out of
    intervals before its absolute tolerance: NaN with that status, never the unconverged number."""
    s = stepper("mujoco")
    p = s.pack(stiffness=1e8, damping=0.0, impedance=0.95)
    row = phase_mean_affine(s.code, p, 0.002, 1.0, 9.81, step_limit(s, p, 0.002), 1e-12)
    assert row[codes.P_STATUS] == codes.QUAD_LIMIT
    assert np.isnan(row[codes.P_MEAN]) and np.isnan(row[codes.P_MIN]) and np.isnan(row[codes.P_STD])


def test_running_out_of_steps_gives_nan():
    """A drop still moving when its steps run out: status step limit, NaN mean."""
    s = stepper("mujoco")
    p = s.pack(stiffness=1e4, damping=1.0, impedance=0.95)
    row = phase_mean_affine(s.code, p, 0.002, 1.0, 9.81, 5, 1e-12)
    assert row[codes.P_STATUS] == codes.STEP_LIMIT and np.isnan(row[codes.P_MEAN])


def test_where_the_drop_by_drop_quadrature_runs_out_the_answer_keeps_the_exact_mean():
    """A pushed scene where ``phase_mean`` runs out of intervals and keeps an estimate: the inverse's
    statistics (``inverse._stats``) take the affine mean, which 262,144 evenly spaced drops confirm
    to 1e-6 (that sample's own error at its ten jumps).  (Its estimate was 9e-5 off while short hops
    counted as capture; read as a user reads them, 2e-7.)"""
    from contactalpha.stepping.inverse import _stats

    p = stepper("mujoco").pack(stiffness=3.13086259e5, damping=514.236298, impedance=0.662812474,
                               diag_ratio=1.06712339)  # fmt: skip
    h, v, a = 0.002, 0.14948567105967747, 39.374262773561426
    old = over_phase("mujoco", p, h, v, a)
    n = 2**18
    dense = at_phases("mujoco", p, h, (np.arange(n) + 0.5) / n, v, a)["e_n"].mean()
    st = _stats("mujoco", p, h, v, a, "kinematic")
    assert old.status == "quadrature interval limit"
    assert abs(st.mean - dense) < 1e-6
    exact = phase_mean_affine(MUJOCO, p, h, v, a, step_limit(stepper("mujoco"), p, h), 1e-12)
    assert st.mean == exact[codes.P_MEAN]
    assert st.eps_mean == old.eps_mean  # eps stays drop by drop
