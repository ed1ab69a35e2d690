"""Domain randomisation: 4,096 random drop scenes to MuJoCo parameters in one call, three checked in MuJoCo.

Each scene is a ball of random mass on a linear contact of random stiffness (N/m, the physical
value: never per unit mass), meeting the floor at a random speed, pressed by gravity and a random
push, with a random target restitution e_N.  ``contact_parameters(..., engine="mujoco")`` takes
the arrays and gives every scene's ``solref`` and ``solimp`` (MuJoCo's soft contact, direct mode)
for the damping that delivers its e_N under its load.  Three scenes are then dropped in MuJoCo
itself, at a step small enough that MuJoCo's discrete contact is close to the continuous law (at
MuJoCo's default 2 ms step, add ``timestep="default"``: docs/stepping.md, "A batch at the step").

Run: python examples/domain_randomisation.py   (needs ``pip install mujoco``)
"""

import math

import mujoco
import numpy as np

import contactalpha as ca

N, G, R = 4096, 9.81, 0.02
rng = np.random.default_rng(2032)
mass = rng.uniform(0.05, 2.0, N)  # kg
stiffness = 10.0 ** rng.uniform(3.0, 5.0, N)  # N/m
speed = rng.uniform(0.2, 2.0, N)  # m/s at touchdown
push = rng.uniform(0.0, 20.0, N)  # N, pressing the ball down besides gravity
e_n = rng.uniform(0.2, 0.9, N)  # the target Newton restitution

cp = ca.contact_parameters(e_N=e_n, mass=mass, stiffness=stiffness, approach_speed=speed,
                           accel=G + push / mass, engine="mujoco")  # fmt: skip
solref, solimp = cp.block["solref"], cp.block["solimp"]
print(f"scenes           {N}, with parameters {int(cp.ok.sum())}")
print(f"damping ratio    {cp.damping.min():.4f} to {cp.damping.max():.4f} (zeta)")


def drop(i):
    """Scene ``i`` dropped in MuJoCo with its solref and solimp: the e_N MuJoCo delivers."""
    omega = math.sqrt(stiffness[i] / mass[i])
    h = 2.0 * math.pi / omega / 20000  # 20,000 steps per undamped period
    ref = " ".join(repr(float(x)) for x in solref[i])  # solref: (N, 2), solimp: (N, 5), a row per scene
    imp = " ".join(repr(float(x)) for x in solimp[i])
    model = mujoco.MjModel.from_xml_string(f"""
<mujoco>
  <option timestep="{h!r}" gravity="0 0 -{G}"/>
  <worldbody>
    <geom type="plane" size="1 1 0.1" condim="1" solref="{ref}" solimp="{imp}"/>
    <body name="ball" pos="0 0 {R + 1e-4}">
      <joint type="slide" axis="0 0 1"/>
      <geom type="sphere" size="{R}" mass="{float(mass[i])!r}" condim="1" solref="{ref}" solimp="{imp}"/>
    </body>
  </worldbody>
</mujoco>""")
    data = mujoco.MjData(model)
    data.xfrc_applied[model.body("ball").id, 2] = -push[i]
    a = G + push[i] / mass[i]
    data.qvel[0] = -math.sqrt(speed[i] ** 2 - 2.0 * a * 1e-4)  # touchdown at speed[i]
    gap, vel = [1e-4], [data.qvel[0]]
    for _ in range(int(3.0 * 20000)):  # three undamped periods: the contact and its rebound
        mujoco.mj_step(model, data)
        gap.append(data.qpos[0] + 1e-4)  # height of the ball's lowest point above the floor
        vel.append(data.qvel[0])
        if gap[-1] > 0.0 and vel[-1] > 0.0 and min(gap) < 0.0:
            break
    gap, vel = np.array(gap), np.array(vel)
    first = int(np.argmax(gap < 0.0))
    last = first + int(np.argmax(gap[first:] >= 0.0))
    v_in = -np.interp(0.0, [gap[first], gap[first - 1]], [vel[first], vel[first - 1]])
    v_out = np.interp(0.0, [gap[last - 1], gap[last]], [vel[last - 1], vel[last]])
    return v_out / v_in


for i in rng.choice(N, size=3, replace=False):
    print(
        f"scene {i:4d}       m = {mass[i]:.3f} kg, k = {stiffness[i]:.4g} N/m, v = {speed[i]:.3f} m/s, "
        f"push {push[i]:.2f} N: target e_N = {e_n[i]:.6f}, MuJoCo delivers e_N = {drop(i):.6f}"
    )
