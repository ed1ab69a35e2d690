"""The adapters' tests' fixtures."""

import os

import pytest

from contactalpha.adapters import lammps_granular as lg


@pytest.fixture(scope="module")
def lammps():
    """The LAMMPS adapter module, LAMMPS itself loaded; skipped without it (failed under CI=true)."""
    try:
        lg.new_instance().close()
    except ImportError as err:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true: LAMMPS is not installed ({err})")
        pytest.skip(f"LAMMPS is not installed ({err}); {lg.INSTALL_HINT}")
    return lg
