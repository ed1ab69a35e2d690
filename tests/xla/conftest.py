"""The JAX front door's tests need JAX (the ``[jax]`` extra): they skip without it, fail under CI=true."""

import importlib
import os

import pytest

JAX_HINT = 'pip install -e ".[jax]"'


def _require(module, hint):
    try:
        return importlib.import_module(module)
    except ImportError as err:
        reason = f"{module!r} is not installed ({err}); install it with {hint}"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true: {reason}")
        pytest.skip(reason)


@pytest.fixture(scope="session")
def jax():
    jax = _require("jax", JAX_HINT)
    jax.config.update("jax_enable_x64", True)
    return jax


@pytest.fixture(scope="session")
def mjx(jax):
    _require("mujoco", 'pip install -e ".[engines]"')
    return _require("mujoco.mjx", 'pip install -e ".[batched-engines]"')


@pytest.fixture(scope="session")
def mujoco_warp():
    _require("warp", 'pip install -e ".[batched-engines]"')
    return _require("mujoco_warp", 'pip install -e ".[batched-engines]"')


@pytest.fixture(scope="session")
def newton():
    _require("warp", 'pip install -e ".[batched-engines]"')
    return _require("newton", 'pip install -e ".[batched-engines]"')
