"""A LAMMPS species table: every pair's parameters for a target restitution matrix under its load.

For ``n`` species and any walls, ``species_table`` gives the ``pair_coeff i j`` lines of
``pair_style granular`` (n x n) and one ``fix wall/gran granular`` line per species and wall
(n x walls) that deliver the target e_N of each pair at its approach speed under its load, with
the arrays behind them.  Each pair is one sphere of the reduced mass ``m* = m_i m_j / (m_i +
m_j)`` and radius ``R* = R_i R_j / (R_i + R_j)`` (``R_i`` against a flat wall, where ``m* = m_i``)
pressed by the pair's effective modulus ``E*`` (``adapters.lammps_granular``'s pair rules); its
load is the acceleration of its gap towards contact (``accel``: a resting bead's gravity against a
wall, a preload's ``F / m*`` between two beads; gravity alone never loads two free beads).

LAMMPS runs one step for every pair: ``timestep`` defaults to the shortest pair's undamped contact
time over ``STEPS_PER_CONTACT``.  With ``refine=True`` each pair's damping is refined on LAMMPS's
own drops at that step (the discrete answer; needs LAMMPS), else it is the continuous law's.

Example::

    from contactalpha.dem.species import Species, Wall, species_table
    glass = Species("glass", radius=1e-3, density=2500, youngs_modulus=6.3e10, poisson=0.23)
    steel = Species("steel", radius=2e-3, density=7800, youngs_modulus=2e11, poisson=0.3)
    table = species_table([glass, steel], [[0.9, 0.8], [0.8, 0.7]], approach_speed=0.5,
                          accel=9.81, walls=[Wall("floor", 2e11, 0.3)], wall_restitution=[[0.85], [0.75]])
    print(table.lammps_input())
"""

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from contactalpha.adapters import lammps_granular as lg
from contactalpha.adapters.contract import DropScene
from contactalpha.validation import check_positive, check_range

# A refined pair's mean e_N is refined until it is this close to its target (the secant's own
# tolerance is tighter): one LAMMPS step serves every pair, and the table should not use up the
# user's tolerance on any of them.
REFINED_TOL = 1e-4


@dataclass(frozen=True)
class Species:
    """A DEM species: ``name``, ``radius`` (m), ``density`` (kg/m^3), ``youngs_modulus`` (Pa), ``poisson``."""

    name: str
    radius: float
    density: float
    youngs_modulus: float
    poisson: float

    def __post_init__(self):
        for name in ("radius", "density", "youngs_modulus"):
            object.__setattr__(self, name, float(check_positive(name, getattr(self, name))))
        object.__setattr__(
            self, "poisson", float(check_range("poisson", self.poisson, -1.0, 0.5, hi_open=True))
        )

    @property
    def mass(self) -> float:
        """The mass, kg."""
        return 4.0 / 3.0 * math.pi * self.radius**3 * self.density


@dataclass(frozen=True)
class Wall:
    """A flat wall: its ``name``, ``youngs_modulus`` (Pa), ``poisson`` and LAMMPS's ``plane`` words."""

    name: str
    youngs_modulus: float
    poisson: float
    plane: str = "zplane 0.0 NULL"

    def __post_init__(self):
        object.__setattr__(
            self, "youngs_modulus", float(check_positive("youngs_modulus", self.youngs_modulus))
        )
        object.__setattr__(
            self, "poisson", float(check_range("poisson", self.poisson, -1.0, 0.5, hi_open=True))
        )


@dataclass(frozen=True)
class PairTable:
    """The arrays of one block of a species table (species x species, or species x walls).

    ``e_star`` (Pa), ``r_star`` (m), ``mass`` (kg, reduced), ``stiffness`` (the law's K, N/m^1.5),
    ``accel`` (m/s^2), ``approach_speed`` (m/s), ``target``, ``xi`` (the load factor), ``damping``
    (the law's dimensionless one), ``damp`` (LAMMPS's), ``coefficient`` (the line's),
    ``modulus`` and ``poisson`` (the line's E and ν), ``ignoring_load`` (the line's coefficient of
    the law's zero-load damping: the scene's load ignored).
    """

    e_star: np.ndarray
    r_star: np.ndarray
    mass: np.ndarray
    stiffness: np.ndarray
    accel: np.ndarray
    approach_speed: np.ndarray
    target: np.ndarray
    xi: np.ndarray
    damping: np.ndarray
    damp: np.ndarray
    coefficient: np.ndarray
    modulus: np.ndarray
    poisson: np.ndarray
    ignoring_load: np.ndarray


@dataclass(frozen=True)
class SpeciesTable:
    """``species_table``'s answer: the pairs' and walls' blocks, the step, and how to write them."""

    species: tuple
    walls: tuple
    pairs: PairTable
    wall_pairs: PairTable | None
    adapter: lg.LammpsGranularAdapter
    settings: lg.LammpsSettings
    timestep: float
    refined: bool
    notes: list = field(default_factory=list)

    def pair_lines(self) -> list[str]:
        """``pair_coeff i j`` lines (i <= j; LAMMPS types 1..n in the species' order)."""
        p, n = self.pairs, len(self.species)
        return [
            lg.pair_line(
                i + 1,
                j + 1,
                p.modulus[i, j],
                p.coefficient[i, j],
                p.poisson[i, j],
                self.settings.damping,
                self.adapter.limit_damping,
            )
            for i in range(n)
            for j in range(i, n)
        ]

    def wall_lines(self) -> list[str]:
        """``group`` and ``fix wall/gran granular`` lines: one fix per species and wall."""
        if self.wall_pairs is None:
            return []
        w, out = self.wall_pairs, []
        for i, s in enumerate(self.species):
            out.append(f"group {s.name} type {i + 1}")
            for k, wall in enumerate(self.walls):
                words = (w.modulus[i, k], w.coefficient[i, k], w.poisson[i, k], self.settings.damping)
                fix = f"{wall.name}_{s.name}"
                line = lg.wall_line(*words, self.adapter.limit_damping, fix_id=fix, group=s.name)
                out.append(line.replace("zplane 0.0 NULL", wall.plane))
        return out

    def lammps_input(self) -> str:
        """The input block: ``pair_style granular``, the pair lines, the walls, the step."""
        head = [f"# contactalpha species table: law {self.adapter.law.name}, damping {self.settings.damping}"]
        head += [f"# {n}" for n in self.notes]
        return "\n".join(
            [
                *head,
                "pair_style granular",
                *self.pair_lines(),
                *self.wall_lines(),
                f"timestep {lg.lammps_number(self.timestep)}",
            ]
        )


def _matrix(name, value, shape):
    arr = np.broadcast_to(np.asarray(value, dtype=float), shape).copy()
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite numbers of shape {shape}; got {value!r}")
    return arr


def _block(adapter, settings, e_star, r_star, mass, poisson, accel, speed, target):
    law = adapter.law
    style = adapter.style(settings)
    check_range("target", target, 0.0, 1.0, lo_open=True, hi_open=True)
    check_range("accel", accel, 0.0, math.inf, hi_open=True)
    k = lg.hertz_stiffness(e_star, r_star)
    xi = np.asarray(law.scene_load_factor(mass, k, speed, accel), dtype=float) * np.ones_like(k)
    damping = np.empty_like(k)
    for idx in np.ndindex(k.shape):
        sol = law.damping_for(float(target[idx]), float(xi[idx]), "kinematic")
        damping[idx] = float(sol.damping) if sol.ok else math.nan
    eta = np.asarray(law.physical_damping_unchecked(damping, mass, k, speed))
    damp = eta / style.per_unit(mass, k, r_star)
    zero = np.array([float(law.damping_for(float(t), 0.0, "kinematic").damping) for t in target.ravel()])
    zero = zero.reshape(target.shape)
    eta_zero = np.asarray(law.physical_damping_unchecked(zero, mass, k, speed))
    ignoring = style.coefficient_of(eta_zero / style.per_unit(mass, k, r_star))
    coefficient = style.coefficient_of(damp)
    modulus = lg.line_modulus(e_star, poisson)
    return PairTable(
        e_star,
        r_star,
        mass,
        k,
        accel,
        speed,
        target,
        xi,
        damping,
        damp,
        coefficient,
        modulus,
        poisson,
        ignoring,
    )


def species_table(
    species: Sequence[Species],
    restitution,
    approach_speed,
    *,
    accel=0.0,
    walls: Sequence[Wall] = (),
    wall_restitution=None,
    wall_accel=9.81,
    wall_speed=None,
    damping: str = "coeff_restitution",
    limit_damping: bool = True,
    timestep: float | None = None,
    refine: bool = False,
) -> SpeciesTable:
    """The LAMMPS parameters of every species pair (and species-wall pair) for the target e_N matrix.

    Parameters
    ----------
    species : the species, in the order of LAMMPS's atom types 1..n.
    restitution : (n, n) symmetric target e_N, or one number for all pairs.
    approach_speed : (n, n) or one number: each pair's approach speed, m/s.
    accel : (n, n) or one number: each pair's gap acceleration towards contact, m/s^2 (0: free beads).
    walls, wall_restitution, wall_accel, wall_speed : the walls and their (n, walls) targets, loads
        (default gravity) and speeds (default ``approach_speed``'s diagonal).
    damping : LAMMPS's damping style ("coeff_restitution", "tsuji"; "viscoelastic" applies Hertz with
        √δ damping).
    limit_damping : the force floor (without it the unfloored law of the style, LAMMPS's default).
    timestep : LAMMPS's step, s; default the shortest pair's contact time over ``STEPS_PER_CONTACT``.
    refine : refine each pair's damping on LAMMPS's own drops at the step (needs LAMMPS).
    """
    species = tuple(species)
    n = len(species)
    if n == 0:
        raise ValueError("species must list at least one species")
    adapter = _adapter(damping, limit_damping)
    settings = replace(adapter.settings, damping=damping)
    target = _matrix("restitution", restitution, (n, n))
    if not np.allclose(target, target.T, rtol=0.0, atol=0.0):
        raise ValueError("restitution must be symmetric: pair (i, j) is pair (j, i)")
    speed = _matrix("approach_speed", approach_speed, (n, n))
    r = np.array([s.radius for s in species])
    m = np.array([s.mass for s in species])
    e = np.array([s.youngs_modulus for s in species])
    nu = np.array([s.poisson for s in species])
    e_star = lg.effective_modulus(e[:, None], nu[:, None], e[None, :], nu[None, :])
    # An explicit line's ν enters only its E (``line_modulus``): LAMMPS's geometric mixing where it exists.
    prod, mean = nu[:, None] * nu[None, :], 0.5 * (nu[:, None] + nu[None, :])
    nu_line = np.where((nu[:, None] >= 0.0) & (nu[None, :] >= 0.0), np.sqrt(np.abs(prod)), mean)
    pairs = _block(
        adapter,
        settings,
        e_star,
        lg.effective_radius(r[:, None], r[None, :]),
        m[:, None] * m[None, :] / (m[:, None] + m[None, :]),
        nu_line,
        _matrix("accel", accel, (n, n)),
        speed,
        target,
    )
    wall_pairs = None
    walls = tuple(walls)
    if walls:
        shape = (n, len(walls))
        ew, nw = np.array([w.youngs_modulus for w in walls]), np.array([w.poisson for w in walls])
        if wall_restitution is None:
            raise ValueError("walls need wall_restitution: the (species, walls) target e_N")
        wspeed = np.diag(speed)[:, None] if wall_speed is None else wall_speed
        r_col, m_col, nu_col = (np.broadcast_to(x[:, None], shape).copy() for x in (r, m, nu))
        wall_pairs = _block(
            adapter,
            settings,
            lg.effective_modulus(e[:, None], nu[:, None], ew[None, :], nw[None, :]),
            r_col,
            m_col,
            nu_col,
            _matrix("wall_accel", wall_accel, shape),
            _matrix("wall_speed", wspeed, shape),
            _matrix("wall_restitution", wall_restitution, shape),
        )
    blocks = [b for b in (pairs, wall_pairs) if b is not None]
    if timestep is None:
        t_c = min(float(np.min(lg.contact_time(b.mass, b.stiffness, b.approach_speed))) for b in blocks)
        timestep = t_c / settings.steps_per_contact
    timestep = float(check_positive("timestep", timestep))
    settings = replace(settings, timestep=timestep)
    notes = [f"step {timestep:.6g} s; each pair's damping at its load factor xi (the continuous law's)"]
    if refine:
        pairs = _refined(adapter, settings, pairs)
        wall_pairs = None if wall_pairs is None else _refined(adapter, settings, wall_pairs)
        notes[0] = f"step {timestep:.6g} s; each pair's damping refined on LAMMPS's drops at this step"
    return SpeciesTable(species, walls, pairs, wall_pairs, adapter, settings, timestep, refine, notes)


def _adapter(damping, limit_damping):
    for a in lg.VARIANTS:
        if damping in a.styles and a.limit_damping == bool(limit_damping):
            return a
    valid = [(s, a.limit_damping) for a in lg.VARIANTS for s in a.styles]
    raise ValueError(
        f"damping = {damping!r} with limit_damping = {limit_damping!r} is none of LAMMPS's laws here: {valid}"
    )


def wall_equivalent(block: PairTable, idx) -> DropScene:
    """The particle-wall drop equivalent to one pair: a sphere of ``m*`` and ``R*`` under the pair's load."""
    return DropScene(
        float(block.mass[idx]),
        float(block.stiffness[idx]),
        float(block.approach_speed[idx]),
        float(block.accel[idx]),
        0.0,
        float(block.r_star[idx]),
    )


def _refined(adapter, settings, block):
    settings = replace(settings, tol=REFINED_TOL)
    damping, damp, coefficient = block.damping.copy(), block.damp.copy(), block.coefficient.copy()
    for idx in np.ndindex(block.damping.shape):
        scene = wall_equivalent(block, idx)
        if not math.isfinite(damping[idx]):
            continue
        _, ref, _ = adapter.calibrate(
            scene, float(block.target[idx]), start=float(damping[idx]), settings=settings
        )
        if math.isfinite(ref.damping):
            damping[idx] = ref.damping
            p = adapter.parameters(ref.damping, scene, settings)
            damp[idx], coefficient[idx] = p["damp"], p["coefficient"]
    return replace(block, damping=damping, damp=damp, coefficient=coefficient)
