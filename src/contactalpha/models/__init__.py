"""Contact models alpha(eps, xi): the registry and the paper's closed forms.

``contactalpha.models.alpha(eps, xi, model=NAME)`` evaluates any registered model;
``MODELS`` maps names to their descriptions.
"""

from .model import Model
from .registry import ALL_MODELS, MODELS, REGISTRY, alpha, contact_force, register
from .shen import eq40 as shen_eq40
from .shen import shen_published, shen_refit

__all__ = [
    "ALL_MODELS",
    "MODELS",
    "REGISTRY",
    "Model",
    "alpha",
    "contact_force",
    "register",
    "shen_eq40",
    "shen_published",
    "shen_refit",
]
