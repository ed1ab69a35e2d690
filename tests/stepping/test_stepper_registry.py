"""The steppers' registry: capabilities, parameter packing, the kernel table."""

import numpy as np
import pytest

from contactalpha.adapters.contract import DropScene
from contactalpha.adapters.registry import adapter
from contactalpha.stepping import drake_map, kernels, pybullet_map
from contactalpha.stepping.drop import drop_mujoco, run_drop
from contactalpha.stepping.mujoco_map import DAMPING, IMPEDANCE, STIFFNESS, step_mujoco
from contactalpha.stepping.registry import STEPPER_NAMES, STEPPERS, stepper


def test_every_stepper_names_its_capabilities():
    assert len(set(STEPPER_NAMES)) == len(STEPPERS)
    for s in STEPPERS:
        assert s.timestep > 0 and s.integrators and s.source
        assert s.damping_slots and all(0 <= k < len(s.slots) for k in s.damping_slots)
        assert all(0 <= k < len(s.slots) for k in s.stiffness_slots)


def test_pack_fills_defaults_and_names_bad_slots():
    s = stepper("mujoco")
    p = s.pack(stiffness=4e4, damping=80.0, impedance=0.9)
    assert p[STIFFNESS] == 4e4 and p[DAMPING] == 80.0 and p[IMPEDANCE] == 0.9
    assert s.unpack(p)["diag_ratio"] == 1.0
    with pytest.raises(ValueError, match="impedance"):
        s.pack(stiffness=4e4, damping=80.0)
    with pytest.raises(ValueError, match="solref"):
        s.pack(stiffness=4e4, damping=80.0, impedance=0.9, solref=1.0)
    with pytest.raises(ValueError, match="valid choices"):
        stepper("bullet")


def test_the_table_dispatches_to_the_engines_step():
    p = stepper("mujoco").pack(stiffness=4e4, damping=80.0, impedance=0.9)
    for z, w in [(-1e-3, -0.3), (2e-3, 0.1), (-2e-4, 0.4)]:
        assert kernels.step_map(kernels.MUJOCO, z, w, p, 0.002, 9.81) == step_mujoco(z, w, p, 0.002, 9.81)


def test_the_interface_drop_is_the_generic_drop():
    p = stepper("mujoco").pack(stiffness=4e4, damping=80.0, impedance=0.9)
    e, n, status = drop_mujoco(p, 0.002, 0.3, 0.5, 9.81, 10_000)
    row = run_drop(kernels.MUJOCO, p, 0.002, 0.3, 0.5, 9.81, 10_000)
    assert (e, n, status) == (row[0], int(row[2]), int(row[4]))
    assert status == 0 and 0.4 < e < 0.7 and 5 <= n <= 10


def _front_door_samples(s):
    """Two scenes of any engine's map through its front door (its block of ``contact_parameters``)."""
    a = adapter(s.name)
    scenes = [DropScene(0.5, 0.5 * (np.pi / (n * s.timestep)) ** 2, 1.0, radius=0.05) for n in (8, 30)]
    return [s.from_block(a.parameters(0.3, scene), scene.mass, scene.radius) for scene in scenes]


MJ = stepper("mujoco")
# Hand-made samples for the maps that have them; any other map's come through its front door.
SAMPLES = {
    "mujoco": [MJ.pack(stiffness=k, damping=c, impedance=0.9) for k, c in [(4e4, 80), (5e3, 300)]],
    "pybullet": [pybullet_map.make_params(0.5, 2 * k, c, 2 * k, c, 0.05) for k, c in [(2e4, 4), (1e3, 20)]],
    "drake": [drake_map.make_params(0.5, 2 * k, d, 2 * k, d) for k, d in [(2e4, 0.5), (1e3, 5.0)]],
}


@pytest.mark.parametrize("s", STEPPERS, ids=STEPPER_NAMES)
def test_every_steppers_drop_agrees_with_the_generic_drop(s):
    """The engine's own drop and ``run_drop`` on its map: the same e_N and status at 256 phases.

    MuJoCo's overdamped sample creeps until the step limit, where both call it captured (the same
    status at any limit: 10^4 steps keep every other drop whole)."""
    seen = set()
    for p in SAMPLES.get(s.name) or _front_door_samples(s):
        for v, a in [(0.5, 9.81), (0.05, 29.81)]:
            for phase in np.arange(256) / 256:
                e, _, status = s.drop(p, s.timestep, phase, v, a, 10**4)
                row = run_drop(s.code, p, s.timestep, phase, v, a, 10**4)
                assert status == int(row[4])
                assert e == row[0] or (np.isnan(e) and np.isnan(row[0]))
                seen.add(status)
    assert 0 in seen  # bounces are among the cases


def test_step_mujoco_against_hand_arithmetic():
    """One step in penetration, worked by hand from MuJoCo's formulas (mj_makeImpedance, aref)."""
    k, b, d, h, a = 4e4, 80.0, 0.9, 0.002, 9.81
    p = stepper("mujoco").pack(stiffness=k, damping=b, impedance=d)
    z, w = -1e-3, -0.3
    aref = -(b / d) * w - (k / d**2) * d * z
    r = (1 - d) / d
    qacc = -a + max(0.0, (a + aref) / (1 + r))
    w1 = w + h * qacc
    assert np.allclose(step_mujoco(z, w, p, h, a), (z + h * w1, w1), rtol=1e-15, atol=0)
    # Above the surface: free flight.
    assert step_mujoco(1e-3, -0.3, p, h, a) == (1e-3 + h * (-0.3 - h * a), -0.3 - h * a)


def test_a_stepper_joins_the_registry_only_on_its_own_registered_map(monkeypatch):
    """``register``: a run-time map's stepper is found by name; a code that runs no map or another
    engine's, or a name taken, is refused naming it."""
    from dataclasses import replace

    from contactalpha.stepping import registry

    for name in ("MAPS", "AFFINE"):
        monkeypatch.setattr(kernels, name, dict(getattr(kernels, name)))
    for name in ("STEPPERS", "STEPPER_NAMES"):
        monkeypatch.setattr(registry, name, getattr(registry, name))
    drake = stepper("drake")
    with pytest.raises(ValueError, match=r"kernel code 2 is 'drake''s step map, not 'spring''s"):
        registry.register(replace(drake, name="spring"))
    unknown = max(kernels.MAPS) + 1
    with pytest.raises(ValueError, match=rf"kernel code {unknown} of 'spring' is not a registered step map"):
        registry.register(replace(drake, name="spring", code=unknown))
    m = kernels.register_map("spring", drake_map.step_drake)
    s = replace(drake, name="spring", code=m.code)
    assert registry.register(s) is s and registry.register(s) is s  # once: the same stepper again is kept
    assert stepper("spring") is s and registry.STEPPER_NAMES[-1] == "spring" and not s.affine
    with pytest.raises(ValueError, match="'spring' is registered already"):
        registry.register(replace(s))
    with pytest.raises(ValueError, match="'drake' is registered already"):
        registry.register(replace(drake))
