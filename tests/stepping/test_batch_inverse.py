"""The batch inverse at the step: each row's mean is the target by the drop-by-drop quadrature."""

import math

import numba
import numpy as np
import pytest

from contactalpha import contact_parameters
from contactalpha.stepping.batch_inverse import (
    B_DAMPING,
    B_GUESS_MEAN,
    B_MEAN,
    B_NEAREST,
    B_OK,
    B_STATUS,
    B_UNREACHABLE,
    solve_rows,
)
from contactalpha.stepping.delivered import over_phase, step_limit
from contactalpha.stepping.inverse import BRACKET_START, MEAN_TOL, damping_for
from contactalpha.stepping.registry import stepper

H = {"mujoco": 0.002, "pybullet": 1.0 / 240.0}


def _rows(engine, n, seed, guess_noise=0.1):
    """Random scenes of ``engine`` at its default step: ``solve_rows``'s arguments."""
    s = stepper(engine)
    h = H[engine]
    rng = np.random.default_rng(seed)
    m = np.exp(rng.uniform(np.log(0.05), np.log(10.0), n))
    k = m * (math.pi / (rng.uniform(8.0, 60.0, n) * h)) ** 2
    c = 2.0 * rng.uniform(0.05, 0.6, n) * np.sqrt(k * m) * np.exp(rng.normal(0.0, guess_noise, n))
    if engine == "mujoco":
        params = s.pack(stiffness=1.0, damping=1.0, impedance=0.95) * np.ones((n, 1))
        params[:, 0], params[:, 1] = k / m, c / m
    else:
        params = np.array([s.pack(mass=mi, stiffness_ball=2 * ki, damping_ball=ci / 2,
                                  stiffness_ground=2 * ki, damping_ground=ci / 2, breaking=1.7e-3)
                           for mi, ki, ci in zip(m, k, c, strict=True)])  # fmt: skip
    v = rng.uniform(0.2, 2.5, n)
    a = 9.81 * (1.0 + rng.uniform(0.0, 5.0, n) * (rng.uniform(size=n) < 0.5))
    e = rng.uniform(0.1, 0.9, n)
    guess = params[:, s.damping_slots[0]].copy()
    args = (s.code, params, np.array(s.damping_slots), h, v, a, e, guess,
            BRACKET_START / s.contact_time(params.T), step_limit(s, params.T, h))  # fmt: skip
    return s, args


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_each_row_delivers_its_target_by_the_drop_by_drop_quadrature(engine):
    """Every "ok" row's damping, evaluated by ``over_phase`` (drops at adaptive nodes, not the
    polynomial sweep), has the target mean within MEAN_TOL; the row's own mean agrees with it."""
    s, args = _rows(engine, 24, 4)
    out = solve_rows(*args)
    code, params, slots, h, v, a, e = args[:7]
    ok = np.flatnonzero(out[:, B_STATUS] == B_OK)
    assert ok.size >= 12
    for i in ok:
        p = params[i].copy()
        p[list(slots)] = out[i, B_DAMPING]
        mean = over_phase(engine, p, h, v[i], a[i]).mean
        assert abs(mean - e[i]) <= MEAN_TOL
        assert out[i, B_MEAN] == pytest.approx(mean, abs=1e-11)
        q = params[i].copy()  # the guess's row: what the given damping delivers
        assert out[i, B_GUESS_MEAN] == pytest.approx(over_phase(engine, q, h, v[i], a[i]).mean, abs=1e-11)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_rows_agree_with_the_one_scene_inverse(engine):
    """``damping_for`` (its own ladder, Brent on the drop-by-drop mean) finds the same status, the same
    damping (to 1e-5, both means within MEAN_TOL) and, out of reach, the same nearest mean."""
    s, args = _rows(engine, 12, 9)
    out = solve_rows(*args)
    code, params, slots, h, v, a, e = args[:7]
    statuses = set()
    for i in range(len(e)):
        ref = damping_for(engine, params[i], h, v[i], a[i], e[i], remedies=False)
        statuses.add(ref.status)
        assert ref.status == {B_OK: "ok", B_UNREACHABLE: "unreachable"}[int(out[i, B_STATUS])]
        if ref.status == "ok":
            assert out[i, B_DAMPING] == pytest.approx(ref.damping, rel=1e-5)
        else:
            assert out[i, B_NEAREST] == pytest.approx(ref.nearest, abs=1e-11)
    assert "ok" in statuses


def test_out_of_reach_rows_say_so_with_the_nearest_mean():
    """PyBullet at 1/240 s cannot deliver 0.95 with a soft contact: unreachable, NaN damping, the
    nearest mean is zero damping's mean."""
    s, args = _rows("pybullet", 6, 2)
    code, params, slots, h, v, a, e = args[:7]
    e = np.full_like(e, 0.97)
    out = solve_rows(*args[:6], e, *args[7:])
    assert (out[:, B_STATUS] == B_UNREACHABLE).all()
    assert np.isnan(out[:, B_DAMPING]).all()
    for i in range(len(e)):
        p = params[i].copy()
        p[list(slots)] = 0.0
        assert out[i, B_NEAREST] == pytest.approx(over_phase("pybullet", p, h, v[i], a[i]).mean, abs=1e-11)


def test_the_same_bits_at_any_thread_count_and_chunking():
    """Rows never depend on each other: one thread, two threads, the batch in two halves agree bit for bit."""
    _, args = _rows("mujoco", 40, 13)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = solve_rows(*args)
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        two = solve_rows(*args)
    finally:
        numba.set_num_threads(before)
    half = [solve_rows(*(x[sl] if isinstance(x, np.ndarray) and x.shape[:1] == (40,) else x for x in args))
            for sl in (slice(0, 17), slice(17, 40))]  # fmt: skip
    assert np.array_equal(one, two, equal_nan=True)
    assert np.array_equal(one, np.vstack(half), equal_nan=True)


@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_the_front_door_batch_is_exact_row_by_row(engine):
    """``contact_parameters`` with arrays at the engine's step: each ok row's block, read back into
    the map's parameters, delivers its target by ``over_phase``; a scene too slow to fly a step
    has no answer and says why."""
    s = stepper(engine)
    h = H[engine]
    rng = np.random.default_rng(17)
    n = 10
    m = np.exp(rng.uniform(np.log(0.05), np.log(5.0), n))
    k = m * (math.pi / (rng.uniform(10.0, 50.0, n) * h)) ** 2
    v = rng.uniform(0.3, 2.0, n)
    v[-1] = 0.45 * 9.81 * h  # slower than accel * h / 2
    e = rng.uniform(0.2, 0.8, n)
    radius = 0.05 if s.needs_radius else None
    cp = contact_parameters(mass=m, stiffness=k, approach_speed=v, accel=9.81, e_N=e, engine=engine,
                            timestep=h, radius=radius)  # fmt: skip
    st = cp.stepped
    assert not cp.ok[-1]
    # MuJoCo's law has a continuous answer there, which the step cannot use; the spring-dashpot's
    # force floor has none that slow.
    assert ("accel * timestep / 2" if engine == "mujoco" else "no continuous answer") in st.status[-1]
    block = cp.engines[engine]
    checked = 0
    for i in np.flatnonzero(st.status == "ok"):
        row = {key: (tuple(float(np.ravel(x)[i]) for x in val) if isinstance(val, tuple)
                     else tuple(float(x) for x in val[i]) if np.ndim(val) == 2  # a row per world
                     else (float(np.ravel(val)[i]) if isinstance(val, np.ndarray) else val))
               for key, val in block.items()}  # fmt: skip
        p = s.from_block(row, float(m[i]), radius)
        assert abs(over_phase(engine, p, h, v[i], 9.81).mean - e[i]) <= MEAN_TOL
        assert st.mean_error[i] <= MEAN_TOL and st.source[i] == "exact"
        checked += 1
    assert checked >= 5
