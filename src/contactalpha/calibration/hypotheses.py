"""Restitution hypotheses a drop test is fitted with: one registry of ``Hypothesis`` values.

"Law" names a contact law only (``contactalpha.laws``); a *hypothesis* here is what stays constant
from bounce to bounce in a contact law (their names and fields still say "law" where they mean the
contact law).  A hypothesis says what one contact does to a ball that lands at approach speed ``v`` under the
constant acceleration ``a`` (gravity plus a push): the rebound speed and how long the contact
lasts.  The three laws here are the package's Hunt-Crossley n = 3/2 contact
``f = k delta^{3/2} (1 + alpha delta_dot / v)`` integrated exactly by ``engine.kernel`` (one
scaled impact, paper Eq. 24), and differ only in what stays constant from bounce to bounce:

``hc_eps`` (the default)
    Stronge's energetic restitution ``eps`` of the material; each contact's alpha is the exact
    ``alpha(eps, xi_i)`` at that contact's influence factor (the package's own bounce
    prediction, ``scene.bounces.predict_bounces`` with ``model="exact"``).  Gravity stays in
    the contact, so ``e_N`` falls at the slow last bounces.
``hc_damping``
    The damping coefficient ``d = alpha / v`` (s/m) of the material, Hunt and Crossley's own
    assumption and Simbody's fixed ``dissipation`` (``c = 2 d / 3``); ``alpha_i = d v_i``, so
    ``e_N`` rises as the bounces slow down, against gravity's fall.
``constant_e``
    The null model: the load is left out of the contact (the paper's case B) and alpha is the
    exact unloaded one for ``e``, so every bounce has ``e_N = e`` exactly, with the Hertz
    contact duration.  It differs from ``hc_eps`` only in gravity inside the contact.

Each law is fitted with its stiffness ``k``; a law whose ``k`` shows only in the contact
durations marks it ``timing_only`` (heights alone cannot see it).  Add a law with ``register``.
"""

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from contactalpha.engine.codes import N_REC, OK, OUT_STATE, OUT_STATUS, OUT_T_END, OUT_V_END, SEPARATION
from contactalpha.engine.driver import ATOL, MAX_STEPS, RTOL
from contactalpha.engine.exact import alpha_exact
from contactalpha.engine.kernel import impact_kernel
from contactalpha.engine.scaling import influence_factor
from contactalpha.engine.table import EPS_MIN, XI_MAX
from contactalpha.models import alpha as model_alpha

NO_RECORD = np.empty((0, N_REC))


@dataclass(frozen=True)
class Param:
    """One fitted parameter of a law.

    Attributes
    ----------
    name, unit, label : key, SI unit, text for tables.
    lo, hi : valid range (the fit's bounds).
    log : fitted as log10 (a scale parameter).
    timing_only : the law's observable consequences of it are contact durations only.
    """

    name: str
    unit: str
    label: str
    lo: float
    hi: float
    log: bool = False
    timing_only: bool = False

    def to_fit(self, value):
        """Natural value -> fitting coordinate."""
        return math.log10(value) if self.log else float(value)

    def from_fit(self, x):
        """Fitting coordinate -> natural value."""
        return float(10.0**x) if self.log else float(x)

    @property
    def fit_bounds(self):
        """Bounds in fitting coordinates."""
        return self.to_fit(self.lo), self.to_fit(self.hi)


@dataclass(frozen=True)
class Contact:
    """One contact: rebound speed (m/s, 0 without separation), duration (s), separated, status."""

    v_out: float
    duration: float
    separated: bool
    status: str


@dataclass(frozen=True)
class Hypothesis:
    """A restitution law: its parameters and what one contact does.

    Attributes
    ----------
    name, label, description : registry key, legend text, one sentence.
    params : tuple of ``Param`` (the law's own; the stiffness is one of them).
    contact : ``contact(values, mass, accel, v) -> Contact``, ``values`` a dict of natural values.
    start : ``start(e, v) -> dict``: the law's parameters (stiffness aside) for a rough
        restitution ``e`` at a typical approach speed ``v``, to start a fit.
    engine_inputs : ``engine_inputs(values, mass, accel, v) -> (damping, stiffness)``: the contact
        law's dimensionless damping (alpha, zeta, beta) and its physical stiffness (N/m^1.5 or N/m)
        at a contact of approach speed ``v``: what the engines that run ``contact_law`` take.
    contact_law : the name of the contact law (``contactalpha.laws``) whose engines run this law.
    constant_damping : the engines' physical damping is the law's fitted constant (it holds for
        every bounce, not only the first).
    given : settings of the contact law that are given, not fitted, with their defaults
        (MuJoCo's impedance ``d``); ``calibrate`` takes them by name and reports them.
    """

    name: str
    label: str
    description: str
    params: tuple
    contact: Callable
    start: Callable
    engine_inputs: Callable
    contact_law: str = "hunt_crossley"
    constant_damping: bool = False
    given: dict = field(default_factory=dict)

    @property
    def names(self):
        """Parameter names, in fitting order."""
        return tuple(p.name for p in self.params)


STIFFNESS = Param("stiffness", "N/m^1.5", "Hertz stiffness k", 1e3, 1e13, log=True)


def hc_contact(alpha, mass, stiffness, accel, v, loaded=True):
    """One exact Hunt-Crossley n = 3/2 contact at approach speed ``v``, in SI units.

    Parameters
    ----------
    alpha : float
        Damping factor of this contact.
    mass, stiffness, accel, v : float
        kg, N/m^1.5, m/s^2 (the constant load per unit mass), m/s.
    loaded : bool
        Keep the load in the contact (case A) or leave it out (case B).

    Returns
    -------
    Contact
    """
    ds = (1.25 * mass * (v * v) / stiffness) ** 0.4
    load = accel * ds / (v * v) if loaded else 0.0
    out, _ = impact_kernel(alpha, load, RTOL, ATOL, MAX_STEPS, NO_RECORD, np.inf)
    status = "ok" if int(out[OUT_STATUS]) == OK else f"impact status {int(out[OUT_STATUS])}"
    sep = int(out[OUT_STATE]) == SEPARATION
    return Contact(-out[OUT_V_END] * v if sep else 0.0, out[OUT_T_END] * ds / v, sep, status)


def exact_loaded_alpha(eps, xi):
    """Exact ``alpha(eps, xi)``: the shipped table, the solver beyond its domain."""
    name = "exact" if eps >= EPS_MIN and xi <= XI_MAX else "exact_solve"
    return float(model_alpha(eps, xi, model=name))


def _hc_eps(values, mass, accel, v):
    k = values["stiffness"]
    xi = influence_factor(mass, k, v, accel)
    return hc_contact(exact_loaded_alpha(values["eps"], xi), mass, k, accel, v)


def _hc_damping(values, mass, accel, v):
    return hc_contact(values["damping"] * v, mass, values["stiffness"], accel, v)


def _constant_e(values, mass, accel, v):
    return hc_contact(float(alpha_exact(values["e"])), mass, values["stiffness"], accel, v, loaded=False)


def _hc_eps_inputs(values, mass, accel, v):
    k = values["stiffness"]
    return exact_loaded_alpha(values["eps"], influence_factor(mass, k, v, accel)), k


def _hc_damping_inputs(values, mass, accel, v):
    return values["damping"] * v, values["stiffness"]


def _constant_e_inputs(values, mass, accel, v):
    # The null model leaves the load out of the contact: its alpha is the unloaded one for e.
    return float(alpha_exact(values["e"])), values["stiffness"]


HYPOTHESES: dict[str, Hypothesis] = {}


def register(law):
    """Add or replace a law in the registry."""
    HYPOTHESES[law.name] = law


register(
    Hypothesis(
        "hc_eps",
        "Hunt–Crossley, constant ε (exact α per impact)",
        "material eps fixed; alpha = exact alpha(eps, xi_i) at each impact, gravity in the contact",
        (Param("eps", "1", "Stronge's restitution ε", 0.02, 1.0), STIFFNESS),
        _hc_eps,
        lambda e, v: {"eps": e},
        _hc_eps_inputs,
    )
)
register(
    Hypothesis(
        "hc_damping",
        "Hunt–Crossley, constant damping d (α = d v⁻)",
        "material damping d = alpha / v fixed (Simbody's dissipation c = 2 d / 3); gravity in the contact",
        (Param("damping", "s/m", "damping d = α / v⁻", 1e-6, 1e3, log=True), STIFFNESS),
        _hc_damping,
        lambda e, v: {"damping": float(alpha_exact(e)) / v},
        _hc_damping_inputs,
    )
)
register(
    Hypothesis(
        "constant_e",
        "constant e_N (null: no load in the contact)",
        "every bounce e_N = e; Hertz contact duration without the load (case B)",
        (
            Param("e", "1", "Newton's restitution e_N", 0.02, 1.0),
            Param(**{**STIFFNESS.__dict__, "timing_only": True}),
        ),
        _constant_e,
        lambda e, v: {"e": e},
        _constant_e_inputs,
    )
)
DEFAULT_HYPOTHESIS = "hc_eps"
# Laws ``calibrate`` fits when none are named: the package's own exact n = 3/2 engine.  The
# family's laws (``calibration.family``) are fitted on request (``laws="all"`` or by name): their
# general integrator costs seconds per fit.
DEFAULT_HYPOTHESES = ("hc_eps", "hc_damping", "constant_e")
ALL = "all"


def hypothesis_names(laws=None):
    """Names to fit: ``DEFAULT_HYPOTHESES`` for None, every registered one for ``"all"``, else checked."""
    if laws is None:
        return list(DEFAULT_HYPOTHESES)
    if laws == ALL or (not isinstance(laws, str) and list(laws) == [ALL]):
        return list(HYPOTHESES)
    if isinstance(laws, str):
        laws = [laws]
    names = [check_hypothesis(n).name for n in laws]
    if not names:
        raise ValueError("laws is empty; choose from " + ", ".join(map(repr, HYPOTHESES)))
    return names


def check_hypothesis(name):
    """The registered law called ``name``; ValueError naming the choices otherwise."""
    if name not in HYPOTHESES:
        raise ValueError(f"law = {name!r} is not one of {', '.join(map(repr, HYPOTHESES))}, or 'all'")
    return HYPOTHESES[name]
