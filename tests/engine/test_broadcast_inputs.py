"""Broadcast inputs reach the kernels without numba's FutureWarning (issue 29, N12).

numba reads an array's flags (and numpy warns for a view of ``np.broadcast_arrays``) only when
a dispatcher types its arguments in Python: at a process's first call of each kernel.  So the
calls run in a fresh process, each public entry point first with broadcast input.
"""

import subprocess
import sys

SCRIPT = r"""
import warnings
import numpy as np
import contactalpha as ca
from contactalpha.models import MODELS

calls = {
    "alpha exact": lambda: ca.alpha([0.5], 0.2),
    "alpha kinematic": lambda: ca.alpha([0.5], 0.2, restitution="kinematic"),
    "alpha_tabulated": lambda: ca.alpha_tabulated(np.array([[0.5], [0.3]]), [0.2, 0.4]),
    "impact": lambda: ca.impact([10.0], 0.2),
    "solve_alpha": lambda: ca.solve_alpha([0.5], 0.2),
    "solve_alpha kinematic": lambda: ca.solve_alpha([0.5], 0.2, restitution="kinematic"),
    "length_scale": lambda: ca.length_scale([0.5], 1.4e8, 1.0),
    "influence_factor": lambda: ca.influence_factor([0.5], 1.4e8, 0.5, [9.81]),
    **{f"alpha {m}": (lambda m=m: ca.alpha([0.5], [0.2], model=m)) for m in MODELS},
}
warned = []
for name, call in calls.items():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()
    warned += [f"{name}: {w.message}" for w in caught]
print("\n".join(warned) or "none")
"""


def test_a_broadcast_array_gives_no_warning():
    """ca.alpha([0.5], 0.2) printed numba's FutureWarning about writeable broadcast arrays."""
    run = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "none", run.stdout
