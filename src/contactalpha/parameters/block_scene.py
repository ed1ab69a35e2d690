"""``BlockScene``: what an engine adapter's ``parameters`` reads of a scene to build its block."""

from dataclasses import dataclass


@dataclass(frozen=True)
class BlockScene:
    """Mass (kg), the law's physical stiffness, approach speed (m/s) and radius (m, or None).

    Plain numbers for one scene, arrays of one shape for a batch.
    """

    mass: object
    stiffness: object
    approach_speed: object
    radius: object
