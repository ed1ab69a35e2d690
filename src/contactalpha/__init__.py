"""contactalpha: the hysteresis damping factor of a Hunt-Crossley contact under a constant load."""

__version__ = "0.1.0"

from .exact import alpha_exact, restitution_exact  # noqa: E402
from .impact import ImpactResult, impact, restitution, trajectory  # noqa: E402
from .io import load_surface  # noqa: E402
from .models import alpha, contact_force  # noqa: E402
from .scaling import influence_factor, length_scale, load_for, scaled_load, time_scale  # noqa: E402
from .solver import AlphaSolution, solve_alpha  # noqa: E402
from .table import alpha_tabulated, jit_alpha_tabulated  # noqa: E402

__all__ = [
    "alpha",
    "alpha_tabulated",
    "contact_force",
    "jit_alpha_tabulated",
    "AlphaSolution",
    "alpha_exact",
    "restitution_exact",
    "solve_alpha",
    "ImpactResult",
    "impact",
    "influence_factor",
    "load_surface",
    "length_scale",
    "load_for",
    "restitution",
    "scaled_load",
    "time_scale",
    "trajectory",
]
