"""The engines' discrete steps: one normal contact as the map an engine's step applies.

A stepping engine (MuJoCo, PyBullet, Drake's discrete plant) advances a drop by a fixed step
``h``; what it delivers depends on ``h`` and on where touchdown falls inside a step (the phase
``phi`` in [0, 1)).  Each engine's step for one frictionless contact is a short deterministic
map, written here in numba from the engine's source (``mujoco_map``, ...).  On top of the maps,
and generic over the ``registry`` of steppers:

- ``drop``: a whole drop from the exact free-flight parabola, e_N, Stronge's eps, contact steps;
- ``phase``: the mean over a uniform touchdown phase, computed exactly across the jumps, with the
  minimum, maximum and standard deviation a single drop sees;
- ``inverse``: the engine's own damping whose phase mean is the target;
- ``stepsize``: the largest step at which a single drop stays within a tolerance.

The kernel interface every map keeps (docs/stepping.md):

- ``p``: float64 1-D array of the engine's own parameters in its units, slot indices as named
  module-level int constants of the map's module;
- ``step_<engine>(z, w, p, h, accel) -> (z, w)``: one step of the height ``z`` above the contact
  (z < 0: penetration) and velocity ``w`` (up), under a constant load acceleration ``accel > 0``
  pressing into the contact;
- ``drop_<engine>(p, h, phase, v_in, accel, max_steps) -> (e_N, n_contact_steps, status)``.
"""

import contactalpha.engine  # noqa: F401  (installs the numba cache locator before any kernel)
