"""A surface file is checked when it is read: checksum, readability, solved alphas (issue 29, N4)."""

import h5py
import numpy as np
import pytest

from contactalpha.io import DIGEST_ATTR, load_dataset, load_surface, write_dataset_atomic
from contactalpha.paper.surface.compute import compute_surface


@pytest.fixture(scope="module")
def surface():
    return compute_surface(np.array([0.2, 0.5, 0.8]), np.array([0.0, 0.2, 0.4]))


@pytest.fixture
def path(surface, tmp_path):
    return write_dataset_atomic(surface, tmp_path / "surface.h5")


def test_a_value_changed_in_place_is_refused_naming_the_file(path):
    with h5py.File(path, "r+") as f:
        f["alpha"][1, 1] = f["alpha"][1, 1] * (1 + 1e-12)
    with pytest.raises(ValueError, match=rf"{path}: its values do not match the checksum"):
        load_surface(path)
    with pytest.raises(ValueError, match="do not match the checksum"):
        load_dataset(path)


def test_corrupted_bytes_of_the_data_are_refused(surface, path):
    with h5py.File(path, "r") as f:
        offset = f["alpha"].id.get_offset()
    raw = bytearray(path.read_bytes())
    raw[offset + 8] ^= 0x01  # one bit of alpha[0, 1]
    path.write_bytes(bytes(raw))
    with pytest.raises(ValueError, match=str(path)):
        load_surface(path)


def test_a_truncated_file_names_itself(path):
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) // 2])
    with pytest.raises(ValueError, match=rf"{path} is not a readable netCDF4/HDF5 file"):
        load_surface(path)


def test_a_surface_without_its_checksum_is_refused(surface, path):
    with h5py.File(path, "r+") as f:
        del f.attrs[DIGEST_ATTR]
    with pytest.raises(ValueError, match=rf"{path} carries no checksum"):
        load_surface(path)


@pytest.mark.parametrize("alpha, first", [(np.nan, "nan"), (-1.0, "-1.0")], ids=["all NaN", "negative"])
def test_a_solved_point_needs_a_finite_alpha_at_least_zero(surface, tmp_path, alpha, first):
    bad = surface.assign(alpha=surface.alpha * 0 + alpha)
    assert (bad.status.values == 0).all()
    path = write_dataset_atomic(bad, tmp_path / "surface.h5")
    with pytest.raises(
        ValueError, match=rf"solved \(status 0\) with alpha not a finite number >= 0, first alpha = {first}"
    ):
        load_surface(path)


def test_a_failed_point_may_carry_nan(surface, tmp_path):
    alpha = surface.alpha.values.copy()
    status = surface.status.values.copy()
    alpha[0, 1], status[0, 1] = np.nan, 6
    ok = surface.assign(alpha=(surface.alpha.dims, alpha), status=(surface.status.dims, status))
    back = load_surface(write_dataset_atomic(ok, tmp_path / "surface.h5"))
    assert np.isnan(back.alpha.values[0, 1]) and DIGEST_ATTR not in back.attrs
