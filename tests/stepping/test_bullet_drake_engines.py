"""The PyBullet and Drake maps against the engines' own steps (integration: needs the engines).

Ten or eleven scenes per engine (mass 0.02-20 kg, approach speed 0.05-3 m/s, pushes 0-100 N,
contacts of 1 to 43 steps, most bouncing and a few captured, equal and unequal per-body values
so that the engines' combining rules are exercised), each dropped at 8 touchdown phases (80 or
more per engine) through the adapters' own drop
scenes.  From the engine's first stored state the map is stepped alongside the engine over the
whole window (about three undamped periods, free flight after the rebound included), and the
map's ``drop_*`` e_N is compared with the e_N that ``adapters.stepped.measure_steps`` reads
from the engine's own states (the flight parabola after the first free step that starts above
the surface and ends moving up; 0 for a drop that stays in contact).

Tolerances: PyBullet, and Drake with ``tamsi``, 1e-9 of the trajectory's scale (measured: below
2e-12).  Drake's ``lagged`` and ``similar`` are solved by SAP, which stops at a relative momentum
residual of 1e-6 (``SapSolverParameters::rel_tolerance``, not exposed to Python); its Newton steps
usually land far below that: measured one-step errors up to 1e-9 and whole trajectories up to
4e-9 of their scale.  Those are checked within 3e-8.
"""

import numpy as np
import pytest

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.stepped import measure_steps
from contactalpha.stepping import drake_map, pybullet_map
from contactalpha.stepping.drop import drop_drake, drop_pybullet

PHASES = 8
# (mass kg, k_ball N/m, c_ball N s/m, k_plane, c_plane, v_in m/s, push N, radius m)
BULLET_SCENES = [
    (0.5, 900.0, 0.5, 900.0, 0.5, 1.0, 0.0, 0.05),
    (0.02, 8e3, 0.0, 8e3, 0.0, 3.0, 0.0, 0.02),
    (20.0, 4e4, 2.0, 4e4, 2.0, 0.5, 100.0, 0.1),
    (1.0, 4e3, 1.0, 1.2e4, 0.0, 1.5, 10.0, 0.05),
    (0.1, 600.0, 0.05, 600.0, 0.05, 2.0, 0.5, 0.03),
    (5.0, 2e4, 5.0, 1e4, 10.0, 1.0, 50.0, 0.08),
    (0.05, 200.0, 0.0, 200.0, 0.0, 0.5, 0.05, 0.05),
    (2.0, 8e5, 0.0, 8e5, 0.0, 2.5, 0.0, 0.05),
    (0.3, 3e3, 0.2, 3e3, 0.2, 1.2, 5.0, 0.05),
    (10.0, 4e5, 10.0, 4e5, 10.0, 0.05, 0.0, 0.2),
    (10.0, 4e4, 1.0, 4e4, 1.0, 2.0, 100.0, 0.2),
    (0.2, 500.0, 0.05, None, None, 1.0, 1.0, 0.05),  # the plane's values unset: Bullet's defaults
]
# (mass kg, k_ball N/m, d_ball s/m, k_ground, d_ground, v_in m/s, push N)
DRAKE_SCENES = [
    (0.5, 2e4, 0.2, 2e4, 0.2, 0.5, 0.0),
    (0.02, 8e3, 0.0, 8e3, 0.0, 3.0, 0.0),
    (20.0, 4e7, 0.5, 4e7, 0.5, 0.05, 100.0),
    (1.0, 1e5, 1.0, 3e5, 0.0, 1.5, 10.0),
    (0.1, 2e4, 2.0, 2e4, 2.0, 1.0, 2.0),
    (5.0, 2e6, 0.5, 1e6, 1.0, 1.0, 50.0),
    (0.05, 4e3, 1.0, 4e3, 1.0, 0.1, 0.5),
    (2.0, 8e5, 0.1, 8e5, 0.1, 2.5, 0.0),
    (0.3, 6e4, 0.5, 6e4, 0.5, 0.8, 20.0),
    (10.0, 4e6, 3.0, 4e6, 3.0, 0.3, 100.0),
]


def pair_stiffness(k1, k2):
    return k1 * k2 / (k1 + k2)


def lockstep_error(step, p, h, accel, zs, ws):
    """Largest |map - engine| over the steps, relative to the trajectory's scale (z and w apart)."""
    z, w = zs[0], ws[0]
    err = 0.0
    for j in range(1, zs.size):
        z, w = step(z, w, p, h, accel)
        err = max(err, abs(z - zs[j]) / np.abs(zs).max(), abs(w - ws[j]) / np.abs(ws).max())
    return err


def compare(scene, p, drop, step, samples_of, tol_traj, tol_e, surface=0.0):
    """The map against the engine's samples (heights above the surface ``surface`` of the map's z)."""
    samples = samples_of()
    heights, ws = samples.extra["z"], samples.extra["v"]
    zs = heights + surface
    h = samples.extra["timestep"]
    engine_e = []
    for i in range(PHASES):
        assert lockstep_error(step, p, h, scene.accel, zs[i], ws[i]) <= tol_traj
        e, n, status = drop(p, h, i / PHASES, scene.approach_speed, scene.accel, 10**6)
        engine_e.append(measure_steps(heights[i], ws[i], scene.accel, h, scene.approach_speed).e_n)
        assert e == pytest.approx(engine_e[-1], abs=tol_e), (i, status, n)
    return np.array(engine_e)


@pytest.mark.parametrize("row", BULLET_SCENES)
def test_pybullet_map_follows_the_engine_step_by_step(pybullet, row):
    from contactalpha.adapters.pybullet_kv import ADAPTER, PyBulletSettings

    m, k1, c1, k2, c2, v, force, radius = row
    scene = DropScene(m, k1 if k2 is None else pair_stiffness(k1, k2), v, force=force, radius=radius)
    settings = PyBulletSettings(phases=PHASES, window=3.0)

    def samples_of():
        model = ADAPTER.build_drop(
            scene, ADAPTER.parameters(0.0, scene), settings, stiffness_each=(k1, k2), damping_each=(c1, c2)
        )
        return ADAPTER.run(model, scene, settings)

    unset = k2 is None
    p = pybullet_map.make_params(
        m,
        k1,
        c1,
        pybullet_map.UNSET_STIFFNESS if unset else k2,
        pybullet_map.UNSET_DAMPING if unset else c2,
        radius,
    )
    engine_e = compare(scene, p, drop_pybullet, pybullet_map.step_pybullet, samples_of, 1e-9, 1e-9,
                       surface=p[pybullet_map.SLOP])  # fmt: skip
    assert np.all(np.isfinite(engine_e))


@pytest.mark.parametrize("approximation", ["lagged", "similar", "tamsi"])
@pytest.mark.parametrize("row", DRAKE_SCENES)
def test_drake_map_follows_the_discrete_plant_step_by_step(pydrake, row, approximation):
    import warnings

    from contactalpha.adapters.drake_point import ADAPTER, DrakeSettings

    m, k1, d1, k2, d2, v, force = row
    scene = DropScene(m, pair_stiffness(k1, k2), v, force=force)
    settings = DrakeSettings(phases=PHASES, window=3.0, approximation=approximation)

    def samples_of():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)  # TAMSI is deprecated in Drake
            model = ADAPTER.build_drop(
                scene,
                ADAPTER.parameters(0.0, scene),
                settings,
                stiffness_each=(k1, k2),
                dissipation_each=(d1, d2),
            )
        return ADAPTER.run(model, scene, settings)

    p = drake_map.make_params(m, k1, d1, k2, d2)
    tol = 1e-9 if approximation == "tamsi" else 3e-8
    engine_e = compare(scene, p, drop_drake, drake_map.step_drake, samples_of, tol, tol)
    assert np.all(np.isfinite(engine_e))
