"""The Python twins of the scalar kernels give the compiled kernels' numbers, bit for bit."""

import types

import numpy as np
import pytest
from numba import njit

from contactalpha.engine import firstcall, scaling, table
from contactalpha.engine.driver import ATOL, MAX_STEPS, NO_RECORD, RTOL
from contactalpha.engine.kernel import impact_kernel
from contactalpha.engine.scaling import scaled_load_unchecked

RNG = np.random.default_rng(25)


def _same(a, b):
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


@pytest.mark.parametrize(
    ("alpha", "xi"),
    [(0.0, 0.0), (1.51, 0.16), (3.0, 0.0), (30.0, 0.5), (300.0, 0.9), (0.2, 0.99)]
    + [
        (float(a), float(x))
        for a, x in zip(10 ** RNG.uniform(-2, 3, 8), RNG.uniform(0, 0.95, 8), strict=True)
    ],
)
def test_impact_twin_is_bit_identical(alpha, xi):
    args = (alpha, scaled_load_unchecked(xi), RTOL, ATOL, MAX_STEPS, NO_RECORD, np.inf)
    with np.errstate(all="ignore"):
        out, n = firstcall.python_twin(impact_kernel)(*map(np.float64, args[:4]), *args[4:])
    ref, n_ref = impact_kernel(*args)
    assert _same(out, ref), np.max(np.abs(out - ref))
    assert n == n_ref


@pytest.mark.parametrize("restitution", ["energetic", "kinematic"])
def test_table_twin_is_bit_identical(restitution):
    kernel, flat = table.scalar_lookup(restitution)
    kernel = getattr(kernel, "dispatcher", kernel)  # the bare dispatcher once compiled code is at hand
    twin = firstcall.python_twin(kernel)
    eps = np.concatenate([10 ** RNG.uniform(-2, 0, 300), [0.01, 1.0, 0.5, 2.0, np.nan]])
    xi = np.concatenate([RNG.uniform(0, 0.99, 300), [0.0, 0.3, 0.99, 0.1, 0.1]])
    got = [float(twin(np.float64(e), np.float64(x), flat)) for e, x in zip(eps, xi, strict=True)]
    ref = [kernel(float(e), float(x), flat) for e, x in zip(eps, xi, strict=True)]
    assert _same(got, ref)
    assert np.isfinite(ref[:-2]).all()  # the sample is inside the domain: values, not NaNs compared


def test_influence_factor_twin_is_bit_identical():
    for A in [1e-12, 1e-3, 0.3, 7.0, 1e6]:
        assert firstcall.python_twin(scaling.xi_of_load_scalar.dispatcher)(np.float64(A)) == (
            scaling.xi_of_load_scalar.dispatcher(A)
        )


def test_first_call_interprets_then_compiles_once(monkeypatch, capsys):
    @njit
    def twice(x):
        return 2.0 * np.sqrt(x)

    fc = firstcall.FirstCall(twice)
    assert fc(4.0) == 4.0
    assert not twice.signatures  # answered by the twin, nothing compiled
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(firstcall, "INTERPRET_BUDGET_S", 0.0)
    monkeypatch.setattr(firstcall.NOTICE, "said", False)  # as in a fresh process
    assert fc(9.0) == 6.0
    assert twice.signatures and fc.compiled
    err = capsys.readouterr().err
    assert "compiling numba kernels on first use" in err and "twice compiled in" in err
    assert err.index("compiling twice ...") < err.index("twice compiled in")
    assert fc(16.0) == 8.0
    assert capsys.readouterr().err == ""  # said once


def test_a_compile_is_announced_when_it_starts(monkeypatch, capsys):
    def kernel():
        pass

    kernel.__module__ = "contactalpha.somewhere"
    ev = types.SimpleNamespace(data={"dispatcher": types.SimpleNamespace(py_func=kernel)})
    monkeypatch.setattr(firstcall.NOTICE, "said", True)  # not the first compile of the process
    firstcall.NOTICE.on_start(ev)
    try:
        assert capsys.readouterr().err == "contactalpha:   compiling kernel ...\n"  # before it ends
    finally:
        firstcall.NOTICE.on_end(ev)
    assert capsys.readouterr().err.startswith("contactalpha:   kernel compiled in ")


def test_compiled_only_compiles_silently(capsys):
    @njit
    def plus_one(x):
        return x + 1.0

    fc = firstcall.FirstCall(plus_one)
    with firstcall.compiled_only():
        assert fc(1.0) == 2.0
    assert plus_one.signatures and fc.compiled
    assert capsys.readouterr().err == ""


def test_cold_first_calls_compile_nothing_and_give_the_compiled_numbers(tmp_path):
    """A fresh process, an empty numba cache: alpha and contact_parameters answer without compiling."""
    import json
    import os
    import subprocess
    import sys

    import contactalpha as ca
    from contactalpha.engine.firstcall import compiled_only

    code = (
        "import json, contactalpha as ca\n"
        "cp = ca.contact_parameters(0.5, 2.0, 2.51e6, 0.5, accel=9.81)\n"
        "print(json.dumps([ca.alpha(0.5, 0.2), cp.damping, cp.e_n, cp.e_n_half_speed, cp.e_n_twice_speed]))\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert "compil" not in out.stderr  # nothing announced: nothing compiled
    assert not list(tmp_path.rglob("*.nbi"))  # and nothing written to the cache
    with compiled_only():
        cp = ca.contact_parameters(0.5, 2.0, 2.51e6, 0.5, accel=9.81)
        expected = [ca.alpha(0.5, 0.2), cp.damping, cp.e_n, cp.e_n_half_speed, cp.e_n_twice_speed]
    assert json.loads(out.stdout) == expected


def test_arguments_the_twin_would_be_slow_on_compile_at_once():
    @njit
    def square(x):
        return x * x

    fc = firstcall.FirstCall(square, interpret_if=lambda x: x < 10.0)
    assert fc(3.0) == 9.0 and not square.signatures  # interpreted
    assert fc(30.0) == 900.0 and square.signatures and fc.compiled  # compiled for it
