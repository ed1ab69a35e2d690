"""The names other DEM codes use, converted to and from this package's laws and damping.

Every code below maps a restitution ``e`` to a damping with the zero-load formula of the linear
oscillator, ``ζ(e) = −ln e / √(π² + ln² e)``; the package's laws give the damping that delivers
``e`` under the scene's load instead (``contactalpha params``), and these functions turn it into
the code's own input.  Read from each code's source:

- **LIGGGHTS** (``model hertz``; ``src/normal_model_hertz.h``, ``NormalModel<HERTZ>::surfacesIntersect``,
  and ``src/global_properties.cpp``, ``MODEL_PARAMS::createBetaEff``): ``coefficientRestitution`` e
  gives ``β_L = ln e / √(ln² e + π²)`` (a *negative* number), ``S_n = 2 Y* √(R* δ)``,
  ``γ_n = −2 √(5/6) β_L √(S_n m*)`` and ``F = (4/3) Y* √(R* δ) δ + γ_n δ̇``, floored at 0 only with
  ``limitForce on``.  With ``K = (4/3) Y* √R*`` that is ``η = −√5 β_L √(m* K)``: the package's
  ``β = −√5 β_L`` (``hertz_tsuji`` with ``limitForce on``, ``hertz_tsuji_unfloored`` without).
- **Chrono SMC** (``ChDefaultContactForceTorqueSMC::CalculateForce``, Hertz with material
  properties): the same ``β``, ``S_n`` and ``g_n`` from the composite ``cr_eff``; the normal force is
  floored at 0: ``hertz_tsuji``.  Give both bodies the same restitution so that any composition
  rule of the pair gives it.
- **Yade** ``ViscElMat(en, tc)`` (``pkg/dem/ViscoelasticPM.cpp``,
  ``Ip2_ViscElMat_ViscElMat_ViscElPhys::Calculate_ViscElMat_ViscElMat_ViscElPhys`` and
  ``computeForceTorqueViscEl``): a linear spring-dashpot ``F = max(0, k_n δ + c_n δ̇)`` (the
  package's ``kelvin_voigt``) with ``k_n = (π² + ln² en) m_R / tc²`` and ``c_n = −2 ln en m_R / tc``,
  where ``m_R = m_1 m_2 / (m_1 + m_2)`` and a body of zero mass (a fixed wall or facet) takes the
  other's: a sphere on a wall gets ``m_R = m / 2`` while it moves with ``m``, so it sees
  ``ζ = ζ(en) / √2`` and lasts ``√2 tc`` (``yade_reduced_mass``).
- **MFIX-DEM** linear spring-dashpot (``DES_EN_INPUT``, ``KN``; ``model/des/check_data/
  check_solids_dem.f``, ``CHECK_SOLIDS_DEM_COLLISION_LSD``, and ``calc_force_dem.f``):
  ``DES_ETAN = 2 √(KN m*) |ln e| / √(π² + ln² e)``, ``m*`` the reduced mass (the particle's own
  against a wall, ``DES_EN_WALL_INPUT`` and ``KN_W``), and ``F = KN δ + DES_ETAN δ̇`` summed without a
  floor: the unfloored spring-dashpot, whose e_N at zero load is exactly ``DES_EN_INPUT``.

``reduced_mass`` is the mass a free pair's contact sees (give it as ``mass=`` to ``params``).
"""

import math
from dataclasses import dataclass

import numpy as np

from contactalpha.validation import check_positive, check_range

SQRT5 = math.sqrt(5.0)


def reduced_mass(m1, m2=None):
    """``m1 m2 / (m1 + m2)``, kg: the mass of a free pair's contact; without ``m2`` a wall's: ``m1``."""
    m1 = np.asarray(check_positive("m1", m1), dtype=float)
    if m2 is None:
        return float(m1) if m1.ndim == 0 else m1
    m2 = np.asarray(check_positive("m2", m2), dtype=float)
    out = m1 * m2 / (m1 + m2)
    return float(out) if out.ndim == 0 else out


def classic_zeta(e):
    """``ζ(e) = −ln e / √(π² + ln² e)``: the linear oscillator's damping ratio every code starts from."""
    ln = np.log(np.asarray(check_range("e", e, 0.0, 1.0, lo_open=True), dtype=float))
    return -ln / np.sqrt(math.pi**2 + ln * ln)


def restitution_of_zeta(zeta):
    """``e = exp(−π ζ / √(1 − ζ²))``, the inverse of ``classic_zeta`` (0 <= ζ < 1)."""
    z = np.asarray(check_range("zeta", zeta, 0.0, 1.0, hi_open=True), dtype=float)
    return np.exp(-math.pi * z / np.sqrt(1.0 - z * z))


# --- LIGGGHTS and Chrono SMC: Hertz with Tsuji damping -----------------------------------------
def liggghts_beta(e):
    """LIGGGHTS' ``betaeff`` of ``coefficientRestitution`` e: ``ln e / √(ln² e + π²)`` (negative)."""
    return -classic_zeta(e)


def beta_from_liggghts(beta_liggghts):
    """The package's Tsuji ``β`` (``η = β √(m K)``) of LIGGGHTS' ``betaeff``: ``β = −√5 β_L``."""
    b = np.asarray(check_range("beta_liggghts", beta_liggghts, -1.0, 0.0, lo_open=True), dtype=float)
    return -SQRT5 * b


def liggghts_restitution(beta):
    """The ``coefficientRestitution`` to give LIGGGHTS (or Chrono SMC's ``cr``) for the package's ``β``.

    ``β`` is ``params --law hertz_tsuji``'s (or ``hertz_tsuji_unfloored``'s) answer under the
    scene's load; ``β_L = −β/√5`` and ``e = exp(π β_L / √(1 − β_L²))`` (0 <= β < √5).
    """
    b = np.asarray(check_range("beta", beta, 0.0, SQRT5, hi_open=True), dtype=float)
    return restitution_of_zeta(b / SQRT5)


def beta_from_restitution(e):
    """The package's ``β`` that LIGGGHTS, Chrono SMC and LAMMPS' ``coeff_restitution`` set for e: √5 ζ(e)."""
    return SQRT5 * classic_zeta(e)


# --- Yade ViscElMat: linear spring-dashpot with the floor ---------------------------------------
def yade_reduced_mass(m1, m2=0.0):
    """Yade's ``massR``: ``m1 m2 / (m1 + m2)``, a zero mass (a fixed wall) replaced by the other's (m1/2)."""
    m1 = float(check_positive("m1", m1))
    m2 = float(check_range("m2", m2, 0.0, math.inf, hi_open=True))
    m2 = m1 if m2 == 0.0 else m2
    return m1 * m2 / (m1 + m2)


def yade_stiffness_damping(en, tc, mass_r):
    """``(k_n, c_n)`` of ``ViscElMat(en, tc)`` for a contact of Yade's ``massR`` ``mass_r``: N/m, N s/m."""
    en = float(check_range("en", en, 0.0, 1.0, lo_open=True))
    tc, mass_r = float(check_positive("tc", tc)), float(check_positive("mass_r", mass_r))
    ln = math.log(en)
    return (math.pi**2 + ln * ln) * mass_r / tc**2, -2.0 * ln * mass_r / tc


def yade_material(stiffness, damping, mass_r):
    """``(en, tc)`` to give ``ViscElMat`` for the spring-dashpot ``(k, c)`` (N/m, N s/m) at ``massR``.

    The inverse of ``yade_stiffness_damping``: ``a = k/m_R``, ``b = c/m_R``, ``tc = π / √(a − b²/4)``,
    ``en = exp(−b tc / 2)``; ValueError where ``(k, c)`` is overdamped for ``m_R`` (no ``tc``).
    """
    k, c = (
        float(check_positive("stiffness", stiffness)),
        float(check_range("damping", damping, 0.0, math.inf)),
    )
    mass_r = float(check_positive("mass_r", mass_r))
    a, b = k / mass_r, c / mass_r
    if a - 0.25 * b * b <= 0.0:
        raise ValueError(
            f"damping = {c!r} N s/m is critical or over for stiffness = {k!r} N/m at massR = {mass_r!r} kg: "
            f"ViscElMat's (en, tc) need c < 2 sqrt(k massR) = {2.0 * math.sqrt(k * mass_r)!r}"
        )
    tc = math.pi / math.sqrt(a - 0.25 * b * b)
    return math.exp(-0.5 * b * tc), tc


def zeta_of_yade(en, tc, mass_r, mass):
    """The ``kelvin_voigt`` ζ that a contact of reduced mass ``mass`` sees in ``ViscElMat(en, tc)``."""
    k, c = yade_stiffness_damping(en, tc, mass_r)
    return c / (2.0 * math.sqrt(k * float(check_positive("mass", mass))))


# --- MFIX-DEM linear spring-dashpot: no floor ---------------------------------------------------
def mfix_damping(kn, en, mass_eff):
    """MFIX's ``DES_ETAN`` (N s/m) of ``KN`` (N/m) and ``DES_EN_INPUT`` for the reduced mass ``mass_eff``."""
    kn, mass_eff = float(check_positive("kn", kn)), float(check_positive("mass_eff", mass_eff))
    return 2.0 * math.sqrt(kn * mass_eff) * float(classic_zeta(en))


def mfix_restitution(zeta):
    """The ``DES_EN_INPUT`` whose ``DES_ETAN`` is the spring-dashpot damping ratio ``zeta``."""
    return float(restitution_of_zeta(zeta))


@dataclass(frozen=True)
class DemCode:
    """One DEM code's contact convention: ``name``, its inputs, the package law it applies, its source."""

    name: str
    inputs: str
    law: str | None
    floored: bool
    source: str


DEM_CODES = (
    DemCode("LIGGGHTS", "coefficientRestitution, youngsModulus, poissonsRatio (model hertz)",
            "hertz_tsuji_unfloored", False, "normal_model_hertz.h; limitForce on: hertz_tsuji"),
    DemCode("Chrono SMC", "restitution (cr), young_modulus, poisson_ratio (Hertz)", "hertz_tsuji", True,
            "ChDefaultContactForceTorqueSMC::CalculateForce"),
    DemCode("Yade ViscElMat", "en, tc", "kelvin_voigt", True, "pkg/dem/ViscoelasticPM.cpp"),
    DemCode("MFIX-DEM", "DES_EN_INPUT, KN (linear spring-dashpot)", None, False,
            "check_solids_dem.f CHECK_SOLIDS_DEM_COLLISION_LSD; calc_force_dem.f"),
    DemCode("LAMMPS", "damping coeff_restitution | tsuji | viscoelastic, hertz/material E e nu",
            "hertz_tsuji_unfloored", False, "src/GRANULAR (contactalpha.adapters.lammps_granular)"),
)  # fmt: skip
