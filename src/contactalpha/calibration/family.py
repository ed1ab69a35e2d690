"""The other engines' contact laws (``contactalpha.laws``, issue 26) as calibration hypotheses.

Each law of the family other than Hunt–Crossley n = 3/2 (which is ``hc_damping`` here, on the
package's own engine) is registered with its stiffness and its engine's damping coefficient held
constant across bounces, as an engine user sets them once: Drake's ``d`` (s/m), the
spring–dashpot's ``c`` (N s/m), Tsuji's ``eta`` and MuJoCo's ``b`` (1/s, with the stiffness ``s``
per unit mass and the law's default impedance).  One contact is one call of the family's
reference impact (``hypotheses.integrate.impact_kernel``), whose end time gives the contact duration.
"""

import math
from dataclasses import dataclass

from contactalpha.engine.codes import OK, SEPARATION
from contactalpha.laws import get_law
from contactalpha.laws.integrate import ATOL, MAX_STEPS, R_EN, R_STATE, R_STATUS, R_TE, RTOL, impact_kernel

from .hypotheses import Contact, Hypothesis, Param, register


@dataclass(frozen=True)
class FamilyEntry:
    """How one family law is calibrated: its damping and stiffness as fitted parameters.

    Attributes
    ----------
    law : name in ``contactalpha.laws``.
    damping, stiffness : ``Param`` of the engine's damping coefficient and stiffness.
    per_unit_mass : the law is written per unit mass (MuJoCo): scales use mass 1.
    """

    law: str
    damping: Param
    stiffness: Param
    per_unit_mass: bool = False


def _log(name, unit, label, lo, hi):
    return Param(name, unit, label, lo, hi, log=True)


ENTRIES = (
    FamilyEntry(
        "hunt_crossley_linear",
        _log("damping", "s/m", "Drake's dissipation d", 1e-6, 1e3),
        _log("stiffness", "N/m", "stiffness k", 1e1, 1e11),
    ),
    FamilyEntry(
        "kelvin_voigt",
        _log("damping", "N s/m", "dashpot c", 1e-6, 1e6),
        _log("stiffness", "N/m", "stiffness k", 1e1, 1e11),
    ),
    FamilyEntry(
        "hertz_tsuji",
        _log("damping", "N s/m^1.25", "Tsuji's eta", 1e-4, 1e8),
        _log("stiffness", "N/m^1.5", "Hertz stiffness k", 1e3, 1e13),
    ),
    FamilyEntry(
        "mujoco_soft",
        _log("damping", "1/s", "MuJoCo's b (solref damping)", 1e-4, 1e6),
        _log("stiffness", "1/s^2", "MuJoCo's s (stiffness per unit mass)", 1e0, 1e11),
        per_unit_mass=True,
    ),
)


def _law_at(entry, values):
    """The contact law of ``entry`` with the given settings found in ``values`` (MuJoCo's impedance)."""
    base = get_law(entry.law)
    return get_law(base, **{name: values[name] for name in given_settings(base) if name in values})


def given_settings(law):
    """The contact law's given (not fitted) settings and their defaults: MuJoCo's impedance ``d``."""
    return {} if law.impedance_range is None else {"impedance": law.impedance}


def family_contact(entry):
    """``Hypothesis.contact`` of a family law with constant engine damping and stiffness."""

    def contact(values, mass, accel, v):
        law = _law_at(entry, values)
        m = 1.0 if entry.per_unit_mass else mass
        k, c = values["stiffness"], values["damping"]
        ds = law.length_scale(m, k, v)
        A = accel * ds / (v * v)
        p = float(law.damping_from_physical(c, m, k, v))
        x_eq = float(law.equilibrium(A))
        row = impact_kernel(law.code, p, A, law.impedance, x_eq, RTOL, ATOL, MAX_STEPS)
        status = "ok" if int(row[R_STATUS]) == OK else f"impact status {int(row[R_STATUS])}"
        sep = int(row[R_STATE]) == SEPARATION
        return Contact(row[R_EN] * v if sep else 0.0, row[R_TE] * ds / v, sep, status)

    return contact


def family_engine_inputs(entry):
    """``Hypothesis.engine_inputs`` of a family law: its damping parameter and the physical stiffness."""

    def engine_inputs(values, mass, accel, v):
        law = _law_at(entry, values)
        m = 1.0 if entry.per_unit_mass else mass
        p = float(law.damping_from_physical(values["damping"], m, values["stiffness"], v))
        return p, values["stiffness"] * (mass if entry.per_unit_mass else 1.0)

    return engine_inputs


def _middle(param):
    return lambda e, v: {param.name: math.sqrt(param.lo * param.hi)}


def register_family():
    """Register every ``ENTRIES`` law (named ``<law>_damping``) in the calibration registry."""
    for entry in ENTRIES:
        law = get_law(entry.law)
        register(
            Hypothesis(
                f"{entry.law}_damping",
                f"{law.label}, constant {entry.damping.label}",
                f"{law.formula}; damping and stiffness fixed across bounces ({', '.join(law.engines)})",
                (entry.damping, entry.stiffness),
                family_contact(entry),
                _middle(entry.damping),
                family_engine_inputs(entry),
                contact_law=law.name,
                constant_damping=True,
                given=given_settings(law),
            )
        )


register_family()
FAMILY_HYPOTHESES = tuple(f"{e.law}_damping" for e in ENTRIES)
