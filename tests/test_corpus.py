"""Every number of the public API is bit-identical to the stored corpus (``tests/data/corpus.json``).

The corpus was made by ``python tests/data/make_corpus.py`` from the code of its commit: each
entry is one number, array or string the public API gives on fixed inputs, floats as
``float.hex``.  A refactor keeps them bit for bit; a change of numbers that is meant is
regenerated in its own commit, saying why.  Only stored keys are compared: a law, engine or model
added later adds keys, which are not checked here; but every stored key must still be produced.

Bits are compared between hosts of one SIMD level (``make_corpus.host_level``): NumPy and numba
pick their code by the CPU, and with the code unchanged 11 of 2,412 default entries differ (up to
1.7e4 ulp after root-finds) between the corpus's host (taken to be X86_V4) and an X86_V3 one.  A level other
than the corpus's own compares against its recorded overrides (``tests/data/corpus_hosts.json``,
made with ``python tests/data/make_corpus.py --host`` from the corpus's commit); an unrecorded
level compares within a relative 1e-9 and warns.
"""

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parent / "data"
_spec = importlib.util.spec_from_file_location("make_corpus", DATA / "make_corpus.py")
make_corpus = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_corpus)

STORED = make_corpus.load()


def _require(part):
    lacking = make_corpus.missing(part)
    if lacking:
        reason = f"the corpus's {part!r} part needs {', '.join(lacking)} (not installed)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true: {reason}")
        pytest.skip(reason)


def _value(token):
    try:
        return float.fromhex(token)
    except ValueError:  # "str:...", "int:...", "bool:...", "none"
        return token


def _difference(stored, now):
    """Where two entries first differ, in words: the shape, or the first differing value."""
    if stored[1] != now[1]:
        return f"shape {tuple(stored[1])} stored, {tuple(now[1])} now"
    i = next(i for i, (a, b) in enumerate(zip(stored[2], now[2], strict=True)) if a != b)
    return f"value {i} of {len(stored[2])}: stored {_value(stored[2][i])!r}, now {_value(now[2][i])!r}"


UNRECORDED_RTOL = 1e-9


def _close(stored, now):
    """Two entries equal up to a relative ``UNRECORDED_RTOL`` (a host level with no record)."""
    if stored[1] != now[1]:
        return False
    for x, y in zip(map(_value, stored[2]), map(_value, now[2]), strict=True):
        floats = isinstance(x, float) and isinstance(y, float)
        if not (np.isclose(x, y, rtol=UNRECORDED_RTOL, atol=0.0, equal_nan=True) if floats else x == y):
            return False
    return True


def check_part(part, got):
    """Every stored entry of ``part`` is in ``got`` and equal token for token (bit for bit)."""
    stored = make_corpus.expected(part)
    if stored is None:
        import warnings

        warnings.warn(
            f"corpus {part}: no record of host level {make_corpus.host_level()!r}; compared within "
            f"{UNRECORDED_RTOL:g} (record it: python tests/data/make_corpus.py --host)",
            stacklevel=2,
        )
        stored = STORED[part]
        missing = sorted(set(stored) - set(got))
        assert not missing, f"corpus {part}: {len(missing)} stored entries are no longer produced"
        far = [key for key in sorted(stored) if not _close(stored[key], got[key])]
        assert not far, (
            f"corpus {part}: {len(far)} entries differ by more than {UNRECORDED_RTOL:g}; first {far[0]!r}"
        )
        return
    missing = sorted(set(stored) - set(got))
    assert not missing, (
        f"corpus {part}: {len(missing)} stored entries are no longer produced, first {missing[0]!r}"
    )
    differ = [key for key in sorted(stored) if got[key][1:] != stored[key][1:]]  # shape, values
    assert not differ, (
        f"corpus {part}: {len(differ)} of {len(stored)} entries differ; first {differ[0]!r}, "
        f"{_difference(stored[differ[0]], got[differ[0]])}"
    )


def test_the_corpus_cases_cover_every_law_engine_stepper_and_model():
    """The cases iterate the registries (never a list of names): a new entry gets its keys."""
    import contactalpha as ca
    from contactalpha.adapters.registry import ENGINE_NAMES
    from contactalpha.models.registry import ALL_MODELS
    from contactalpha.stepping.registry import STEPPER_NAMES

    heads = {"/".join(key.split("/")[:2]) for _, key, _ in make_corpus.package_cases()}
    wanted = {f"law/{law.name}" for law in ca.LAWS} | {f"critical_speed/{law.name}" for law in ca.LAWS}
    wanted |= {f"engine/{e}" for e in ENGINE_NAMES} | {f"step/{e}" for e in STEPPER_NAMES}
    wanted |= {f"alpha/{m}" for m in ALL_MODELS}
    assert wanted <= heads, f"no corpus case for {sorted(wanted - heads)}"
    assert set(STORED) == set(make_corpus.PARTS)


def test_the_package_gives_the_corpus_numbers_bit_for_bit():
    check_part("default", make_corpus.part_of("default"))


@pytest.mark.integration
def test_the_slow_paths_give_the_corpus_numbers_bit_for_bit():
    check_part("heavy", make_corpus.part_of("heavy"))


@pytest.mark.integration
def test_a_model_file_gives_the_corpus_numbers_bit_for_bit():
    _require("model_file")
    check_part("model_file", make_corpus.model_file_part())


@pytest.mark.integration
def test_the_jax_front_door_gives_the_corpus_numbers_bit_for_bit():
    _require("jax")
    check_part("jax", make_corpus.jax_part())
