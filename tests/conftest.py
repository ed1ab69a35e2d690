import os

import numpy as np
import pytest

# Determinism: the hypothesis profile is fixed so CI runs the same examples.
try:
    from hypothesis import settings

    settings.register_profile("ci", max_examples=25, deadline=None, derandomize=True)
    settings.load_profile("ci")
except ImportError:  # pragma: no cover
    pass

os.environ.setdefault("MPLBACKEND", "agg")


@pytest.fixture(scope="session")
def paper_eps():
    return np.round(np.arange(1, 100) * 0.01, 2)
