"""The constant load pressing the bodies together: an acceleration ``accel`` or a force ``force``."""

import math

import numpy as np

from contactalpha.validation import check_scalar


def positive(name: str, value: float) -> float:
    """``value`` as a float, checked > 0 and finite; else ValueError naming ``name`` and the range."""
    return check_scalar(name, value, 0.0, math.inf, lo_open=True, hi_open=True)


def checked_load(accel: float | None, force: float | None) -> tuple[float, bool]:
    """``(value, is_force)``: exactly one of ``accel`` (m/s^2) and ``force`` (N), checked >= 0."""
    if (accel is None) == (force is None):
        raise ValueError(
            f"give exactly one of accel (m/s^2) and force (N); got accel = {accel!r}, force = {force!r}"
        )
    if force is None:
        return check_scalar("accel", accel, 0.0, np.inf, hi_open=True), False
    return check_scalar("force", force, 0.0, np.inf, hi_open=True), True


def scene_accel(mass: float, accel: float | None = None, force: float | None = None) -> float:
    """Relative acceleration of the load from exactly one of ``accel`` (m/s^2) and ``force`` (N)."""
    load, is_force = checked_load(accel, force)
    return load / positive("mass", mass) if is_force else load
