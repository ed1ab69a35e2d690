"""Write the synthetic drop tests of this folder (see README.md); deterministic (fixed seeds).

Run from the repository root: PYTHONPATH=src python data/drops/make_drops.py
"""

from pathlib import Path

import numpy as np

from contactalpha.calibration import hypotheses, sequence
from contactalpha.calibration.recovery import SCENES, exact_times

HERE = Path(__file__).resolve().parent
BALL = SCENES[0]  # eps 0.8, k 1e8 N/m^1.5, 50 g, first approach 2 m/s
G = 9.81


def write(name, header, columns):
    """Write one CSV of this folder."""
    rows = np.column_stack(columns)
    lines = [",".join(header)] + [",".join(f"{v:.9f}" for v in row) for row in rows]
    (HERE / name).write_text("\n".join(lines) + "\n")
    print(name, len(rows), "rows")


def main():
    """Write every file."""
    rng = np.random.default_rng(28)
    t = exact_times(BALL)  # the package's own prediction: scene.bounces.predict_bounces
    write("hc_eps_times.csv", ["t (s)"], [t + rng.normal(0.0, 1e-4, t.size)])
    null = sequence.simulate(
        hypotheses.HYPOTHESES["constant_e"], {"e": 0.8, "stiffness": 1e8}, BALL.mass, G, BALL.speed, 0.0, 21
    )
    write("constant_e_times.csv", ["t (s)"], [null.touchdowns + rng.normal(0.0, 1e-4, null.touchdowns.size)])
    hc = sequence.simulate(
        hypotheses.HYPOTHESES["hc_eps"], {"eps": 0.8, "stiffness": 1e8}, BALL.mass, G, BALL.speed, 0.0, 100
    )
    h = np.concatenate([[BALL.speed**2 / (2 * G)], hc.apexes[:11]])
    write("hc_eps_heights.csv", ["h (m)"], [h * np.exp(rng.normal(0.0, 0.01, h.size))])
    ts = np.arange(-0.15, 1.8, 1.0 / 240.0)
    z = sequence.height_at(hc, ts) + rng.normal(0.0, 1e-3, ts.size)
    write("hc_eps_trajectory.csv", ["t (s)", "z (m)"], [ts - ts[0], z])
    try:
        from contactalpha.adapters import opensim_hc
        from contactalpha.scene.ball import Scene
    except ImportError:
        return
    scene = Scene(mass=0.05, radius=0.02, stiffness=1e8, approach_speed=2.0, force=0.0, eps=0.8, t_end=6.0)
    try:
        run = opensim_hc.bounce(scene, per_impact=False, accuracy=1e-8, per_tstar=100, window=12.0, settle=5)
    except ImportError:
        print("OpenSim missing: opensim_times.csv not rewritten")
        return
    write("opensim_times.csv", ["t (s)"], [run["contacts"]["t_touch"][:21]])
    print("OpenSim dissipation c =", run["contacts"]["dissipation"][0], "s/m")


if __name__ == "__main__":
    main()
