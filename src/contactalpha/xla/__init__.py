"""xla: the JAX front door (optional extra ``[jax]``): pure functions of arrays for jit, vmap and grad.

- ``contact_parameters`` (``front.py``): target restitution of many scenes -> the law's damping and
  the batched engines' parameters (MuJoCo, MJX, MuJoCo Warp, Newton, Genesis).
- ``law_damping`` (``inverse.py``): the inverse of every law; ``table_damping`` and
  ``device_table`` (``tables.py``): the shipped tables on the device; ``closed_form`` (the forward
  map of the piecewise-linear laws at any impedance).

Numbers agree with the numba batch in float64 (``jax.config.update("jax_enable_x64", True)``);
in float32 the tables' ~1e-7 is the precision.  Importing it needs JAX (``pip install
"contactalpha[jax]"``); the core package never imports it.
"""

try:
    import jax  # noqa: F401
except ImportError as err:  # pragma: no cover - depends on the machine
    raise ImportError('the JAX front door needs JAX: pip install "contactalpha[jax]"') from err

from .front import contact_parameters
from .inverse import closed_form_damping, law_damping
from .tables import device_table, table_damping

__all__ = ["closed_form_damping", "contact_parameters", "device_table", "law_damping", "table_damping"]
