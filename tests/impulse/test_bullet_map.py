"""PyBullet's rigid contact with restitution as a map: closed forms, the inverse, the front door.

The engine itself is in ``test_bullet_engine.py`` (integration).
"""

import math

import numpy as np
import pytest

import contactalpha as ca
from contactalpha.adapters.pybullet_impulse import block
from contactalpha.impulse import bullet_map as bm
from contactalpha.impulse.delivered import drop_bullet, phase_stats
from contactalpha.impulse.inverse import restitution_for, threshold_for

H = 1.0 / 240.0
R = 0.05
NO_LOAD = 1e-12  # "without gravity": a load too small to move anything within a drop


def _zero_gravity_e_n(e, v, phase):
    """e_N of a touchdown at ``phase`` without a load, worked by hand from Bullet's row.

    Contact point within the breaking threshold: one step, ``w' = e v - d / h`` (the speculative
    row takes out the gap d = z0 + slop).  Beyond it: a free step into the plane, then
    ``w' = e v - erp d / h`` with d = z0 - h v + slop < 0.
    """
    z0 = phase * H * v
    if z0 < 0.02 * math.sqrt(3.0) * R:
        return e - (z0 + bm.LINEAR_SLOP) / (H * v)
    return e - bm.CONTACT_ERP * (z0 - H * v + bm.LINEAR_SLOP) / (H * v)


@pytest.mark.parametrize("phase", [1e-9, 0.25, 0.5, 0.8])
@pytest.mark.parametrize("e, v", [(0.5, 1.0), (0.8, 0.6)])
def test_without_gravity_the_rebound_moves_with_the_phase(e, v, phase):
    got, steps, status = drop_bullet(bm.make_params(e, R), H, phase, v, NO_LOAD, 10_000)
    assert status == 0 and steps == 1
    assert got == pytest.approx(_zero_gravity_e_n(e, v, phase), abs=1e-9)


def test_the_issues_phases():
    """0.498, 0.248, 0.540 at phases 0, 0.25, 0.5 for a coefficient of 0.5 (issue 46)."""
    got = [drop_bullet(bm.make_params(0.5, R), H, ph, 1.0, NO_LOAD, 100)[0] for ph in (1e-9, 0.25, 0.5)]
    assert np.round(got, 3).tolist() == [0.498, 0.248, 0.540]


def test_phase_mean_against_random_phases():
    """The midpoint mean against drops at 20,000 random phases (their standard error about 1e-3)."""
    p = bm.make_params(0.55, R)
    mean = phase_stats(p, H, 1.0, 9.81).mean
    rng = np.random.default_rng(46)
    drops = [drop_bullet(p, H, ph, 1.0, 9.81, 10_000)[0] for ph in rng.random(20_000)]
    assert mean == pytest.approx(np.mean(drops), abs=3.5e-3)


@pytest.mark.parametrize("target, v, a", [(0.5, 1.0, 9.81), (0.3, 0.8, 58.86), (0.8, 2.0, 9.81)])
def test_restitution_for_meets_the_target_and_rises(target, v, a):
    ans = restitution_for(target, H, v, a, R)
    # where a phase switches between bouncing and captured the mean jumps by one drop's e_N / 4096
    assert ans.status == "ok" and ans.stats.mean == pytest.approx(target, abs=2e-4)
    below = phase_stats(bm.make_params(0.9 * ans.restitution, R), H, v, a).mean
    assert below < target


def test_an_unreachable_target_says_so():
    ans = restitution_for(0.5, H, 0.1, 9.81, R)  # below PyBullet's 0.2 m/s threshold: never bounces
    assert ans.status == "unreachable" and math.isnan(ans.restitution) and ans.nearest == 0.0


def test_threshold_is_the_critical_speed_plus_half_a_step_of_load():
    assert threshold_for(0.3, H, 9.81) == pytest.approx(0.3 + 0.5 * 9.81 * H, rel=1e-15)
    assert threshold_for(0.0, H, 9.81) == 0.0


def test_each_body_gets_the_square_root():
    b = block(0.25, 0.1)
    assert b["restitution"] ** 2 == pytest.approx(0.25) and b["pair_restitution"] == 0.25


def test_front_door_scalar():
    scene = dict(mass=0.5, stiffness=1e7, approach_speed=1.0, accel=9.81)
    cp = ca.contact_parameters(e_N=0.5, **scene, engine="pybullet_impulse", timestep="default")
    blk, st = cp.block, cp.stepped
    assert st.status == "ok" and st.mean == pytest.approx(0.5, abs=1e-6)
    assert blk["restitution"] ** 2 == pytest.approx(blk["pair_restitution"], rel=1e-12)
    continuous = ca.contact_parameters(e_N=0.5, **scene)
    v_c = ca.critical_speed(continuous.eps, 0.5, 1e7, 9.81)
    assert blk["critical_speed"] == pytest.approx(v_c, rel=1e-9)
    assert blk["restitutionVelocityThreshold"] == pytest.approx(v_c + 0.5 * 9.81 * H, rel=1e-9)
    assert st.minimum < 0.5 < st.maximum and st.continuous_mean != pytest.approx(0.5, abs=1e-3)


def test_front_door_batch_is_its_rows():
    kw = dict(mass=0.5, stiffness=1e7, accel=9.81, engine="pybullet_impulse", timestep=H)
    cp = ca.contact_parameters(e_N=[0.3, 0.7], approach_speed=[1.0, 2.0], **kw)
    for i, (e, v) in enumerate([(0.3, 1.0), (0.7, 2.0)]):
        one = ca.contact_parameters(e_N=e, approach_speed=v, **kw)
        assert cp.block["pair_restitution"][i] == pytest.approx(one.block["pair_restitution"], rel=1e-12)
        assert cp.stepped.mean[i] == pytest.approx(one.stepped.mean, rel=1e-12)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(timestep="coarse"), "timestep"),
        (dict(timestep=-1.0), "timestep"),
        (dict(accel=0.0), "load"),
    ],
)
def test_front_door_refuses(kw, match):
    args = dict(e_N=0.5, mass=0.5, stiffness=1e7, approach_speed=1.0, accel=9.81, engine="pybullet_impulse")
    with pytest.raises(ValueError, match=match):
        ca.contact_parameters(**{**args, **kw})


@pytest.mark.parametrize("engine", ["pybullet_impulse", "physx"])
def test_cli_prints_the_front_doors_block(engine, capsys):
    import json

    from contactalpha import cli

    scene = dict(e_N=0.6, mass=0.3, stiffness=1e7, approach_speed=1.2, accel=9.81, radius=0.05)
    args = [
        "params",
        "--e-n",
        "0.6",
        "--mass",
        "0.3",
        "--stiffness",
        "1e7",
        "--speed",
        "1.2",
        "--accel",
        "9.81",
    ]
    assert cli.main([*args, "--radius", "0.05", "--engine", engine, "--timestep", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)["parameters"]
    block = ca.contact_parameters(**scene, engine=engine, timestep="default").block
    assert printed.keys() == block.keys()
    for name, value in block.items():
        assert printed[name] == pytest.approx(value, rel=1e-15), name
