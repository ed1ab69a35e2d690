"""Differentiable system identification: a contact's damping fitted to a recorded bounce through MJX.

A 0.5 kg ball on a 2e4 N/m contact (MuJoCo's soft contact, direct mode, impedance 0.9) is
dropped from 5 cm; MuJoCo records its bounces at a 0.2 ms step ("the recording", made with
a damping b_true the fit is not told).  The fit's one parameter is the restitution of the first
impact, e_N: the JAX front door (``contactalpha.xla.contact_parameters``) turns it into MuJoCo's
solref, an MJX rollout of the same drop gives the trajectory, and gradient descent (on
``jax.grad`` of the squared height misfit through the front door's implicit derivative and MJX's
steps) moves e_N, with a backtracking line search.  ``contactalpha.calibrate`` fits the same
recording with the continuous law,
for comparison.

Run: python examples/mjx_sysid.py   (needs ``pip install "contactalpha[batched-engines]"``)
"""

import math

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

import contactalpha as ca
from contactalpha.xla import contact_parameters
from contactalpha.xla.mjx_drop import base_model

jax.config.update("jax_enable_x64", True)

MASS, STIFFNESS, G, HEIGHT, IMPEDANCE = 0.5, 2.0e4, 9.81, 0.05, 0.9
TIMESTEP, STEPS = 2e-4, 2500
B_TRUE = 2.0 * 0.15 * math.sqrt(STIFFNESS / MASS)  # the recording's damping, 1/s
SPEED = math.sqrt(2.0 * G * HEIGHT)  # at the first touchdown
ITERATIONS = 25

# The recording: MuJoCo itself, released at rest HEIGHT above the floor (gravity as the motor's push).
model = base_model(IMPEDANCE, mass=MASS)
model.opt.timestep = TIMESTEP
model.geom_solref[:] = (-STIFFNESS / MASS, -B_TRUE)
data = mujoco.MjData(model)
data.qpos[0], data.ctrl[0] = HEIGHT, -MASS * G
heights = [HEIGHT]
for _ in range(STEPS):
    mujoco.mj_step(model, data)
    heights.append(data.qpos[0])
recorded = np.maximum(np.array(heights), 0.0)  # the ball's lowest point above the floor
times = TIMESTEP * np.arange(STEPS + 1)

# The same drop in MJX, from a first-impact e_N through the JAX front door.  One solver iteration
# (reverse-mode needs a fixed count; Newton's step solves one frictionless contact's problem).
model.opt.iterations = 1
mx = mjx.put_model(model)
start = mjx.make_data(mx)
start = start.replace(qpos=start.qpos.at[0].set(HEIGHT), ctrl=start.ctrl.at[0].set(-MASS * G))


def solref_of(e_n):
    """MJX's direct-mode solref for a first impact of restitution ``e_n`` (the JAX front door)."""
    cp = contact_parameters(MASS, STIFFNESS, SPEED, G, e_n, law="mujoco_soft")
    return cp["engines"]["mjx"]["solref"]


def misfit(e_n):
    """Mean squared height misfit (in drop heights) of MJX's drop with the front door's solref for ``e_n``."""
    return _misfit(solref_of(e_n))


def misfit_of_b(b):
    """The misfit of MJX's run at damping ``b`` itself (0 when MJX steps like MuJoCo)."""
    solref = jnp.array([-STIFFNESS / MASS, -b])
    return _misfit(solref)


def _misfit(solref):
    m = mx.replace(geom_solref=jnp.broadcast_to(solref, mx.geom_solref.shape))

    def step(d, _):
        d = mjx.step(m, d)
        return d, d.qpos[0]

    _, z = jax.lax.scan(step, start, None, length=STEPS)
    z = jnp.maximum(jnp.concatenate([jnp.array([HEIGHT]), z]), 0.0)
    return jnp.mean((z - recorded) ** 2) / HEIGHT**2


value_and_grad = jax.jit(jax.value_and_grad(misfit))
loss_of = jax.jit(misfit)
e_n, rate = 0.8, 1.0
loss, g = value_and_grad(e_n)
for it in range(1, ITERATIONS + 1):
    # Gradient descent with a backtracking (Armijo) line search on the rate.
    rate *= 2.0
    while rate > 1e-12:
        trial = e_n - rate * float(g)
        trial_loss = float(loss_of(trial))
        if trial_loss <= float(loss) - 1e-4 * rate * float(g) ** 2:
            break
        rate *= 0.5
    e_n = trial
    loss, g = value_and_grad(e_n)
    if it % 5 == 0:
        print(f"iteration {it:3d}: e_N {e_n:.8f}, misfit {float(loss):.3e}")
b_fit = -float(solref_of(e_n)[1])
print(f"misfit at b_true          {float(misfit_of_b(B_TRUE)):.3e}")

cal = ca.calibrate(recorded, kind="trajectory", t=times, mass=MASS, gravity=G,
                   hypotheses=["mujoco_soft_damping"], intervals=False, impedance=IMPEDANCE)  # fmt: skip
b_cal = cal.fits["mujoco_soft_damping"].values["damping"]
print(f"first-impact e_N fitted   {e_n:.6f}")
print(f"damping b true            {B_TRUE:.6f}")
print(f"damping b by MJX fit      {b_fit:.6f}")
print(f"damping b by calibrate    {b_cal:.6f}")
print(
    f"stiffness s by calibrate  {cal.fits['mujoco_soft_damping'].values['stiffness']:.6g}  "
    f"(true {STIFFNESS / MASS:.6g})"
)
