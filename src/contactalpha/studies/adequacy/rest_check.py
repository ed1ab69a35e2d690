"""Rest prediction against the time-domain ball simulation on random scenes.

``random_scenes`` draws scenes over wide ranges (``SCENE_RANGES``): mass, stiffness,
first approach speed and the constant acceleration log-uniformly, eps uniformly.
``check_rest_prediction`` runs each with ``scene.bounces.predict_bounces`` (no time
stepping) and ``scene.ball.simulate`` (case A) and compares the contact and bounce
counts and the times to rest.
"""

import time

import numpy as np

from contactalpha.scene.ball import RESTS, Scene, simulate
from contactalpha.scene.bounces import predict_bounces

# Ranges of the random scenes: (low, high, "log" or "linear").  From a 1 g bead to a 1 t
# block, soft rubber to hardened steel contacts, a slow touch to a 10 m/s drop, a tenth of
# lunar gravity to 100 g.
SCENE_RANGES = {
    "mass": (1e-3, 1e3, "log"),
    "stiffness": (1e5, 1e11, "log"),
    "approach_speed": (1e-2, 10.0, "log"),
    "accel": (0.16, 1e3, "log"),
    "eps": (0.05, 0.95, "linear"),
}
# Models the scenes cycle through: the exact alpha (solved, any xi < 1) and a classical one that
# ignores the load (so the check covers both kinds).
CHECK_MODELS = ("exact_solve", "hunt_crossley")
# Simulated time limit: far beyond any rest in these ranges, so every run ends by resting.
T_LIMIT = 1e9


def random_scenes(n, seed=0):
    """``n`` scenes drawn from ``SCENE_RANGES`` with ``numpy.random.default_rng(seed)``.

    The acceleration is put in ``gravity`` (no separate force), the radius is irrelevant.
    """
    rng = np.random.default_rng(seed)
    draws = {}
    for name, (lo, hi, kind) in SCENE_RANGES.items():
        u = rng.random(n)
        draws[name] = np.exp(np.log(lo) + u * np.log(hi / lo)) if kind == "log" else lo + u * (hi - lo)
    return [
        Scene(
            mass=float(draws["mass"][i]),
            stiffness=float(draws["stiffness"][i]),
            approach_speed=float(draws["approach_speed"][i]),
            force=0.0,
            gravity=float(draws["accel"][i]),
            eps=float(draws["eps"][i]),
            t_end=T_LIMIT,
        )
        for i in range(n)
    ]


def check_rest_prediction(scenes, models=CHECK_MODELS):
    """Prediction against simulation, one row per scene (model ``models[i % len(models)]``).

    Returns
    -------
    dict of ndarray
        ``mass, stiffness, approach_speed, accel, eps, model``; ``contacts_predicted``,
        ``contacts_simulated``, ``bounces_predicted``, ``bounces_simulated``,
        ``rest_predicted``, ``rest_simulated`` (s), ``rest_rel_diff``, ``predict_seconds``,
        ``simulate_seconds``, ``simulated_end`` (end state of the run).
    """
    rows = []
    for i, scene in enumerate(scenes):
        model = models[i % len(models)]
        clock = time.perf_counter()
        pred = predict_bounces(scene, model)
        mid = time.perf_counter()
        run = simulate(scene, model, "A", flight_samples=2)
        end = time.perf_counter()
        rest_sim = run.end_time if run.end_state == RESTS else np.nan
        same_inf = np.isinf(pred.time_to_rest) and np.isinf(rest_sim) and pred.time_to_rest == rest_sim
        diff = 0.0 if same_inf else abs(pred.time_to_rest / rest_sim - 1.0)
        rows.append(
            {
                "mass": scene.mass,
                "stiffness": scene.stiffness,
                "approach_speed": scene.approach_speed,
                "accel": scene.accel,
                "eps": scene.eps,
                "model": model,
                "contacts_predicted": pred.contacts,
                "contacts_simulated": run.count,
                "bounces_predicted": pred.bounces,
                "bounces_simulated": run.rebounds,
                "rest_predicted": pred.time_to_rest,
                "rest_simulated": rest_sim,
                "rest_rel_diff": diff,
                "predict_seconds": mid - clock,
                "simulate_seconds": end - mid,
                "simulated_end": run.end_state,
            }
        )
    return {key: np.array([r[key] for r in rows]) for key in rows[0]} if rows else {}
