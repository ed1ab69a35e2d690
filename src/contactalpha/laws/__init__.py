"""laws: the normal contact laws engines use, each exact under a constant load.

``LAWS`` lists them as ``ContactLaw`` values; ``get_law(name)`` finds one.  Each law gives both
restitutions at a damping and load factor (``law.impact``, ``law.restitution``), the exact
inverse (``law.damping_for``), fast evaluators (``law.fast_damping``, ``law.fast_restitution``)
and the conversions to the engine's own damping (``law.physical_damping``).  docs/laws.md has
the physics.
"""

import contactalpha.engine  # noqa: F401  (installs the numba cache locator before any kernel)

from .law import DEFAULT_LAW, LAWS, RESTITUTIONS, ContactLaw, get_law
from .maps import DampingSolution, LawImpact

__all__ = ["DEFAULT_LAW", "LAWS", "RESTITUTIONS", "ContactLaw", "DampingSolution", "LawImpact", "get_law"]
