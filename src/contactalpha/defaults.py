"""Defaults and names the command line's ``--help`` shows, in a leaf: no numba, no SciPy, no NumPy.

``contactalpha ... --help`` builds its parsers from these without importing a kernel.  Each has its
one home here; its users import it from here, and the registries check theirs against it when
they load: the integrator's tolerances (``engine.driver``), the alpha solver's (``engine.solver``),
the exit status of an unreachable target (``parameters.reach``), and each contact law's stiffness
unit (``laws``; tests/scene/test_result.py keeps the help and the laws equal).
The engines are not listed here: the registry (``adapters.registry``) is their one home, and
``--engine`` (of ``params`` and ``tune``) takes any name, checked against it when the command runs.
"""

# Default tolerances: tight enough that Stronge's epsilon is good to ~1e-12
# over the paper's domain, which the alpha root-finder needs for 1e-10.
RTOL = 1e-12
ATOL = 1e-14
# Default absolute tolerance on the restitution coefficient reached.
EPS_TOL = 1e-12
# Exit status of `contactalpha params` when no damping reaches the target.
EXIT_UNREACHABLE = 3
# Each contact law's physical stiffness unit (``ContactLaw.stiffness_unit``), in the laws' order.
STIFFNESS_UNITS = {
    "hunt_crossley": "N/m^1.5",
    "hunt_crossley_linear": "N/m",
    "kelvin_voigt": "N/m",
    "mujoco_soft": "N/m",
    "hertz_tsuji": "N/m^1.5",
    "hertz_tsuji_unfloored": "N/m^1.5",
    "hertz_viscoelastic": "N/m^1.5",
    "hertz_viscoelastic_unfloored": "N/m^1.5",
}
