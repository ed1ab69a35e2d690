"""The ``Model`` value: a contact model and its capabilities as fields."""

from collections.abc import Callable
from dataclasses import dataclass

from contactalpha.laws import DEFAULT_LAW, get_law

ENERGETIC = ("energetic",)
KINEMATIC = ("kinematic",)
BOTH = ("energetic", "kinematic")


@dataclass(frozen=True)
class Model:
    """A contact model: the damping of its law for a target restitution and load.

    Attributes
    ----------
    name : registry key.
    label : name for legends.
    source : citation.
    formula : the formula, as text.
    uses_xi : False for models derived without an external load.
    fn : callable ``fn(target, xi) -> damping`` on validated float arrays.
    law : the contact law whose damping it gives (``contactalpha.laws.get_law``).
    restitutions : the restitutions it takes: Stronge's "energetic" eps, Newton's "kinematic" e_N.
    handles_zero : True if it takes eps = 0 (the onset of no restitution, at xi > 0).
    kinematic_fn : ``fn`` for ``restitution="kinematic"`` when it differs from ``fn``.
    validates : True if ``fn`` checks its own input (in one jitted pass, at formula speed).
    scalar_table : True if plain-float calls take the packed table's scalar fast path.
    solver : True if it runs the impact solver (slow; the warm-up's engine part compiles it).
    impedance : the law's shape it assumes (MuJoCo's impedance d), None for the law's default.
    """

    name: str
    label: str
    source: str
    formula: str
    uses_xi: bool
    fn: Callable
    law: str = DEFAULT_LAW
    restitutions: tuple = ENERGETIC
    handles_zero: bool = False
    kinematic_fn: Callable | None = None
    validates: bool = False
    scalar_table: bool = False
    solver: bool = False
    impedance: float | None = None

    @property
    def contact_law(self):
        """The ``ContactLaw`` value this model's damping belongs to."""
        if self.impedance is None:
            return get_law(self.law)
        return get_law(self.law, impedance=self.impedance)
