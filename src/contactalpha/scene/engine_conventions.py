"""Deprecated home of ``contactalpha.adapters.engine_conventions``.

It moved so that ``scene`` imports ``adapters`` and never the reverse; importing this module warns
and re-exports the moved module's names.
"""

import warnings

from contactalpha.adapters.engine_conventions import (  # noqa: F401
    EXUDYN_IMPACT_MODELS,
    EXUDYN_SWITCH,
    exudyn_alpha,
    exudyn_restitution_input,
    opensim_alpha,
    opensim_dissipation,
    opensim_hertz_stiffness,
    opensim_stiffness,
)

warnings.warn(
    "contactalpha.scene.engine_conventions moved to contactalpha.adapters.engine_conventions",
    DeprecationWarning,
    stacklevel=2,
)
