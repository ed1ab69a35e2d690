"""Contacts inside the user's own model (MJCF, URDF, SDF): effective mass, load, tuned parameters.

``read_contact`` gives a ``MechanismContact`` (contact point, normal, ``m_eff``, free normal
acceleration, approach speed; MuJoCo's own contact row); ``tune`` solves the engine's law there
and writes the parameters beside the model (``docs/models-from-files.md``).
"""

from .contact import MechanismContact
from .tune import (
    MASS_CHANGE_WARN,
    JointLimitWarning,
    MassChangeWarning,
    Tuning,
    UnmodelledSettingWarning,
    read_contact,
    tune,
)  # fmt: skip

__all__ = [
    "MASS_CHANGE_WARN", "JointLimitWarning", "MassChangeWarning", "MechanismContact", "Tuning",
    "UnmodelledSettingWarning", "read_contact", "tune",
]  # fmt: skip
