"""The engines' usual restitution mappings, and the exact inverse of each law, as registered models.

Each gives the damping of its law (``Model.law``) for a target restitution; the engines' own
mappings ignore the load.  Their sources:

- ``classic_zeta``: the damping ratio of the linear oscillator *without* the force floor,
  zeta = -ln e / sqrt(pi^2 + ln^2 e) (PhysX, Bullet, ODE and Simscape users' usual choice).
- ``mujoco_dampratio``: MuJoCo's solref = (timeconst, dampratio) in its standard mode makes the soft
  contact's stiffness 1/(timeconst dampratio)^2 and damping 2/timeconst per unit mass whatever the
  impedance, so dampratio *is* zeta; users set it with the classic formula.  ``mujoco_default`` is
  MuJoCo's default dampratio 1.  Neither depends on the impedance; ``mujoco_soft_exact`` assumes
  MuJoCo's default 0.9 (solimp[0]).
- ``tsuji_beta``: the DEM codes' Hertz damping (LIGGGHTS, LAMMPS granular, Chrono SMC)
  gamma_n = 2 sqrt(5/6) beta sqrt(S_n m), S_n = 2 Y* sqrt(R* delta), beta = ln e / sqrt(ln^2 e + pi^2):
  with k = (4/3) Y* sqrt(R*), eta = sqrt(5) |beta| sqrt(m k), i.e. this package's beta = sqrt(5) |beta|.
  ``lammps_coeff_restitution`` is the same number on Tsuji's law without its floor, LAMMPS's default
  (``damping coeff_restitution`` without ``limit_damping``; exact there at zero load).
- ``drake_bound``: Drake documents that the bounce speed after an impact is bounded by 1/d; taking
  that bound as the target rebound, 1/d = e v, gives alpha = d v = 1/e.
"""

import numpy as np

from contactalpha.laws import get_law

from .model import BOTH, KINEMATIC, Model

MUJOCO_DEFAULT_IMPEDANCE = 0.9


def classic_zeta(e, xi=0.0):
    """Damping ratio of the oscillator without the floor: zeta = -ln e / sqrt(pi^2 + ln^2 e).  Ignores xi."""
    ln = np.log(e)
    return -ln / np.sqrt(np.pi**2 + ln**2) + 0.0 * xi


def mujoco_default(e, xi=0.0):
    """MuJoCo's default dampratio, 1 (critical damping), whatever the target.  Ignores xi."""
    return 1.0 + 0.0 * e + 0.0 * xi


def tsuji_beta(e, xi=0.0):
    """The DEM codes' Tsuji damping as this package's beta (eta = beta sqrt(m k)): sqrt(5) zeta(e)."""
    return np.sqrt(5.0) * classic_zeta(e)


def drake_bound(e, xi=0.0):
    """Drake's bound on the bounce speed, 1/d, taken as the target e v: alpha = d v = 1/e.  Ignores xi."""
    return 1.0 / e + 0.0 * xi


def _exact(law_name, restitution, impedance=None):
    law = get_law(law_name) if impedance is None else get_law(law_name, impedance=impedance)

    def fn(target, xi):
        if law.piecewise_linear:  # root finding on the closed form, not its table
            p = law.fast_damping(target, xi, restitution, exact=True)
        else:
            p = law.damping_for(target, xi, restitution).damping
        if np.any(np.isnan(p)):
            raise RuntimeError(
                f"the damping solve of law {law.name!r} failed at {int(np.isnan(p).sum())} point(s)"
            )
        return p

    fn.__doc__ = (
        f"Exact damping of law {law_name!r} for a target {restitution} restitution at load factor xi."
    )
    return fn


def _exact_model(law_name, label, impedance=None):
    law = get_law(law_name)
    return Model(
        f"{law_name}_exact",
        f"exact, {label}",
        "this package: contactalpha.laws",
        f"root of e({law.damping}, ξ) = e",
        True,
        _exact(law_name, "energetic", impedance),
        law=law_name,
        restitutions=BOTH,
        kinematic_fn=_exact(law_name, "kinematic", impedance),
        solver=not law.piecewise_linear,
        impedance=impedance,
    )


ENGINE_MAPPINGS = [
    Model(
        "classic_zeta",
        "classic ζ(e), no floor",
        "linear oscillator without the force floor",
        "ζ = −ln e / √(π² + ln² e)",
        False,
        classic_zeta,
        law="kelvin_voigt",
        restitutions=KINEMATIC,
    ),
    Model(
        "mujoco_dampratio",
        "MuJoCo dampratio = classic ζ(e)",
        "MuJoCo solref (timeconst, dampratio): dampratio = ζ for any impedance",
        "dampratio = −ln e / √(π² + ln² e)",
        False,
        classic_zeta,
        law="mujoco_soft",
        restitutions=KINEMATIC,
    ),
    Model(
        "mujoco_default",
        "MuJoCo default dampratio 1",
        "MuJoCo solref default (0.02, 1)",
        "dampratio = 1",
        False,
        mujoco_default,
        law="mujoco_soft",
        restitutions=KINEMATIC,
    ),
    Model(
        "tsuji_beta",
        "DEM β(e) (Tsuji damping)",
        "LIGGGHTS / LAMMPS granular / Chrono SMC Hertz damping",
        "β = √5 (−ln e) / √(π² + ln² e)",
        False,
        tsuji_beta,
        law="hertz_tsuji",
        restitutions=KINEMATIC,
    ),
    Model(
        "drake_bound",
        "Drake: bounce ≤ 1/d",
        "Drake contact_model_doxygen.h, Modeling Dissipation",
        "α = d v⁻ = 1/e",
        False,
        drake_bound,
        law="hunt_crossley_linear",
        restitutions=KINEMATIC,
    ),
    _exact_model("hunt_crossley_linear", "Hunt–Crossley n = 1"),
    _exact_model("kelvin_voigt", "spring–dashpot"),
    _exact_model("mujoco_soft", "MuJoCo soft", MUJOCO_DEFAULT_IMPEDANCE),
    _exact_model("hertz_tsuji", "Tsuji"),
    Model(
        "lammps_coeff_restitution",
        "LAMMPS coeff_restitution (no floor)",
        "LAMMPS pair granular damping coeff_restitution, no limit_damping",
        "β = √5 (−ln e) / √(π² + ln² e)",
        False,
        tsuji_beta,
        law="hertz_tsuji_unfloored",
        restitutions=KINEMATIC,
    ),
    _exact_model("hertz_tsuji_unfloored", "Tsuji, no floor"),
    _exact_model("hertz_viscoelastic", "Hertz, √δ damping"),
    _exact_model("hertz_viscoelastic_unfloored", "Hertz, √δ damping, no floor"),
]
