"""The front door's checks of its arguments: one scene by name, a batch by name and first bad index."""

from typing import Any

import numpy as np

from contactalpha.adapters.registry import adapter, check_radius_used
from contactalpha.engine.solver import no_kinematic_inverse
from contactalpha.laws import DEFAULT_LAW, get_law
from contactalpha.laws.law import ContactLaw
from contactalpha.scene.load import positive
from contactalpha.validation import PLAIN_FLOATS, check_range, check_scalar


def is_batch(*values: Any) -> bool:
    """True when any input is an array (or a list) of more than a plain number."""
    return any(v is not None and type(v) not in PLAIN_FLOATS and np.ndim(v) > 0 for v in values)


def checked_target(eps: float | None, e_n: float | None) -> tuple[float, str]:
    """``(value, restitution)`` from exactly one of ``eps`` and ``e_N``, checked."""
    if (eps is None) == (e_n is None):
        raise ValueError(
            f"give exactly one of eps (energetic) and e_N (kinematic); got eps = {eps!r}, e_N = {e_n!r}"
        )
    if e_n is None:
        return check_scalar("eps", eps, 0.0, 1.0), "energetic"
    e_n = check_scalar("e_N", e_n, 0.0, 1.0)
    if e_n == 0.0:
        raise no_kinematic_inverse()
    return e_n, "kinematic"


def require_scene(mass: object, stiffness: object, approach_speed: object) -> None:
    """ValueError naming the first of ``mass``, ``stiffness`` and ``approach_speed`` not given."""
    for name, given in (("mass", mass), ("stiffness", stiffness), ("approach_speed", approach_speed)):
        if given is None:
            raise ValueError(f"{name} is required (SI units)")


def check_rows(
    name: str, value: Any, lo: float, hi: float, *, lo_open: bool = False, hi_open: bool = False
) -> np.ndarray:
    """``value`` as a float array in range; else ValueError naming ``name``, its first bad index and value."""
    try:
        return np.asarray(check_range(name, value, lo, hi, lo_open=lo_open, hi_open=hi_open), dtype=float)
    except ValueError as err:
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise err from None
        with np.errstate(invalid="ignore"):
            good = (arr > lo if lo_open else arr >= lo) & (arr < hi if hi_open else arr <= hi)
        bad = np.argwhere(~good)
        if arr.ndim == 0 or bad.size == 0:
            raise
        index = int(bad[0][0]) if arr.ndim == 1 else tuple(int(i) for i in bad[0])
        left, right = "(" if lo_open else "[", ")" if hi_open else "]"
        shown = float(arr[tuple(bad[0])])
        raise ValueError(
            f"{name}[{index}] = {shown!r} is outside the valid range {left}{lo}, {hi}{right} "
            f"(the first bad index of {name}; {len(bad)} of {arr.size} bad): the whole batch is refused"
        ) from None


def broadcast_shape(**arrays: Any) -> tuple[int, ...]:
    """The broadcast shape of the named arrays (None skipped); else ValueError naming the two that clash."""
    shape, owner = (), None
    for name, value in arrays.items():
        if value is None:
            continue
        try:
            joined = np.broadcast_shapes(shape, np.shape(value))
        except ValueError:
            raise ValueError(
                f"{name} has shape {np.shape(value)}, which does not broadcast with {owner}'s shape {shape}: "
                "give arrays of one shape (or plain numbers)"
            ) from None
        owner = name if joined != shape else owner
        shape = joined
    return shape


def checked_radius(radius: Any, batch: bool) -> float | np.ndarray:
    """``radius`` checked > 0 and finite: by name for one scene, by its first bad index for a batch."""
    if not batch:
        return positive("radius", radius)
    return check_rows("radius", radius, 0.0, np.inf, lo_open=True, hi_open=True)


def check_load_rows(accel: Any, force: Any) -> None:
    """A batch at the step needs every row's load > 0, as one scene does: else the whole batch is refused."""
    name, value = ("accel", accel) if force is None else ("force", force)
    try:
        check_rows(name, value, 0.0, np.inf, lo_open=True, hi_open=True)
    except ValueError as err:
        raise ValueError(f"timestep needs a load pressing the bodies together in every row: {err}") from None


def law_reads_radius(law: ContactLaw) -> bool:
    """True when some engine of ``law`` reads the radius (``check_radius_used`` accepts one)."""
    try:
        check_radius_used(law, 1.0)
    except ValueError:
        return False
    return True


def law_of(law: str | ContactLaw | None, engine: str | None) -> ContactLaw:
    """The law to solve for: ``law`` (default Hunt-Crossley), or ``engine``'s (they must agree)."""
    if engine is None:
        return get_law(DEFAULT_LAW if law is None else law)
    engines_law = adapter(engine).law
    if law is not None and get_law(law).name != engines_law.name:
        raise ValueError(
            f"law = {get_law(law).name!r} is not engine {engine!r}'s law {engines_law.name!r}: "
            "give engine= or law=, not both"
        )
    return engines_law
