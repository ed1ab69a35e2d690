"""Does the load matter here?  What ignoring a scene's load does to the delivered e_N, for any law.

Ignoring the load is what a DEM code's restitution mapping does: it takes the law's damping for the
target at zero load (``xi = 0``).  ``load_effect`` puts that damping into the scene's own load
factor and reports the e_N (or eps) it delivers there, how far that is from the target, and whether
it is farther than ``tol``: then the load matters and the loaded damping (``params``) is needed.
``contactalpha params`` prints its line under every law's block.
"""

import math
from dataclasses import asdict, dataclass

from contactalpha.laws import get_law
from contactalpha.laws.domain import target_name

# Tolerance on the delivered restitution below which the load is said not to matter.
LOAD_TOL = 1e-3


@dataclass(frozen=True)
class LoadEffect:
    """What the zero-load damping delivers in the loaded scene.

    Attributes
    ----------
    law, restitution : the law and the restitution judged ("kinematic" e_N, "energetic" eps).
    target : the restitution asked for; ``xi`` the scene's load factor.
    damping_ignoring : the law's damping for the target at zero load.
    delivered_ignoring : what that damping delivers at ``xi`` (NaN where the impact fails).
    change : ``delivered_ignoring - target``.
    tol : the tolerance; ``matters`` is ``|change| > tol`` (True where the impact failed).
    """

    law: str
    restitution: str
    target: float
    xi: float
    damping_ignoring: float
    delivered_ignoring: float
    change: float
    tol: float
    matters: bool

    def to_dict(self) -> dict:
        """Plain data (for ``--json``)."""
        return asdict(self)

    def line(self) -> str:
        """One line of text for ``params``."""
        name = target_name(self.restitution)
        if not math.isfinite(self.change):
            return (
                f"load            ignoring it fails: the zero-load {name} damping has no impact "
                f"at xi = {self.xi:.6g}"
            )
        verdict = "matters" if self.matters else "may be ignored"
        return (
            f"load            {verdict}: the zero-load damping delivers {name} = "
            f"{self.delivered_ignoring:.6g} here ({self.change:+.3g}; tolerance {self.tol:g})"
        )


def load_effect(law, target, restitution, mass, stiffness, approach_speed, accel, tol=LOAD_TOL) -> LoadEffect:
    """``LoadEffect`` of the scene: the law's zero-load damping for ``target`` run at the scene's load."""
    law = get_law(law)
    xi = float(law.scene_load_factor(mass, stiffness, approach_speed, accel))
    zero = law.damping_for(target, 0.0, restitution)
    p = float(zero.damping)
    got = math.nan
    if zero.ok:
        r = law.impact(p, xi)
        got = float(r.e_n if restitution == "kinematic" else r.eps)
    change = got - float(target)
    matters = not math.isfinite(change) or abs(change) > tol
    return LoadEffect(law.name, restitution, float(target), xi, p, got, change, float(tol), bool(matters))
