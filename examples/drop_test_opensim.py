"""From a drop test to OpenSim's HuntCrossleyForce parameters, checked inside OpenSim.

A solid rubber ball (60 mm, 124 g, Young's modulus 5 MPa, Poisson ratio 0.5) is dropped from
0.5 m onto concrete and rebounds to 0.3 m.  The drop gives the approach speed and Newton's
restitution e_N; Hertz's law gives the stiffness; ``contact_parameters`` gives OpenSim's
``stiffness`` and ``dissipation``.  If OpenSim is installed (``pip install -e ".[engines]"``),
the same drop is then run in OpenSim with those parameters and the e_N it delivers is printed.

Run: ``python examples/drop_test_opensim.py``
"""

import math

import contactalpha as ca

G = 9.81  # m/s^2
DROP_HEIGHT = 0.5  # m, released from rest
REBOUND_HEIGHT = 0.3  # m, measured apex of the first rebound
MASS = 0.124  # kg
RADIUS = 0.03  # m
YOUNG = 5e6  # Pa, the rubber; the concrete counts as rigid
POISSON = 0.5

approach_speed = math.sqrt(2 * G * DROP_HEIGHT)  # m/s at touchdown
e_n = math.sqrt(REBOUND_HEIGHT / DROP_HEIGHT)  # Newton: rebound speed / approach speed
# Hertz, sphere on a rigid half space: F = k delta^(3/2), k = (4/3) E* sqrt(R), E* = E / (1 - nu^2).
stiffness = 4 / 3 * YOUNG / (1 - POISSON**2) * math.sqrt(RADIUS)

cp = ca.contact_parameters(
    e_N=e_n, mass=MASS, stiffness=stiffness, approach_speed=approach_speed, accel=G, radius=RADIUS
)
opensim = cp.engines["opensim"]
print(f"approach speed   {approach_speed:.6g} m/s")
print(f"measured e_N     {e_n:.6g}")
print(f"Hertz stiffness  {stiffness:.6g} N/m^1.5")
print(f"xi               {cp.xi:.6g}")
print(f"alpha            {cp.damping:.6g}")
print(f"OpenSim stiffness   {opensim['stiffness']:.6g} Pa (each geometry, Simbody's convention)")
print(f"OpenSim dissipation {opensim['dissipation']:.6g} s/m (for this approach speed only)")

try:
    from contactalpha.adapters import opensim_hc

    opensim_hc.version()
except ImportError as err:
    print(f"not checked in OpenSim: {err}")
else:
    measured, _ = opensim_hc.drop_impact(
        MASS, RADIUS, stiffness, approach_speed, opensim["dissipation"], G, 0.0
    )
    print(f"OpenSim delivers e_N {measured.e_n:.6g}")
