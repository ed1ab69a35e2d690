"""Every law's first call on a cold numba cache: its kernels run as Python twins, the same bits.

A fresh process with an empty ``NUMBA_CACHE_DIR`` (and a twin budget no machine's load can use up)
computes each registered law's exact inverse and impact (on the family's integrator) and its fast
inverse on 200 points (run in threads once compiled).  It compiles nothing, and every number equals
the compiled kernels' (this process, ``compiled_only``), NaN for NaN.
"""

import json
import os
import subprocess
import sys

import numpy as np

from contactalpha.engine.firstcall import compiled_only
from contactalpha.laws import LAWS

RESTITUTIONS = ("energetic", "kinematic")

CODE = """
import json
import numpy as np
from contactalpha.engine import firstcall
from contactalpha.laws import LAWS
from contactalpha.laws.backends import FAMILY

firstcall.INTERPRET_BUDGET_S = 1e9


def numbers():
    rng = np.random.default_rng(7)
    targets, xis = rng.uniform(0.05, 0.95, 200), rng.uniform(0.0, 0.6, 200)
    out = {}
    for law in LAWS:
        for r in ("energetic", "kinematic"):
            row = []
            if law.backend is FAMILY:  # the engine's own solver is not twinned: it compiles at once
                sol = law.damping_for(0.5, 0.2, r)
                imp = law.impact(np.float64(sol.damping), 0.2)
                row += [float(sol.damping), float(imp.eps), float(imp.e_n)]
            if law.fast is not None:
                row += map(float, law.fast_damping(targets, xis, r))
            out[f"{law.name} {r}"] = row
    return out
"""


def test_every_laws_cold_first_call_compiles_nothing_and_gives_the_compiled_bits(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_NUM_THREADS": "2"}
    run = subprocess.run(
        [sys.executable, "-c", CODE + "print(json.dumps(numbers()))"],
        env=env, capture_output=True, text=True, timeout=900,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert "compil" not in run.stderr  # nothing announced: nothing compiled
    assert not list(tmp_path.rglob("*.nbi"))  # and nothing written to the cache
    cold = json.loads(run.stdout.strip().splitlines()[-1])
    scope = {}
    exec(CODE, scope)  # noqa: S102 - the test's own source, now compiled
    with compiled_only():
        compiled = scope["numbers"]()
    assert sorted(cold) == sorted(f"{law.name} {r}" for law in LAWS for r in RESTITUTIONS)
    for key, values in compiled.items():
        np.testing.assert_array_equal(np.array(cold[key]), np.array(values), err_msg=key)
