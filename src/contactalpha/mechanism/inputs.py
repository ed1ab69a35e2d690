"""What ``tune`` refuses before it solves: a file too large, coordinates, a step, a link's inertia.

- **The file's size.**  Reading a model is the engine's own compile (MuJoCo's, Drake's parser),
  whose time grows with the file and which cannot be interrupted; a file above
  ``MAX_MODEL_BYTES`` is refused up front, naming its size and the limit.
- **Coordinates.**  ``qpos`` and ``qvel`` are finite numbers.
- **The step.**  A step is a finite number of seconds above 0; and it is shorter than the
  contact's undamped contact time ``pi sqrt(m_eff / k)``, else the engine steps over the contact.
- **Links.**  A link that moves with its own joint has a mass above 0 and an inertia whose
  principal moments are above 0, the rule MuJoCo's compiler applies to its moving bodies; no link
  has a negative mass or an inertia that is not physical (a negative principal moment, or one
  above the sum of the other two).  MuJoCo refuses such models itself and its message names the
  body; Drake's parser replaces a bad inertia by its own with a warning, so ``link_inertias``
  reads the values from the file (URDF ``<inertial>``, SDF ``<inertial>`` with SDFormat's
  defaults where absent).
"""

import math
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from contactalpha.validation import check_scalar

# Largest model file tune reads, bytes.
MAX_MODEL_BYTES = 10_000_000
# The six values of a link's inertia in URDF and SDF.
INERTIA_KEYS = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
# Principal moments below this fraction of the largest one are zero (a singular inertia).
INERTIA_RTOL = 1e-12


def check_model_size(path: str | Path) -> None:
    """ValueError naming the size when the model file is above ``MAX_MODEL_BYTES``."""
    size = os.path.getsize(path)
    if size > MAX_MODEL_BYTES:
        raise ValueError(
            f"model = {str(path)!r} is {size / 1e6:.1f} MB, above the {MAX_MODEL_BYTES / 1e6:g} MB tune "
            "reads: give a model of the mechanism without what does not move with the contact"
        )


def check_coordinates(name: str, values: ArrayLike | None) -> np.ndarray | None:
    """``values`` as a float array, or ValueError naming the first that is not a finite number."""
    if values is None:
        return None
    try:
        arr = np.asarray(values, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {values!r} is not a list of numbers") from None
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] = {float(arr[bad[0]])!r} is not a finite number")
    return arr


def check_timestep(timestep: float | None) -> float | None:
    """The step in s (None stays None); ValueError unless a finite number above 0."""
    if timestep is None:
        return None
    return check_scalar("timestep", timestep, 0.0, math.inf, lo_open=True, hi_open=True)


def check_step_resolves(
    timestep: float | None, effective_mass: float, stiffness: float, name: str = "timestep"
) -> None:
    """ValueError when ``timestep`` is not shorter than the undamped contact time ``pi sqrt(m/k)``."""
    if timestep is None:
        return
    contact_time = math.pi * math.sqrt(effective_mass / stiffness)
    if not timestep < contact_time:
        raise ValueError(
            f"{name} = {timestep!r} s is not shorter than the contact (pi sqrt(m_eff/k) = "
            f"{contact_time:.3g} s undamped): the engine steps over it; give a smaller timestep"
        )


def _numbers(elem, keys, defaults):
    out = []
    for key, default in zip(keys, defaults, strict=True):
        value = elem.get(key) if elem is not None else None
        if value is None and elem is not None and elem.find(key) is not None:
            value = elem.find(key).text
        out.append(default if value is None else float(value))
    return out


def link_inertias(path: str | Path) -> dict[str | None, tuple[float, np.ndarray]]:
    """``{link: (mass, 3x3 inertia)}`` as written in a URDF or SDF file (the SDF's defaults where absent)."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as err:
        raise ValueError(f"model = {str(path)!r} is not well-formed XML: {err}") from None
    urdf = root.tag == "robot"
    out = {}
    for link in root.iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            out[link.get("name")] = (0.0 if urdf else 1.0, np.zeros((3, 3)) if urdf else np.eye(3))
            continue
        mass_elem = inertial.find("mass")
        sdf_mass = mass_elem.text if mass_elem is not None else None
        mass = _numbers(mass_elem, ("value",), (0.0,))[0] if urdf else (
            float(sdf_mass) if sdf_mass is not None else 1.0)  # fmt: skip
        defaults = (0.0,) * 6 if urdf else (1.0, 1.0, 1.0, 0.0, 0.0, 0.0)  # SDFormat's defaults
        ixx, iyy, izz, ixy, ixz, iyz = _numbers(inertial.find("inertia"), INERTIA_KEYS, defaults)
        out[link.get("name")] = (mass, np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]))
    return out


def check_link(name: str | None, mass: float, inertia: np.ndarray, moves: bool) -> None:
    """ValueError naming link ``name`` when its mass or inertia is not physical (see the module doc)."""
    if not math.isfinite(mass) or mass < 0.0 or (moves and mass == 0.0):
        need = "above 0 for a link that moves with its own joint" if moves else "at least 0"
        raise ValueError(f"link {name!r}: mass = {mass!r} kg; it must be {need}")
    if not np.all(np.isfinite(inertia)):
        raise ValueError(f"link {name!r}: its inertia has a value that is not a finite number")
    moments = np.linalg.eigvalsh(inertia)
    scale = max(float(np.max(np.abs(moments))), 1e-300)
    if moments[0] < -INERTIA_RTOL * scale or moments[2] > moments[0] + moments[1] + INERTIA_RTOL * scale:
        raise ValueError(
            f"link {name!r}: principal moments of inertia {tuple(float(x) for x in moments)} kg m^2 are not "
            "physical (each must be >= 0 and at most the sum of the other two)"
        )
    if moves and moments[0] <= INERTIA_RTOL * scale:
        raise ValueError(
            f"link {name!r}: principal moments of inertia {tuple(float(x) for x in moments)} kg m^2: a "
            "link that moves with its own joint needs all three above 0 (a singular inertia)"
        )
