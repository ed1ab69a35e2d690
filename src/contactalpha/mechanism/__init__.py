"""Contacts inside the user's own model (MJCF, URDF, SDF): effective mass, load, tuned parameters.

``read_contact`` gives a ``MechanismContact`` (contact point, normal, ``m_eff``, free normal
acceleration, approach speed; MuJoCo's own contact row); ``tune`` solves the engine's law there
and writes the parameters beside the model (``docs/models-from-files.md``).  ``tune`` is split by
what it does: ``model_kind`` (what the file is, which engine tunes it), ``reading``, ``reduced``
(each engine's reduced-model answer), ``writers``, ``tuners`` (their records), ``on_engine``
(the engine loop, refine, check; ``loops``) and ``tune`` (the orchestration).
"""

from .contact import MechanismContact
from .on_engine import MASS_CHANGE_WARN
from .reading import read_contact
from .tune import Tuning, tune
from .tune_warnings import (
    JointLimitWarning,
    MassChangeWarning,
    OtherContactsWarning,
    UnmodelledSettingWarning,
)

__all__ = [
    "MASS_CHANGE_WARN", "JointLimitWarning", "MassChangeWarning", "MechanismContact", "OtherContactsWarning",
    "Tuning", "UnmodelledSettingWarning", "read_contact", "tune",
]  # fmt: skip
