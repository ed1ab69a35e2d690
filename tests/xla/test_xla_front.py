"""The JAX front door against the numba front door, and its blocks for the batched engines."""

import numpy as np
import pytest

from contactalpha.adapters.mujoco_soft import ADAPTER as MUJOCO
from contactalpha.parameters.batch import batched_parameters


def _scenes(n, seed=0):
    rng = np.random.default_rng(seed)
    return {
        "mass": rng.uniform(0.1, 2.0, n),
        "stiffness": 10.0 ** rng.uniform(3.0, 6.0, n),
        "approach_speed": rng.uniform(0.2, 3.0, n),
        "accel": rng.uniform(0.0, 30.0, n),
        "target": rng.uniform(0.05, 0.95, n),
    }


TABLE_LAWS = ["hunt_crossley", "hunt_crossley_linear", "hertz_tsuji", "hertz_tsuji_unfloored"]
TABLE_LAWS += ["hertz_viscoelastic", "hertz_viscoelastic_unfloored"]


@pytest.mark.parametrize("law", TABLE_LAWS)
def test_table_laws_match_the_numba_front_door(jax, law):
    from contactalpha.xla import contact_parameters

    s = _scenes(400)
    got = jax.jit(lambda **kw: contact_parameters(**kw, law=law))(**s)
    ref = batched_parameters(**s, law=law)
    np.testing.assert_array_equal(np.asarray(got["ok"]), ref.ok)
    np.testing.assert_allclose(np.asarray(got["xi"])[ref.ok], ref.xi[ref.ok], rtol=1e-13)
    np.testing.assert_allclose(np.asarray(got["damping"])[ref.ok], ref.damping[ref.ok], rtol=1e-12)
    np.testing.assert_allclose(
        np.asarray(got["physical_damping"])[ref.ok], ref.physical_damping[ref.ok], rtol=1e-12
    )


def test_mujoco_blocks_match_the_adapter(jax):
    """Every MuJoCo-law engine's block against the MuJoCo adapter's own parameters."""
    from contactalpha.parameters.block_scene import BlockScene
    from contactalpha.xla import contact_parameters

    s = _scenes(40, 3)
    s["stiffness"] = 10.0 ** np.linspace(2.0, 7.0, 40)  # timeconst on both sides of 2 steps
    got = contact_parameters(**s, law="mujoco_soft")
    zeta = np.asarray(got["damping"])
    assert np.all(np.isfinite(zeta))
    ref = MUJOCO.parameters(zeta, BlockScene(s["mass"], s["stiffness"], s["approach_speed"], None))
    for name in ("mujoco", "mjx", "mujoco_warp"):
        block = got["engines"][name]
        # the adapter's batch: (n, 2) and (n, 5), the shape MJX and MuJoCo Warp take
        np.testing.assert_allclose(np.asarray(block["solref"]), np.asarray(ref["solref"]), rtol=1e-15)
        np.testing.assert_allclose(np.asarray(block["solimp"])[0], np.asarray(ref["solimp"])[0], rtol=0)
        np.testing.assert_allclose(np.asarray(block["timeconst"]), ref["timeconst"], rtol=1e-15)
    missing = np.isnan(ref["timeconst"])
    assert 0 < missing.sum() < missing.size
    genesis = got["engines"]["genesis"]
    np.testing.assert_array_equal(np.asarray(genesis["needs_direct"]), missing)
    want = np.stack([ref["timeconst"], ref["dampratio"]], -1)[~missing]
    np.testing.assert_allclose(np.asarray(genesis["sol_params"])[~missing, :2], want, rtol=1e-15)


def test_newton_gains_give_mujoco_law(jax):
    """Newton's ke, kd through its solver's gain (1 - d)/m: the direct-mode stiffness and damping."""
    from contactalpha.xla import contact_parameters

    s = _scenes(20, 4)
    got = contact_parameters(**s, law="mujoco_soft")
    newton, mujoco = got["engines"]["newton"], got["engines"]["mujoco"]
    gain = (1.0 - 0.9) / s["mass"]
    np.testing.assert_allclose(
        np.asarray(newton["shape_material_ke"]) * gain, s["stiffness"] / s["mass"], rtol=1e-14
    )
    np.testing.assert_allclose(
        np.asarray(newton["shape_material_kd"]) * gain, np.asarray(mujoco["damping"]), rtol=1e-14
    )


def test_bad_scenes_are_nan_and_flagged(jax):
    from contactalpha.xla import contact_parameters

    got = contact_parameters([1.0, -1.0, 1.0, 1.0], 1e7, 1.0, [9.81, 9.81, 9.81, 1e9], [0.5, 0.5, 0.005, 0.5])
    np.testing.assert_array_equal(np.asarray(got["ok"]), [True, False, False, False])
    assert np.all(np.isnan(np.asarray(got["damping"])[1:]))


def test_gradient_of_the_damping_through_the_front_door(jax):
    """d alpha / d speed by jax.grad against central differences of the numba front door."""
    from contactalpha.xla import contact_parameters

    kw = {"mass": 0.5, "stiffness": 1.4e8, "accel": 9.81, "target": 0.5}
    f = lambda v: contact_parameters(approach_speed=v, **kw)["damping"]  # noqa: E731
    g = float(jax.grad(f)(0.7))
    h = 1e-5
    ref = (batched_parameters(approach_speed=[0.7 + h], **kw).damping[0]
           - batched_parameters(approach_speed=[0.7 - h], **kw).damping[0]) / (2 * h)  # fmt: skip
    assert g == pytest.approx(ref, rel=1e-6)
