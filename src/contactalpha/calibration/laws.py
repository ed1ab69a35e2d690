"""Deprecated: the restitution hypotheses moved to ``contactalpha.calibration.hypotheses``.

"Law" names a contact law only (``contactalpha.laws``).  Importing this module warns; its old
names (``LAWS``, ``Law``, ``DEFAULT_LAW``, ...) still resolve, each with a DeprecationWarning.
"""

import warnings

from . import hypotheses as _hypotheses

warnings.warn(
    "contactalpha.calibration.laws moved to contactalpha.calibration.hypotheses",
    DeprecationWarning,
    stacklevel=2,
)


def __getattr__(name):
    return getattr(_hypotheses, name)
