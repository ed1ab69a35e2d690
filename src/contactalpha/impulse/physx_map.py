"""PhysX 5's rigid contact with restitution (TGS, through SAPIEN), one step as a map (numba).

What one ``scene.step()`` of SAPIEN 3.0.3's ``PhysxCpuSystem`` does to a free sphere on a plane,
read from PhysX (github NVIDIA-Omniverse/PhysX, ``physx/source/lowleveldynamics/src/``:
``DyTGSDynamics.cpp``, ``DyTGSContactPrep.cpp``) and checked against SAPIEN step by step:

1. **Forces first**: gravity and the push enter the velocity, ``v* = w - h a``.
2. **A contact pair** while the distance is below the two shapes' contact offsets (SAPIEN's
   default 0.01 m each: 0.02 m).  The rest offset is 0: the contact surface is the geometric one.
3. **The prep** (``constructContactConstraintStep``): with the separation ``s = z``, the row
   bounces when the restitution is positive, the approach beats the threshold (``v* <
   -bounceThreshold``, SAPIEN's default 2 m/s) and the gap closes within the step.  Then the
   target velocity is ``t = e |v*|`` and the error ``s + t (h + s / v*)``: the bounce is placed at
   the time of impact inside the step.  PhysX's source tests ``-v* > s / h``; SAPIEN 3.0.3's build
   bounces while ``s < 1.1 h |v*|`` (measured by bisection at four speeds: the switch sits at
   1.1000 of the step's travel), which ``CLOSING`` holds.
4. **Position iterations** (10, each of ``h / 10``): the separation error ``s_k = error + dx -
   t k h/10`` gives the bias ``-s_k / (h/10)`` (a contact separated at the prep) or ``-0.632 s_k /
   (h/10)`` (penetrating: ``min(0.8, 2 sqrt(1/10))``), and the row's impulse per unit mass
   ``bias - (v - t)``, with the accumulated impulse kept >= 0; the position moves ``v h/10`` after
   each iteration.
5. **Velocity iteration** (1): the same with the error clamped at 0 and no motion.

A touchdown faster than the contact distance a step passes it in a free step and lands deep; the
bounce leaves the body below the plane moving up, and the next step's position iterations push it
out (the penetrating bias) while the clamped impulse (kept >= 0) gives the velocity back: an
impulse seen only in the position, which ``delivered.free_steps`` reads (9 mm at 4 m/s, 0.01 s).

So the rebound leaves at exactly ``e |v*|``, the step's gravity counted, and from where the bounce
at the time of impact would be: unlike Bullet, the touchdown phase moves the rebound only through
``|v*|`` and the threshold.  The map runs in double precision; PhysX in single (agreement to
about 1e-7 of the scale, and a ball at rest jitters by the float's resolution).  ``z`` is PhysX's
own separation: a ball at rest has 0 there (penetrating: the 0.632 bias), while its pose reads a
few float steps below the plane (``adapters.physx_sapien.drop_sequence`` adds the difference); a
coefficient that sends a body off from rest delivers less than ``e |v*|`` on that branch (0.77 of
it for ``e = 336`` at 1 ms).
Combined restitution: PhysX averages the two materials' (``PxCombineMode::eAVERAGE``, the default):
the same value on both bodies is the pair's.
"""

import math

import numpy as np
from numba import njit

# SAPIEN's defaults (sapien.physx.get_scene_config / get_shape_config / get_body_config).
DEFAULT_TIMESTEP = 0.01
BOUNCE_THRESHOLD = 2.0
CONTACT_DISTANCE = 0.02  # two shapes' contact_offset, 0.01 m each
POSITION_ITERATIONS = 10
VELOCITY_ITERATIONS = 1
# SAPIEN 3.0.3's build: the row bounces while the gap is below this many steps' travel (measured).
CLOSING = 1.1

# Slots of ``p``.
RESTITUTION = 0  # the pair's restitution (the average of the two materials')
THRESHOLD = 1  # bounce_threshold, m/s
DISTANCE = 2  # contact distance, m
POS_ITERS = 3
VEL_ITERS = 4
CLOSING_SLOT = 5
N_PARAMS = 6


def make_params(restitution: float, threshold: float = BOUNCE_THRESHOLD, distance: float = CONTACT_DISTANCE,
                position_iterations: int = POSITION_ITERATIONS,
                velocity_iterations: int = VELOCITY_ITERATIONS) -> np.ndarray:  # fmt: skip
    """``p`` for the pair's ``restitution`` at SAPIEN's defaults."""
    p = np.empty(N_PARAMS)
    p[RESTITUTION], p[THRESHOLD], p[DISTANCE] = restitution, threshold, distance
    p[POS_ITERS], p[VEL_ITERS], p[CLOSING_SLOT] = position_iterations, velocity_iterations, CLOSING
    return p


@njit(cache=True)
def step_physx(z: float, w: float, p: np.ndarray, h: float, accel: float) -> tuple[float, float]:
    """One step of the height ``z`` (m, above the plane) and velocity ``w`` (m/s, up)."""
    v = w - h * accel
    if not z < p[DISTANCE]:
        return z + h * v, v
    n_pos = int(p[POS_ITERS])
    dt = h / n_pos
    bias_scale = min(0.8, 2.0 * math.sqrt(1.0 / n_pos))
    e = p[RESTITUTION]
    bounce = e > 0.0 and v < -p[THRESHOLD] and -v * p[CLOSING_SLOT] * h > z
    target = e * -v if bounce else 0.0
    error = z + target * (h + z / v) if bounce else z
    coeff = 1.0 / dt if z > 0.0 else bias_scale / dt  # separated: PhysX's penetration > 0
    dx, total, vn = 0.0, 0.0, v
    for k in range(n_pos):
        sep = error + dx - target * k * dt
        d = max(-coeff * sep - (vn - target), -total)
        total += d
        vn += d
        dx += vn * dt
    for _ in range(int(p[VEL_ITERS])):
        sep = max(0.0, error + dx - target * h)
        d = max(-coeff * sep - (vn - target), -total)
        total += d
        vn += d
    return z + dx, vn
