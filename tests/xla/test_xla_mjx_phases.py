"""The phase-mean answer at MuJoCo's default 2 ms step, in MJX: one world per touchdown phase.

``contact_parameters(..., engine="mujoco", timestep=0.002)`` gives the solref whose e_N, averaged
over a uniformly random touchdown phase, is the target (``parameters.at_step``), and the range one
drop sees.  In MJX, 128 worlds per scene start at the midpoints of 128 equal phase intervals of a
step (all scenes in one batched rollout): each world's e_N is the MuJoCo map's at its phase
(``stepping.mujoco_map``), their mean is the target, and they stay inside the predicted range.
"""

import numpy as np
import pytest

pytestmark = pytest.mark.integration

STEP = 0.002
PHASES = (np.arange(128) + 0.5) / 128
# (mass kg, stiffness N/m, speed m/s, load m/s^2, target e_N)
SCENES = [
    (0.5, 1e4, 0.5, 9.81, 0.5),
    (0.2, 2e3, 0.3, 20.0, 0.3),
    (2.0, 1e5, 2.0, 5.0, 0.8),
    (0.1, 5e3, 1.5, 30.0, 0.6),
]


def test_mjx_phase_mean_is_the_target_and_each_phase_the_map(jax, mjx):
    from contactalpha.parameters.front_door import contact_parameters
    from contactalpha.stepping.delivered import at_phases
    from contactalpha.stepping.registry import stepper
    from contactalpha.xla import mjx_drop

    answers, blocks = [], []
    for m, k, v, a, e in SCENES:
        scene = {"mass": m, "stiffness": k, "approach_speed": v, "accel": a, "e_N": e}
        cp = contact_parameters(**scene, engine="mujoco", timestep=STEP)
        assert cp.stepped.status == "ok"
        answers.append(cp.stepped)
        blocks.append(cp.engines["mujoco"])
    n = len(PHASES)
    per_world = lambda values: np.repeat(np.asarray(values, dtype=float), n, axis=0)  # noqa: E731
    mass, k, v, a, target = (per_world([s[i] for s in SCENES]) for i in range(5))
    nstep = int(3.0 * 2.0 * np.pi / np.sqrt(min(s[1] / s[0] for s in SCENES)) / STEP) + 4
    h = np.full(mass.size, STEP)
    z, w = mjx_drop.rollout(
        mjx_drop.base_model(0.9), mass, a, v, per_world([b["solref"] for b in blocks]),
        per_world([b["solimp"] for b in blocks]), h, nstep, phase=np.tile(PHASES, len(SCENES)),
    )  # fmt: skip
    got = mjx_drop.delivered_e_n(z, w, a, h, v).reshape(len(SCENES), n)
    for i, (ans, block, (m, _, speed, accel, goal)) in enumerate(zip(answers, blocks, SCENES, strict=True)):
        p = stepper("mujoco").from_block(block, m, None)
        mapped = at_phases("mujoco", p, STEP, PHASES, speed, accel)["e_n"]
        np.testing.assert_allclose(got[i], mapped, rtol=1e-9, atol=1e-12)  # MJX steps as the map
        assert abs(got[i].mean() - goal) <= 1e-3
        assert ans.minimum <= got[i].min() and got[i].max() <= ans.maximum
        span = ans.maximum - ans.minimum
        assert span > 0.05  # the phase matters at 2 ms
        assert got[i].min() - ans.minimum <= 0.05 * span and ans.maximum - got[i].max() <= 0.05 * span
