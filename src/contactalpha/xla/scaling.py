"""A scene's load factor xi in JAX, for any law of the family (``ContactLaw.load`` and ``load_factor``).

``A = a delta_s / v^2`` with ``delta_s = ((n + 1) m v^2 / (2 k))^(1/(n+1))``; the undamped loaded
maximum ``x_m`` solves ``x^(n+1) = 1 + 2 (1 - d) A x`` and ``xi = A x_m / (1/2 + A x_m)``.  For
n = 1 the root is the quadratic's; otherwise Newton from above (the function is convex there)
until no point moves or alternates between two neighbours, with no derivative carried, then one
step that carries it: at the root that step moves nothing and its derivative is the implicit
function's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import jax
import jax.numpy as jnp

from contactalpha.engine.scaling import A_ROUNDS_TO_ONE, XI_NEWTON_STEPS

if TYPE_CHECKING:
    from jax.typing import ArrayLike

    from contactalpha.laws.law import ContactLaw


def length_scale(
    law: ContactLaw, mass: ArrayLike, stiffness: ArrayLike, approach_speed: ArrayLike
) -> jax.Array:
    """``delta_s`` of ``law`` (``ContactLaw.length_scale``), elementwise."""
    c = 0.5 * (law.exponent + 1.0)
    scale = (c * mass * approach_speed * approach_speed / stiffness) ** (1.0 / (law.exponent + 1.0))
    return cast(jax.Array, scale)  # numpy or JAX in, as the arithmetic gives


def scaled_load(
    law: ContactLaw, mass: ArrayLike, stiffness: ArrayLike, approach_speed: ArrayLike, accel: ArrayLike
) -> jax.Array:
    """``A = a delta_s / v^2`` (``ContactLaw.load``)."""
    load = accel * length_scale(law, mass, stiffness, approach_speed) / (approach_speed * approach_speed)
    return cast(jax.Array, load)


def _newton(n1, b, x):
    return x - (x**n1 - 1.0 - 2.0 * b * x) / (n1 * x ** (n1 - 1.0) - 2.0 * b)


def load_factor(law: ContactLaw, A: ArrayLike) -> jax.Array:
    """``xi`` of scaled load ``A >= 0`` (``ContactLaw.load_factor``); NaN where A is not finite or huge."""
    real = cast(jax.Array, A)  # a real load (ArrayLike admits complex)
    ok = jnp.isfinite(real) & (real >= 0.0) & (real < A_ROUNDS_TO_ONE)
    A = jnp.where(ok, A, 0.0)
    b = (1.0 - law.impedance) * A
    if law.exponent == 1.0:
        x = b + jnp.sqrt(b * b + 1.0)
    else:
        n1 = law.exponent + 1.0
        x0 = jax.lax.stop_gradient(
            (1.0 + 2.0 * b) ** (1.0 / (n1 - 1.0)) if law.impedance == 0.0 else 2.0 + 2.0 * b
        )
        bs = jax.lax.stop_gradient(b)

        def step(st):
            k, x, before, _ = st
            nxt = _newton(n1, bs, x)
            return k + 1, nxt, x, jnp.all((nxt == x) | (nxt == before))

        # Newton from above until every point stands still or alternates between two neighbours
        # (a 1-ulp cycle, about one load in ten, as the numba form stops), at most its step count.
        start = (0, x0, jnp.full(jnp.shape(x0), jnp.nan), False)
        _, x, _, _ = jax.lax.while_loop(lambda st: (st[0] < XI_NEWTON_STEPS) & ~st[3], step, start)
        x = _newton(n1, b, jax.lax.stop_gradient(x))
    w = A * x
    xi = w / (0.5 + w)
    return jnp.where(ok & (xi < 1.0), xi, jnp.nan)
