"""The contact-law family as values: ``ContactLaw`` carries a law's capabilities, ``LAWS`` lists them.

Every law moves, in its own scaling, as ``x'' = A - max(0, f(x, x'))`` from ``x = 0``,
``x' = 1`` (docs/laws.md).  Length is scaled by ``delta_s = ((n + 1) m v^2 / (2 k))^(1/(n+1))``
(the undamped, unloaded maximum compression), time by ``delta_s / v`` and the load by
``A = a delta_s / v^2``; for ``n = 1`` that is ``x = delta omega / v``, ``t omega`` and
``A = a / (omega v)`` with ``omega = sqrt(k/m)``.  The load factor ``xi`` is the share of the
load's work in the undamped loaded maximum stored energy, ``xi = A x_m / (1/2 + A x_m)``
(the paper's influence factor for ``n = 3/2``): every law's restitution is a function of its
damping ``p`` and ``xi`` only.
"""

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from contactalpha.engine.codes import END_STATES, STATUS
from contactalpha.validation import check_positive, check_range

from . import forces
from .backends import ENGINE, FAMILY
from .domain import RESTITUTIONS, check_restitution
from .fast import CLOSED_FORM, ENGINE_TABLE
from .table import LawTable, LawTableSettings

# Scaled load past which xi is 1.0 in double precision for every law (n = 1: 1 - xi ~ 1 / (4 A^2)).
A_ROUNDS_TO_ONE = 1e30
# The load factors every law covers: the paper's 0 <= xi <= 0.99.
XI_MAX = 0.99
# The restitution targets every law covers.
RESTITUTION_MIN = 0.01
# MuJoCo's default constant impedance d (solimp = (d, d, ...)); its table is built at it.
MUJOCO_IMPEDANCE = 0.9
# End states of the family (engine/codes.py names them).
ALL_END_STATES = ("separation", "nonseparation", "creep", "no_restitution")


@dataclass(frozen=True)
class ContactLaw:
    """One normal contact law of the family and what it can do.

    Attributes
    ----------
    name : registry key.
    label : name for legends.
    formula : the physical law, F(delta, delta_dot) >= 0.
    scaled_formula : its dimensionless form ``x'' = A - max(0, f)``.
    engines : engines whose normal contact is this law.
    exponent : n of the elastic term k delta^n.
    damping : name of the dimensionless damping parameter ``p``.
    damping_physical : the law's physical damping coefficient in terms of ``p`` (physical mass
        and stiffness: N/m for n = 1, N/m^1.5 for n = 3/2).
    physical_unit : the unit of that coefficient (``physical_damping``'s value).
    damping_unit : (factor, mass power, stiffness power, speed power): the engine's damping
        is ``p * factor * m^a * k^b * v^c`` (``physical_damping``).
    piecewise_linear : True when the motion in contact is linear (closed-form phases).
    floor_reached : True when the force floor ``max(0, .)`` acts before ``x = 0`` (the
        damping force pulls): the impact then ends in a free flight under the load.  False
        too for a law without the floor (``floored``), whose force pulls until ``x = 0``.
    end_states : the end states the law can reach.
    restitutions : the restitutions it inverts ("energetic" Stronge, "kinematic" Newton).
    load_domain, restitution_domain : the (xi, target) ranges its inverse and tables cover.
    impedance : MuJoCo's constant impedance d (0 for the other laws).
    impedance_range : valid (lo, hi) of ``impedance``, hi excluded; None if the law has none.
    force : jitted scaled force argument ``f(x, v, p, A, d)`` (``forces.py``).
    code : its position in the kernels' force table (``forces.scaled_force``).
    backend : where its reference numbers come from (``backends.py``).
    fast : its fast evaluator: the closed form or the engine's table (``fast.py``), the law's
        shipped table (``table.py``), or None.
    """

    name: str
    label: str
    formula: str
    scaled_formula: str
    engines: tuple
    exponent: float
    damping: str
    damping_physical: str
    physical_unit: str
    damping_unit: tuple
    piecewise_linear: bool
    floor_reached: bool
    end_states: tuple
    force: Callable
    fast: Any  # ClosedForm, EngineTable, LawTable or None: duck-typed evaluators
    code: int
    backend: object = FAMILY
    restitutions: tuple = RESTITUTIONS
    load_domain: tuple = (0.0, XI_MAX)
    restitution_domain: tuple = (RESTITUTION_MIN, 1.0)
    impedance: float = 0.0
    impedance_range: tuple | None = None

    # --- shape -------------------------------------------------------------------------
    def with_impedance(self, d):
        """Return this law with MuJoCo's impedance ``d`` (solimp = (d, d, ...)), for laws that have one."""
        if self.impedance_range is None:
            raise ValueError(f"law {self.name!r} has no impedance; laws with one: {_with_impedance()}")
        lo, hi = self.impedance_range
        d = float(check_range("impedance", d, lo, hi, hi_open=True))
        return replace(self, impedance=d)

    @property
    def floored(self):
        """False for a law whose force is not floored at 0: it pulls as the bodies part (``FLOORLESS``)."""
        return self.code not in forces.FLOORLESS

    @property
    def stiffness_unit(self):
        """Unit of the law's physical stiffness k in ``k delta^n``: "N/m" (n = 1) or "N/m^1.5" (n = 3/2)."""
        return "N/m" if self.exponent == 1.0 else f"N/m^{self.exponent:g}"

    # --- load ---------------------------------------------------------------------------
    @property
    def _stiffness_coefficient(self):
        """Coefficient c = (n + 1) / 2 of the scaled elastic force c x^n: x_m = 1 undamped, unloaded."""
        return 0.5 * (self.exponent + 1.0)

    def scaled_load(self, xi):
        """Scaled load ``A`` of load factor ``xi`` in [0, 1).

        ``W = A x_m = xi / (2 (1 - xi))`` and ``x_m^(n+1) = 1 + 2 (1 - d) W`` (the undamped
        loaded maximum), so ``A = W / x_m``.
        """
        return self.scaled_load_unchecked(check_range("xi", xi, 0.0, 1.0, hi_open=True))

    def scaled_load_unchecked(self, xi):
        """``scaled_load`` of a load factor already checked: for the inner layers."""
        x = np.asarray(xi, dtype=float)
        w = 0.5 * x / (1.0 - x)
        x_m = (1.0 + 2.0 * (1.0 - self.impedance) * w) ** (1.0 / (self.exponent + 1.0))
        return _plain(w / x_m)

    def load_factor(self, A):
        """Load factor ``xi = A x_m / (1/2 + A x_m)`` of scaled load ``A >= 0`` (``scaled_load`` inverted).

        Past ``A_ROUNDS_TO_ONE`` xi is 1.0 in double precision for every law: ``A`` is capped there.
        """
        return self.load_factor_unchecked(check_range("A", A, 0.0, np.inf, hi_open=True))

    def load_factor_unchecked(self, A):
        """``load_factor`` of a scaled load already checked (``A >= 0``, not NaN): for the inner layers."""
        a = np.minimum(np.asarray(A, dtype=float), A_ROUNDS_TO_ONE)
        n1 = self.exponent + 1.0
        b = (1.0 - self.impedance) * a
        if self.exponent == 1.0:  # x^2 = 1 + 2 b x: the quadratic's positive root
            w = a * (b + np.sqrt(b * b + 1.0))
            return _plain(w / (0.5 + w))
        # x_m solves x^(n+1) = 1 + 2 b x: Newton from above (the function is convex there).
        x = 1.0 + 2.0 * b + 1.0
        for _ in range(100):
            step = (x**n1 - 1.0 - 2.0 * b * x) / (n1 * x ** (n1 - 1.0) - 2.0 * b)
            x = x - step
            if np.all(np.abs(step) <= 1e-16 * x):
                break
        w = a * x
        return _plain(w / (0.5 + w))

    def equilibrium(self, A):
        """Scaled static compression under load ``A``: ``f(x_eq, 0) = A``."""
        return ((1.0 - self.impedance) * np.asarray(A, dtype=float) / self._stiffness_coefficient) ** (
            1.0 / self.exponent
        )

    def length_scale(self, mass, stiffness, approach_speed):
        """``delta_s = ((n + 1) m v^2 / (2 k))^(1/(n+1))``, m (``mass`` 1 for per-unit-mass laws).

        From logarithms where the direct power under- or overflows; a ``ValueError`` names the
        inputs where the scale itself is beyond the doubles.
        """
        return self.length_scale_unchecked(*_checked_scene(mass, stiffness, approach_speed))

    def length_scale_unchecked(self, mass, stiffness, approach_speed):
        """``length_scale`` of inputs already checked (positive, finite): for the inner layers."""
        m, k, v = (np.asarray(x, dtype=float) for x in (mass, stiffness, approach_speed))
        n1 = self.exponent + 1.0
        with np.errstate(all="ignore"):
            direct = (self._stiffness_coefficient * m * v * v / k) ** (1.0 / n1)
            log_d = (np.log(self._stiffness_coefficient) + np.log(m) + 2.0 * np.log(v) - np.log(k)) / n1
        d = _direct_or_log(direct, log_d)
        bad = ~((d > 0.0) & (d < np.inf))
        if np.any(bad):
            m1, k1, v1 = (float(np.broadcast_to(x, d.shape)[bad][0]) for x in (m, k, v))
            raise ValueError(
                f"mass = {m1!r}, stiffness = {k1!r}, approach_speed = {v1!r} give law {self.name!r} a length "
                "scale beyond double precision; valid: a scene whose scale lies between 1e-308 and 1e308 m"
            )
        return _plain(d)

    def load(self, mass, stiffness, approach_speed, accel):
        """Scaled load ``A = a delta_s / v^2`` of a scene.

        From logarithms where the product would under- or overflow; capped at ``A_ROUNDS_TO_ONE``,
        where xi is 1.0 for every law.
        """
        return self.load_unchecked(*_checked_load(mass, stiffness, approach_speed, accel))

    def load_unchecked(self, mass, stiffness, approach_speed, accel):
        """``load`` of inputs already checked: for the inner layers."""
        a, v = np.asarray(accel, dtype=float), np.asarray(approach_speed, dtype=float)
        d = self.length_scale_unchecked(mass, stiffness, v)
        with np.errstate(all="ignore"):
            direct = a * d / (v * v)
            log_A = np.log(a) + np.log(d) - 2.0 * np.log(v)
        A = np.where(a == 0.0, 0.0, _direct_or_log(direct, np.minimum(log_A, np.log(A_ROUNDS_TO_ONE))))
        return _plain(np.minimum(A, A_ROUNDS_TO_ONE))

    def scene_load_factor(self, mass, stiffness, approach_speed, accel):
        """Load factor ``xi`` of a scene; a ``ValueError`` naming the scene where it rounds to 1.0."""
        A = self.load_unchecked(*_checked_load(mass, stiffness, approach_speed, accel))
        return self._xi_below_one(self.load_factor_unchecked(A), (mass, stiffness, approach_speed, accel))

    def scene_load_factor_unchecked(self, mass, stiffness, approach_speed, accel):
        """``scene_load_factor`` of inputs already checked: for the inner layers."""
        xi = self.load_factor_unchecked(self.load_unchecked(mass, stiffness, approach_speed, accel))
        return self._xi_below_one(xi, (mass, stiffness, approach_speed, accel))

    def _xi_below_one(self, xi, scene):
        mass, stiffness, approach_speed, accel = scene
        if np.any(np.asarray(xi) >= 1.0):
            raise ValueError(
                f"accel = {accel!r} m/s^2 at approach_speed = {approach_speed!r} m/s (mass = {mass!r}, "
                f"stiffness = {stiffness!r}) gives law {self.name!r} a load factor that rounds to 1.0, "
                "outside [0, 1): the load is too large for the approach speed"
            )
        return xi

    def physical_damping(self, p, mass, stiffness, approach_speed):
        """The engine's damping coefficient for dimensionless damping ``p`` (see ``damping_physical``)."""
        m, k, v = _checked_scene(mass, stiffness, approach_speed)
        p = check_range(self.damping, p, 0.0, np.inf, hi_open=True)
        return self.physical_damping_unchecked(p, m, k, v)

    def physical_damping_unchecked(self, p, mass, stiffness, approach_speed):
        """``physical_damping`` of inputs already checked: for the inner layers."""
        factor, pm, pk, pv = self.damping_unit
        p, m, k, v = (np.asarray(x, dtype=float) for x in (p, mass, stiffness, approach_speed))
        return _plain(p * factor * m**pm * k**pk * v**pv)

    def damping_from_physical(self, c, mass, stiffness, approach_speed):
        """Dimensionless damping ``p`` of the engine's damping coefficient ``c`` (its inverse)."""
        c = check_range("damping", c, 0.0, np.inf, hi_open=True)
        unit = self.physical_damping_unchecked(1.0, *_checked_scene(mass, stiffness, approach_speed))
        return _plain(c / unit)

    # --- maps ---------------------------------------------------------------------------
    def impact(self, p, xi, **settings):
        """Both restitutions and the end state of one impact at damping ``p``, load factor ``xi``."""
        from .maps import impact

        return impact(self, p, xi, **settings)

    def restitution(self, p, xi, restitution="energetic", **settings):
        """Forward map: the restitution (``"energetic"`` eps or ``"kinematic"`` e_N) at ``(p, xi)``."""
        res = self.impact(p, xi, **settings)
        return res.eps if check_restitution(restitution) == "energetic" else res.e_n

    def damping_for(self, target, xi, restitution="energetic", **settings):
        """Exact inverse: the damping ``p`` that gives ``target`` at load factor ``xi``."""
        from .maps import damping_for

        return damping_for(self, target, xi, restitution, **settings)

    def fast_damping(self, target, xi, restitution="energetic", exact=False):
        """Fast evaluator of the inverse (``fast``; None: not yet, a ValueError says so).

        ``exact``: root finding on the closed form instead of a table (piecewise-linear laws).
        """
        from .fast import fast_damping

        return fast_damping(self, target, xi, restitution, exact)

    def fast_restitution(self, p, xi, restitution="energetic"):
        """Fast evaluator of the forward map (``fast``; None: not yet, a ValueError says so)."""
        from .fast import fast_restitution

        return fast_restitution(self, p, xi, restitution)


def _checked_scene(mass, stiffness, approach_speed):
    """``(mass, stiffness, approach_speed)`` checked positive and finite, as float arrays."""
    return (
        check_positive("mass", mass),
        check_positive("stiffness", stiffness),
        check_positive("approach_speed", approach_speed),
    )


def _checked_load(mass, stiffness, approach_speed, accel):
    """``(mass, stiffness, approach_speed, accel)`` checked, in ``ContactLaw.load``'s order of checks."""
    a = check_range("accel", accel, 0.0, np.inf, hi_open=True)
    v = check_positive("approach_speed", approach_speed)
    return check_positive("mass", mass), check_positive("stiffness", stiffness), v, a


def _direct_or_log(direct, log_value):
    """``direct`` where it agrees with its logarithm (nothing under- or overflowed), else its exp."""
    direct, log_value = np.broadcast_arrays(
        np.asarray(direct, dtype=float), np.asarray(log_value, dtype=float)
    )
    with np.errstate(all="ignore"):
        agree = (direct > 0.0) & (direct < np.inf)
        agree &= np.abs(np.log(direct) - log_value) <= 1e-9 * np.maximum(1.0, np.abs(log_value))
        return np.where(agree, direct, np.exp(log_value))


def _plain(arr):
    arr = np.asarray(arr, dtype=float)
    return float(arr) if arr.ndim == 0 else arr


_LINEAR_UNIT = (2.0, 0.5, 0.5, 0.0)  # c = 2 zeta sqrt(k m)
_TSUJI_UNIT = (1.0, 0.5, 0.5, 0.0)  # eta = beta sqrt(m k)
_VISCOELASTIC_UNIT = (1.0, 0.4, 0.6, -0.2)  # eta = kappa m^{2/5} k^{3/5} / v^{1/5}

LAWS = [
    ContactLaw(
        name="hunt_crossley",
        label="Hunt–Crossley, n = 3/2",
        formula="F = k δ^{3/2} (1 + α δ̇/δ̇⁻)",
        scaled_formula="x'' = A − (5/4) x^{3/2} (1 + α x')",
        engines=("OpenSim", "Exudyn", "Simbody"),
        exponent=1.5,
        damping="alpha",
        damping_physical="μ/k = α / δ̇⁻ (s/m)",
        physical_unit="s/m",
        damping_unit=(1.0, 0.0, 0.0, -1.0),
        piecewise_linear=False,
        floor_reached=False,
        end_states=ALL_END_STATES,
        force=forces.hunt_crossley_force,
        code=forces.HUNT_CROSSLEY,
        fast=ENGINE_TABLE,
        backend=ENGINE,
        restitution_domain=(0.01, 1.0),
    ),
    ContactLaw(
        name="hunt_crossley_linear",
        label="Hunt–Crossley, n = 1 (Drake)",
        formula="F = k δ (1 + d δ̇)₊",
        scaled_formula="x'' = A − x (1 + α x'),  α = d δ̇⁻",
        engines=("Drake (point contact)",),
        exponent=1.0,
        damping="alpha",
        damping_physical="d = α / δ̇⁻ (s/m)",
        physical_unit="s/m",
        damping_unit=(1.0, 0.0, 0.0, -1.0),
        piecewise_linear=False,
        floor_reached=False,
        end_states=ALL_END_STATES,
        force=forces.hunt_crossley_linear_force,
        code=forces.HUNT_CROSSLEY_LINEAR,
        fast=LawTable("law_table_hunt_crossley_linear.npz", cuts=("separation", "creep_onset")),
    ),
    ContactLaw(
        name="kelvin_voigt",
        label="spring–dashpot with floor",
        formula="F = max(0, k δ + c δ̇)",
        scaled_formula="x'' = A − max(0, x + 2ζ x'),  ζ = c / (2√(k m))",
        engines=("PhysX compliant contact", "Bullet", "ODE", "Gazebo", "Simscape", "Newton"),
        exponent=1.0,
        damping="zeta",
        damping_physical="c = 2 ζ √(k m) (N s/m)",
        physical_unit="N s/m",
        damping_unit=_LINEAR_UNIT,
        piecewise_linear=True,
        floor_reached=True,
        end_states=ALL_END_STATES,
        force=forces.kelvin_voigt_force,
        code=forces.KELVIN_VOIGT,
        fast=LawTable(
            "law_table_kelvin_voigt.npz",
            cuts=("separation", "first_of_floor_creep", "both_floor_creep"),
            forward=CLOSED_FORM,
        ),
    ),
    ContactLaw(
        name="mujoco_soft",
        label="MuJoCo soft contact",
        formula="δ̈ = a − max(0, d a + b δ̇ + s δ)  (per unit mass; solref = (−s, −b), solimp = (d, d, …))",
        scaled_formula="x'' = A − max(0, d A + x + 2ζ x'),  ζ = b / (2√s)",
        engines=("MuJoCo", "MJX", "MuJoCo Warp", "Genesis", "Newton (MuJoCo solver)"),
        exponent=1.0,
        damping="zeta",
        damping_physical="c = 2 ζ √(k m) (N s/m); MuJoCo's solref takes s = k/m and b = c/m",
        physical_unit="N s/m",
        damping_unit=_LINEAR_UNIT,
        piecewise_linear=True,
        floor_reached=True,
        end_states=ALL_END_STATES,
        force=forces.mujoco_soft_force,
        code=forces.MUJOCO_SOFT,
        fast=LawTable(
            "law_table_mujoco_soft.npz",
            # Below the first of floor and creep eps(zeta) need not fall monotonically at small loads
            # (the creep cut lies above the floor's there): no cut below it.
            cuts=("separation", "first_of_floor_creep"),
            impedance=MUJOCO_IMPEDANCE,
            forward=CLOSED_FORM,
        ),
        impedance=MUJOCO_IMPEDANCE,
        impedance_range=(0.0, 1.0),
    ),
    ContactLaw(
        name="hertz_tsuji",
        label="Hertz with Tsuji damping",
        formula="F = max(0, k δ^{3/2} + η δ^{1/4} δ̇),  η = β √(m k)",
        scaled_formula="x'' = A − max(0, (5/4) x^{3/2} + (√5/2) β x^{1/4} x')",
        engines=("Chrono SMC", "LIGGGHTS", "LAMMPS", "MercuryDPM", "Yade"),
        exponent=1.5,
        damping="beta",
        damping_physical="η = β √(m k) (N s/m^{5/4})",
        physical_unit="N s/m^1.25",
        damping_unit=_TSUJI_UNIT,
        piecewise_linear=False,
        floor_reached=True,
        end_states=ALL_END_STATES,
        force=forces.hertz_tsuji_force,
        code=forces.HERTZ_TSUJI,
        fast=LawTable(
            "law_table_hertz_tsuji.npz",
            cuts=("separation", "first_of_floor_creep", "both_floor_creep"),
            # 199 rows gave 3.2e-7 below the creep cut near xi = 0.8 (139: 6.9e-8); see docs/laws.md.
            settings=LawTableSettings(n_eta=139),
        ),
    ),
    ContactLaw(
        name="hertz_tsuji_unfloored",
        label="Hertz with Tsuji damping, no floor",
        formula="F = k δ^{3/2} + η δ^{1/4} δ̇ while δ > 0 (pulls where negative),  η = β √(m k)",
        scaled_formula="x'' = A − (5/4) x^{3/2} − (√5/2) β x^{1/4} x'  while x > 0",
        engines=("LAMMPS (tsuji, coeff_restitution; no limit_damping)",),
        exponent=1.5,
        damping="beta",
        damping_physical="η = β √(m k) (N s/m^{5/4})",
        physical_unit="N s/m^1.25",
        damping_unit=_TSUJI_UNIT,
        piecewise_linear=False,
        floor_reached=False,
        end_states=ALL_END_STATES,
        force=forces.hertz_tsuji_force,
        code=forces.HERTZ_TSUJI_UNFLOORED,
        # No floor: eps(beta) kinks only where the separation ends and where the creep begins.  On 199
        # rows its eps table missed by 2.7e-7 below the creep cut near xi = 0.82 (139: 5.8e-8).
        fast=LawTable(
            "law_table_hertz_tsuji_unfloored.npz",
            cuts=("separation", "creep_onset"),
            settings=LawTableSettings(n_eta=139),
        ),
    ),
    ContactLaw(
        name="hertz_viscoelastic",
        label="Hertz with √δ damping",
        formula="F = max(0, k δ^{3/2} + η δ^{1/2} δ̇),  η = κ m^{2/5} k^{3/5} / (δ̇⁻)^{1/5}",
        scaled_formula="x'' = A − max(0, (5/4) x^{3/2} + (5/4)^{3/5} κ x^{1/2} x')",
        engines=("LAMMPS (viscoelastic, limit_damping)", "jaxsim (soft contact)"),
        exponent=1.5,
        damping="kappa",
        damping_physical="η = κ m^{2/5} k^{3/5} / (δ̇⁻)^{1/5} (N s/m^{3/2})",
        physical_unit="N s/m^1.5",
        damping_unit=_VISCOELASTIC_UNIT,
        piecewise_linear=False,
        floor_reached=True,
        end_states=ALL_END_STATES,
        force=forces.hertz_viscoelastic_force,
        code=forces.HERTZ_VISCOELASTIC,
        # Its floor's last reach and the onset of creep cross near xi = 0.02, as Tsuji's do.
        # Its floor enters e(kappa) at kappa^{5/2}: square-root columns at e = 1 (``table.py``).
        fast=LawTable(
            "law_table_hertz_viscoelastic.npz",
            cuts=("separation", "first_of_floor_creep", "both_floor_creep"),
            root_near_one=True,
            # 259 rows: at 199 one point of 20000 next to the cuts' crossing missed eps by 3.7e-7.
            settings=LawTableSettings(n_eta=259),
        ),
    ),
    ContactLaw(
        name="hertz_viscoelastic_unfloored",
        label="Hertz with √δ damping, no floor",
        formula=(
            "F = k δ^{3/2} + η δ^{1/2} δ̇ while δ > 0 (pulls where negative),  "
            "η = κ m^{2/5} k^{3/5} / (δ̇⁻)^{1/5}"
        ),
        scaled_formula="x'' = A − (5/4) x^{3/2} − (5/4)^{3/5} κ x^{1/2} x'  while x > 0",
        engines=("LAMMPS (viscoelastic; no limit_damping)",),
        exponent=1.5,
        damping="kappa",
        damping_physical="η = κ m^{2/5} k^{3/5} / (δ̇⁻)^{1/5} (N s/m^{3/2})",
        physical_unit="N s/m^1.5",
        damping_unit=_VISCOELASTIC_UNIT,
        piecewise_linear=False,
        floor_reached=False,
        end_states=ALL_END_STATES,
        force=forces.hertz_viscoelastic_force,
        code=forces.HERTZ_VISCOELASTIC_UNFLOORED,
        fast=LawTable(
            "law_table_hertz_viscoelastic_unfloored.npz",
            cuts=("separation", "creep_onset"),
            root_near_one=True,
        ),
    ),
]

_BY_NAME = {law.name: law for law in LAWS}
DEFAULT_LAW = "hunt_crossley"


def _with_impedance():
    return ", ".join(law.name for law in LAWS if law.impedance_range is not None)


def get_law(law: "str | ContactLaw" = DEFAULT_LAW, **shape: float) -> ContactLaw:
    """The registered law named ``law`` (a ``ContactLaw`` passes through), with ``impedance=`` if given.

    Raises
    ------
    ValueError
        For an unknown name, naming the valid choices.
    """
    if isinstance(law, ContactLaw):
        found = law
    elif isinstance(law, str) and law in _BY_NAME:
        found = _BY_NAME[law]
    else:
        raise ValueError(f"unknown contact law {law!r}; valid: {', '.join(_BY_NAME)}")
    if "impedance" in shape:
        found = found.with_impedance(shape.pop("impedance"))
    if shape:
        raise ValueError(f"unknown law settings {sorted(shape)}; valid: impedance (laws {_with_impedance()})")
    return found


__all__ = ["END_STATES", "STATUS"]
