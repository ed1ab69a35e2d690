"""contactalpha: the hysteresis damping factor of a Hunt-Crossley contact under a constant load.

The public names below are imported on first use (PEP 562), so that ``import contactalpha``
in a workflow job that only draws a figure does not load every numba kernel.
"""

import importlib

from contactalpha.version import __version__  # noqa: F401

# Public name -> module that defines it.
_EXPORTS = {
    "ImpactResult": "engine.driver",
    "impact": "engine.driver",
    "restitution": "engine.driver",
    "trajectory": "engine.driver",
    "alpha": "models.registry",
    "contact_force": "models.registry",
    "alpha_tabulated": "engine.table",
    "jit_alpha_tabulated": "engine.table",
    "AlphaSolution": "engine.solver",
    "solve_alpha": "engine.solver",
    "convert_restitution": "engine.restitution",
    "alpha_exact": "engine.exact",
    "restitution_exact": "engine.exact",
    "influence_factor": "engine.scaling",
    "length_scale": "engine.scaling",
    "load_for": "engine.scaling",
    "scaled_load": "engine.scaling",
    "time_scale": "engine.scaling",
    "load_surface": "io",
    "ContactParameters": "parameters.result",
    "contact_parameters": "parameters.front_door",
    "hertz_stiffness": "scene.hertz",
    "Advice": "scene.advisor",
    "advise": "scene.advisor",
    "critical_speed": "scene.threshold",
    "Scene": "scene.ball",
    "BouncePrediction": "scene.bounces",
    "predict_bounces": "scene.bounces",
    "Calibration": "calibration.api",
    "calibrate": "calibration.api",
    "ContactLaw": "laws.law",
    "LAWS": "laws.law",
    "get_law": "laws.law",
}
__all__ = sorted(_EXPORTS)


def __getattr__(name):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'contactalpha' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
