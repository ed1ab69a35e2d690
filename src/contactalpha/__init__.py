"""contactalpha: the hysteresis damping factor of a Hunt-Crossley contact under a constant load.

The public names below are imported on first use (PEP 562), so that ``import contactalpha``
in a workflow job that only draws a figure does not load every numba kernel.
"""

import importlib

__version__ = "0.1.0"

# Eager: the submodule ``impact`` shares its name with the function, and importing the
# submodule anywhere would otherwise leave the module object under ``contactalpha.impact``.
from .impact import ImpactResult, impact, restitution, trajectory  # noqa: E402, F401

# Public name -> module that defines it.
_EXPORTS = {
    "alpha": "models",
    "contact_force": "models",
    "alpha_tabulated": "table",
    "jit_alpha_tabulated": "table",
    "AlphaSolution": "solver",
    "solve_alpha": "solver",
    "alpha_exact": "exact",
    "restitution_exact": "exact",
    "influence_factor": "scaling",
    "length_scale": "scaling",
    "load_for": "scaling",
    "scaled_load": "scaling",
    "time_scale": "scaling",
    "load_surface": "io",
}
__all__ = sorted([*_EXPORTS, "ImpactResult", "impact", "restitution", "trajectory"])


def __getattr__(name):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'contactalpha' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
