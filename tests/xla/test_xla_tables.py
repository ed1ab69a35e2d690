"""The shipped tables on the device agree with the numba lookups and differentiate like differences."""

import numpy as np
import pytest

from contactalpha.engine.table import alpha_tabulated, kinematic_alpha_from_packed
from contactalpha.laws import LAWS
from contactalpha.laws.fast import ENGINE_TABLE
from contactalpha.laws.table import damping_from_packed_as

N = 1500


def _numba(law, e, xi, restitution):
    if law.fast is ENGINE_TABLE:
        return alpha_tabulated(e, xi, restitution=restitution)
    flat = law.fast.packed(law, restitution == "kinematic")
    if restitution == "kinematic":
        return np.array([kinematic_alpha_from_packed(a, b, flat) for a, b in zip(e, xi, strict=True)])
    root = law.fast.root_near_one  # region 0 square-root-like at e = 1 too
    return np.array([damping_from_packed_as(a, b, flat, root) for a, b in zip(e, xi, strict=True)])


@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
def test_device_table_matches_numba(jax, law, restitution):
    from contactalpha.xla.tables import device_table, table_damping

    rng = np.random.default_rng(7)
    e, xi = rng.uniform(0.01, 1.0, N), rng.uniform(0.0, 0.99, N)
    e[:3], xi[3:6] = (0.01, 1.0, 0.5), (0.0, 0.99, 1e-12)  # the domain's edges
    tab = device_table(law, restitution)
    got = np.asarray(jax.jit(lambda e, x: table_damping(tab, e, x))(e, xi))
    ref = _numba(law, e, xi, restitution)
    assert np.all(np.isfinite(ref))
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
def test_outside_the_domain_is_nan(jax, law):
    from contactalpha.xla.tables import device_table, table_damping

    tab = device_table(law, "energetic")
    got = np.asarray(table_damping(tab, [0.005, 1.2, 0.5, 0.5, np.nan], [0.5, 0.5, -0.1, 0.995, 0.5]))
    assert np.all(np.isnan(got))
    assert float(table_damping(tab, 1.0, 0.3)) == 0.0


@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
@pytest.mark.parametrize("law", [LAWS[0], LAWS[4]], ids=lambda law: law.name)
def test_table_gradient_matches_finite_differences(jax, law, restitution):
    """jax.grad in both arguments against central differences of the numba lookup, off the cuts."""
    from contactalpha.xla.tables import device_table, table_damping

    rng = np.random.default_rng(3)
    e, xi = rng.uniform(0.05, 0.95, 300), rng.uniform(0.02, 0.95, 300)
    tab = device_table(law, restitution)
    f = jax.vmap(jax.grad(lambda e, x: table_damping(tab, e, x), argnums=(0, 1)))
    de, dx = (np.asarray(a) for a in f(e, xi))
    checked = 0
    for h in (1e-5,):
        fd_e = (_numba(law, e + h, xi, restitution) - _numba(law, e - h, xi, restitution)) / (2 * h)
        fd_x = (_numba(law, e, xi + h, restitution) - _numba(law, e, xi - h, restitution)) / (2 * h)
        # Off the kinks: where halving the step moves the difference quotient by under 1e-7 relative.
        h2 = h / 2
        fd_e2 = (_numba(law, e + h2, xi, restitution) - _numba(law, e - h2, xi, restitution)) / (2 * h2)
        smooth = np.abs(fd_e2 - fd_e) <= 1e-7 * (1 + np.abs(fd_e))
        assert smooth.mean() > 0.8
        np.testing.assert_allclose(de[smooth], fd_e[smooth], rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(dx[smooth], fd_x[smooth], rtol=1e-6, atol=1e-6)
        checked += smooth.sum()
    assert checked > 200
