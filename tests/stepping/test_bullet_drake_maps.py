"""The PyBullet and Drake step maps, checked without the engines.

- Drake: the step's end velocity is the root of the momentum balance with Hunt-Crossley at the
  step's end, found here by SciPy's ``brentq`` on that equation written out again.
- PyBullet: in penetration the impulse is the implicit spring-dashpot ``-h (k z' + c w')`` at the
  step's end, in the speculative row ``-(h k + c) z'``, and no impulse beyond the breaking
  threshold: identities of the algebra that the map's ERP/CFM form must reproduce.
- Both: the engines' combining rules, and the continuous law (SciPy's DOP853 reference of
  tests/laws) approached at first order as the step shrinks.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from contactalpha.stepping import drake_map as dm
from contactalpha.stepping import pybullet_map as pm
from contactalpha.stepping.codes import CAPTURED, SEPARATED, STEP_LIMIT
from contactalpha.stepping.drop import drop_drake, drop_pybullet

sys.path.insert(0, str(Path(__file__).parents[1] / "laws"))
from scipy_reference import reference_impact  # noqa: E402


def drake_root(z, w, m, k, d, h, a):
    """The end velocity by brentq on m (w' - w + h a) = h k (-(z + h w'))_+ (1 - d w')_+."""

    def g(v):
        return m * (v - w + h * a) - h * k * max(0.0, -(z + h * v)) * max(0.0, 1.0 - d * v)

    if z > 0.0:
        return w - h * a
    lo, hi = w - h * a - 10.0, w - h * a + 10.0 + abs(z) / h
    return brentq(g, lo, hi, xtol=1e-15, rtol=1e-15)


@pytest.mark.parametrize("d", [0.0, 0.3, 5.0, 200.0])
@pytest.mark.parametrize("z", [1e-3, 0.0, -1e-5, -2e-3, -0.05])
@pytest.mark.parametrize("w", [-2.0, -0.3, 0.0, 0.4, 3.0])
def test_drake_step_solves_the_momentum_balance(d, z, w):
    m, k, h, a = 0.7, 3e4, 1e-3, 12.0
    p = dm.make_params(m, 2 * k, d, 2 * k, d)
    z1, w1 = dm.step_drake(z, w, p, h, a)
    ref = drake_root(z, w, m, k, d, h, a)
    assert w1 == pytest.approx(ref, rel=1e-12, abs=1e-13)
    assert z1 == z + h * w1


def test_drake_combines_the_geometries_like_drake():
    p = dm.make_params(1.0, 3e5, 2.0, 1e5, 0.5)
    k, d = dm.pair_values(p)
    assert k == pytest.approx(3e5 * 1e5 / 4e5, rel=1e-15)
    assert d == pytest.approx((1e5 * 2.0 + 3e5 * 0.5) / 4e5, rel=1e-15)
    assert dm.pair_values(dm.make_params(1.0, 0.0, 1.0, 0.0, 1.0)) == (0.0, 0.0)


@pytest.mark.parametrize("z", [-0.02, -1e-4, 0.0])
@pytest.mark.parametrize("w", [-1.5, -0.1, 0.05])
def test_pybullet_penetrating_step_is_the_implicit_spring_dashpot(z, w):
    m, k, c, h, a = 0.4, 5e3, 3.0, 1.0 / 240.0, 9.81
    p = pm.make_params(m, 2 * k, 0.5 * c, 2 * k, 0.5 * c, 0.05)
    z1, w1 = pm.step_pybullet(z, w, p, h, a)
    impulse = m * (w1 - w + h * a)
    assert impulse == pytest.approx(max(0.0, -h * (k * z1 + c * w1)), rel=1e-12, abs=1e-14)
    assert impulse >= 0.0


def test_pybullet_speculative_row_and_breaking_threshold():
    m, k, c, h, a, r = 0.4, 5e3, 3.0, 1.0 / 240.0, 9.81, 0.05
    p = pm.make_params(m, 2 * k, 0.5 * c, 2 * k, 0.5 * c, r)
    edge = 0.02 * math.sqrt(3.0) * r + pm.LINEAR_SLOP
    z = 0.5 * edge  # inside the threshold, above the surface, falling through it in one step
    z1, w1 = pm.step_pybullet(z, -1.0, p, h, a)
    assert m * (w1 + 1.0 + h * a) == pytest.approx(-(h * k + c) * z1, rel=1e-12)
    z1, w1 = pm.step_pybullet(1.01 * edge, -1.0, p, h, a)  # beyond it: free flight
    assert w1 == -1.0 - h * a
    z1, w1 = pm.step_pybullet(0.99 * edge, -1.0, p, h, a)
    assert w1 > -1.0 - h * a


def test_pybullet_contact_point_edge_includes_the_linear_slop():
    # The manifold keeps a point below the breaking threshold plus Bullet's 1e-5 m linear slop: half
    # a slop inside that edge the row acts, half a slop outside it the step is free flight (issue 44:
    # 0.99 and 1.01 of the edge lie on the same side with or without the slop).
    m, k, c, h, a, r = 0.4, 5e3, 3.0, 1.0 / 240.0, 9.81, 0.05
    p = pm.make_params(m, 2 * k, 0.5 * c, 2 * k, 0.5 * c, r)
    edge = 0.02 * math.sqrt(3.0) * r + 1e-5  # gContactBreakingThreshold sqrt(3) r, plus PyBullet's slop
    free = -1.0 - h * a
    z1, w1 = pm.step_pybullet(edge - 0.5e-5, -1.0, p, h, a)
    assert w1 > free  # the speculative row pushes: this step would end below the surface
    assert m * (w1 - free) == pytest.approx(-(h * k + c) * z1, rel=1e-12)  # as the row's target says
    z1, w1 = pm.step_pybullet(edge + 0.5e-5, -1.0, p, h, a)
    assert w1 == free


def test_pybullet_combines_the_bodies_like_bullet():
    p = pm.make_params(1.0, 3e5, 2.0, pm.UNSET_STIFFNESS, pm.UNSET_DAMPING, 0.05)
    k, c = pm.pair_values(p)
    assert k == pytest.approx(3e5, rel=1e-12) and c == pytest.approx(2.1, rel=1e-15)
    p = pm.make_params(1.0, 3e5, 2.0, 1e5, 0.5, 0.05)
    k, c = pm.pair_values(p)
    assert k == pytest.approx(1.0 / (1.0 / 3e5 + 1.0 / 1e5), rel=1e-15) and c == 2.5


def scaled_drop(drop, p, h, A):
    """e_N over 8 phases of the scaled drop (m = k = v_in = 1, load A): (mean, spread)."""
    e = np.array([drop(p, h, i / 8, 1.0, A, 10**8)[0] for i in range(8)])
    return e.mean(), np.ptp(e)


@pytest.mark.parametrize(
    ("law", "damping", "A"), [("kelvin_voigt", 0.3, 0.1), ("hunt_crossley_linear", 0.4, 0.2)]
)
def test_maps_approach_the_continuous_law_at_first_order(law, damping, A):
    eps_ref, e_ref, state = reference_impact(law, damping, A)
    assert state == "separation"
    errors = []
    for h in (1e-2, 1e-3, 1e-4):
        if law == "kelvin_voigt":
            p = pm.make_params(1.0, 2.0, damping, 2.0, damping, 1.0)  # pair k = 1, c = 2 zeta
            p[pm.SLOP] = 0.0
            e, _ = scaled_drop(drop_pybullet, p, h, A)
        else:
            p = dm.make_params(1.0, 2.0, damping, 2.0, damping)  # pair k = 1, d = alpha / v_in
            e, _ = scaled_drop(drop_drake, p, h, A)
        errors.append(abs(e - e_ref))
    assert errors[-1] < 2e-4  # measured 7.6e-5 (KV, the science's 0.348) and 1.3e-4 (HC)
    for coarse, fine in zip(errors, errors[1:], strict=False):
        assert 0.08 < fine / coarse < 0.12  # first order: a tenth of the step, a tenth of the error


def test_drop_statuses():
    p = dm.make_params(1.0, 2.0, 0.0, 2.0, 0.0)
    e, n, status = drop_drake(p, 1e-2, 0.3, 1.0, 0.1, 10**6)
    assert status == SEPARATED and 0.9 < e < 1.0 and n > 100
    e, n, status = drop_drake(p, 1e-2, 0.3, 1.0, 0.1, 20)
    assert status == STEP_LIMIT and math.isnan(e)
    p = dm.make_params(1.0, 2.0, 50.0, 2.0, 50.0)
    e, n, status = drop_drake(p, 1e-2, 0.3, 1.0, 2.0, 10**6)
    assert status == CAPTURED and e == 0.0
    p = pm.make_params(1.0, 2.0, 5.0, 2.0, 5.0, 1.0)
    e, n, status = drop_pybullet(p, 1e-2, 0.3, 1.0, 2.0, 10**6)
    assert status == CAPTURED and e == 0.0


def piecewise_reference(s, p, v, a):
    """The phase mean by SciPy's quad between the phases where the forced steps change (bisection)."""
    from scipy.integrate import quad

    from contactalpha.stepping.drop import run_drop

    def row(x):
        return run_drop(s.code, p, s.timestep, x, v, a, 10**6)

    grid = np.linspace(1e-300, np.nextafter(1.0, 0.0), 2049)
    counts = [row(x)[2] for x in grid]
    cuts = [(grid[0], grid[0])]
    for lo, hi, n_lo, n_hi in zip(grid, grid[1:], counts, counts[1:], strict=False):
        if n_lo != n_hi:
            for _ in range(200):
                m = 0.5 * (lo + hi)
                if m <= lo or m >= hi:
                    break
                lo, hi = (m, hi) if row(m)[2] == n_lo else (lo, m)
            cuts.append((lo, hi))
    cuts.append((grid[-1], grid[-1]))
    return sum(
        quad(lambda x: row(x)[0], a0[1], b0[0], epsabs=1e-15, epsrel=1e-13, limit=400)[0]
        for a0, b0 in zip(cuts, cuts[1:], strict=False)
    )


@pytest.mark.parametrize(
    ("engine", "values", "v"),
    [
        # fast enough that the contact point appears inside the last free step at some phases:
        # e_N jumps there (by 0.31) without a change of the steps that start below the surface
        ("pybullet", {"mass": 2.0, "stiffness_ball": 4e5, "damping_ball": 0.0,
                      "stiffness_ground": pm.UNSET_STIFFNESS, "damping_ground": pm.UNSET_DAMPING,
                      "breaking": pm.breaking_threshold(0.05)}, 2.5),
        # Drake counts contact at z = 0: touchdown exactly at a step's start is the limit from phase 1
        ("drake", {"mass": 0.5, "stiffness_ball": 2e4, "dissipation_ball": 0.2, "stiffness_ground": 2e4,
                   "dissipation_ground": 0.2}, 0.5),
    ],
)  # fmt: skip
def test_phase_mean_of_the_maps_across_their_jumps(engine, values, v):
    from contactalpha.stepping.delivered import over_phase
    from contactalpha.stepping.registry import stepper

    s = stepper(engine)
    p = s.pack(**values)
    st = over_phase(engine, p, s.timestep, v, 9.81)
    assert st.status == "ok"
    # SciPy's quad between the bisected jumps: 1.1e-12 from both exact means (6e-16 apart) in
    # PyBullet's scene read at the geometric surface
    assert st.mean == pytest.approx(piecewise_reference(s, p, v, 9.81), abs=2e-12)
