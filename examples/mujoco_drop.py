"""From a target restitution to MuJoCo's solref, checked by a drop run in MuJoCo itself.

A 0.5 kg ball meets the floor at 0.5 m/s, pressed by gravity and a 5 N push. Its contact is a
linear spring of 2e4 N/m (MuJoCo's soft contact, direct mode, impedance d = 0.9), and the drop
test says e_N = 0.5. ``contact_parameters(..., law="mujoco_soft")`` gives the solref and solimp
that deliver it under that load; the drop below runs them in MuJoCo at a small time step, where
MuJoCo's discrete contact is close to the continuous law (at the default 2 ms step, use
``contactalpha params --engine mujoco --refine``, which calibrates on MuJoCo's own drops).

Run: python examples/mujoco_drop.py   (needs ``pip install mujoco``)
"""

import mujoco
import numpy as np

import contactalpha as ca

MASS, STIFFNESS, SPEED, PUSH, G, TARGET = 0.5, 2.0e4, 0.5, 5.0, 9.81, 0.5
TIMESTEP = 1e-5  # s: small, so that the step's own dissipation stays below 1e-3 in e_N

cp = ca.contact_parameters(
    e_N=TARGET, mass=MASS, stiffness=STIFFNESS, approach_speed=SPEED, accel=G + PUSH / MASS, law="mujoco_soft"
)
mj = cp.engines["mujoco"]  # MuJoCo's block, per unit mass (solref = (-k/m, -2 zeta sqrt(k/m)))
solref = " ".join(f"{x:.17g}" for x in mj["solref"])
solimp = " ".join(f"{x:.17g}" for x in mj["solimp"])
print(f"load factor xi   {cp.xi:.6f}")
print(f"damping ratio    {cp.damping:.9f}")  # zeta, the law's dimensionless damping
print(f"solref           {solref}")
print(f"solimp           {solimp}")

R = 0.02
xml = f"""
<mujoco>
  <option timestep="{TIMESTEP}" gravity="0 0 -{G}"/>
  <worldbody>
    <geom name="floor" type="plane" size="1 1 0.1" condim="1" solref="{solref}" solimp="{solimp}"/>
    <body name="ball" pos="0 0 {R + 1e-4}">
      <joint type="slide" axis="0 0 1"/>
      <geom type="sphere" size="{R}" mass="{MASS}" condim="1" solref="{solref}" solimp="{solimp}"/>
    </body>
  </worldbody>
</mujoco>
"""
model = mujoco.MjModel.from_xml_string(xml)
data = mujoco.MjData(model)
body = model.body("ball").id
# The push is a constant force on the ball: gravity plus PUSH press it into the floor.
data.xfrc_applied[body, 2] = -PUSH
# Start just above the floor with the approach speed reached exactly at touchdown.
a = G + PUSH / MASS
data.qvel[0] = -np.sqrt(SPEED**2 - 2 * a * 1e-4)
gap = []
vel = []
for _ in range(int(0.2 / TIMESTEP)):
    mujoco.mj_step(model, data)
    gap.append(data.qpos[0] + R + 1e-4 - R)  # height of the ball's lowest point above the floor
    vel.append(data.qvel[0])
gap, vel = np.array(gap), np.array(vel)
inside = np.flatnonzero(gap < 0.0)
first, last = inside[0], inside[0] + np.argmax(gap[inside[0] :] >= 0.0)
v_in = -np.interp(0.0, [gap[first], gap[first - 1]], [vel[first], vel[first - 1]])
v_out = np.interp(0.0, [gap[last - 1], gap[last]], [vel[last - 1], vel[last]])
print(f"approach speed   {v_in:.6f} m/s")
print(f"MuJoCo delivers  e_N = {v_out / v_in:.6f} (target {TARGET})")
