import os

import numpy as np
import pytest
from hypothesis import settings

# Determinism: the hypothesis profile is fixed so CI runs the same examples.  Hypothesis is a
# declared test dependency: without it this import fails instead of leaving the profile unset
# (which silently gave random examples and the default 100 of them).
settings.register_profile("ci", max_examples=25, deadline=None, derandomize=True)
settings.load_profile("ci")

os.environ.setdefault("MPLBACKEND", "agg")


@pytest.fixture(scope="session")
def paper_eps():
    return np.round(np.arange(1, 100) * 0.01, 2)


# Optional real engines (pip install -e ".[engines]"): a test that needs one skips with the reason
# when it is missing, except under CI=true, where CI installs the extra and a missing engine fails.
ENGINE_HINT = 'pip install -e ".[engines]"'


def _require_engine(module):
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as err:
        reason = f"engine {module!r} is not installed ({err}); install it with {ENGINE_HINT}"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true: {reason}")
        pytest.skip(reason)


# Fixtures of the real engines: a test that uses one is an integration test (pytest -m integration).
ENGINE_FIXTURES = ("opensim", "exudyn", "mujoco", "pydrake", "pybullet", "sapien")
# JAX's fixture (tests/xla/conftest.py): each such test compiles with XLA, an integration test too.
COMPILE_FIXTURES = ("jax",)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Mark every test that runs a real engine or compiles with JAX ``integration`` (before ``-m``)."""
    for item in items:
        if any(name in getattr(item, "fixturenames", ()) for name in (*ENGINE_FIXTURES, *COMPILE_FIXTURES)):
            item.add_marker(pytest.mark.integration)


@pytest.fixture(scope="session")
def opensim():
    return _require_engine("opensim")


@pytest.fixture(scope="session")
def exudyn():
    return _require_engine("exudyn")


@pytest.fixture(scope="session")
def mujoco():
    return _require_engine("mujoco")


@pytest.fixture(scope="session")
def pydrake():
    return _require_engine("pydrake")


@pytest.fixture(scope="session")
def pybullet():
    return _require_engine("pybullet")


@pytest.fixture(scope="session")
def sapien():
    """SAPIEN (PhysX 5): the optional ``physx`` extra."""
    return _require_engine("sapien")
