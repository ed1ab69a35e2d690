"""Reports of the adequacy study: the paper's "small xi" claim judged, xi_ignore, shares, thresholds.

``maps`` computes where each model is adequate; this module turns that dataset into the
generated statements (``paper.statements`` types), the xi_ignore(eps; tol) and area-share
tables, and the physical bounce threshold of typical scenes next to PhysX's default.
"""

import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from contactalpha.engine.scaling import influence_factor
from contactalpha.paper.statements import Statement, not_checked, verdict
from contactalpha.scene.advisor import XI_LEVELS, xi_level
from contactalpha.scene.hertz import hertz_stiffness
from contactalpha.scene.threshold import boundary_load, boundary_load_fit, speed_for_load
from contactalpha.studies.adequacy.maps import NONE_ADEQUATE, StrideSettings
from contactalpha.validation import check_positive, check_range

# Upper end of the paper's "small" level of xi (Sect. 3), from the advisor's one table of levels.
SMALL_XI = next(hi for name, _, hi in XI_LEVELS if name == "small")
# Upper end of the paper's "moderate" level.
MODERATE_XI = next(hi for name, _, hi in XI_LEVELS if name == "moderate")
# PhysX's default bounce threshold (PxSceneDesc::bounceThresholdVelocity, 2 m/s in the PhysX 4/5
# SDK documentation): relative normal speeds below it get no restitution.
PHYSX_BOUNCE_THRESHOLD = 2.0

CLAIM_SMALL = (
    "ξ has three levels, small (0–0.1), moderate (0.1–0.5) and large (0.5–1); "
    '"except the small value of ξ, the constant external forces should be considered carefully" (Sect. 3)'
)


def small_claim_statements(ds):
    """The paper's "xi < 0.1 is small" claim judged at each tolerance of the maps.

    Criterion: the load is negligible where the exact alpha at xi = 0 is adequate (delivered eps
    within ``tol`` of the requested eps, the same end state).  The claim holds at a restitution
    when ignoring the load is adequate at every grid xi below 0.1 (``xi_ignore`` reaches the last
    grid column below 0.1); it is judged over every eps row of the maps.  Its converse, that
    beyond the small level the load must be considered, is judged by whether ignoring the load
    fails somewhere in the moderate level 0.1 <= xi < 0.5 at each eps.
    """
    xi = ds["xi"].values
    eps = ds["epsilon"].values
    small = xi[xi < SMALL_XI]
    moderate = (xi >= SMALL_XI) & (xi < MODERATE_XI)
    out = []
    for tol in ds["tol"].values:
        criterion = (
            f"α at ξ = 0 delivers ε within {tol:g} of the target, with the exact end state, "
            f"at every grid ξ < {SMALL_XI:g}, for each of the {eps.size} grid ε"
        )
        if small.size == 0:
            out.append(not_checked(CLAIM_SMALL, criterion, "no grid ξ below 0.1"))
        else:
            reach = ds["xi_ignore"].sel(tol=tol).values
            flags = np.nan_to_num(reach, nan=-1.0) >= small[-1]
            low = eps[~flags]
            evidence = (
                f"holds at {flags.sum()} of {eps.size} ε; "
                + (
                    f"fails for {low.min():g} ≤ ε ≤ {low.max():g} ({low.size} rows), "
                    f"where ξ_ignore is as small as {np.nanmin(reach):.3g}"
                    if low.size
                    else f"smallest ξ_ignore {np.nanmin(reach):.3g}"
                )
                + f"; ignoring the load is adequate on {_share_below(ds, tol, SMALL_XI):.1%} "
                "of the ξ < 0.1 points"
            )
            out.append(Statement(CLAIM_SMALL, criterion, evidence, verdict(flags)))
        criterion = (
            f"at each grid ε, α at ξ = 0 is not adequate (tol {tol:g}) somewhere in the moderate "
            f"level {SMALL_XI:g} ≤ ξ < {MODERATE_XI:g}"
        )
        claim = "beyond the small level the constant force must be considered (Sect. 3)"
        if not moderate.any():
            out.append(not_checked(claim, criterion, "no grid ξ in the moderate level"))
        else:
            fails = ~ds["ignore_adequate"].sel(tol=tol).values[:, moderate].astype(bool).all(axis=1)
            evidence = f"ignoring the load fails in the moderate level at {fails.sum()} of {eps.size} ε"
            out.append(Statement(claim, criterion, evidence, verdict(fails)))
    return out


def _share_below(ds, tol, xi_max):
    cols = ds["xi"].values < xi_max
    return float(ds["ignore_adequate"].sel(tol=tol).values[:, cols].mean())


def xi_ignore_table(ds, eps_values):
    """Markdown table of xi_ignore(eps; tol) at the grid rows nearest ``eps_values``."""
    tols = ds["tol"].values
    rows = ds["xi_ignore"].sel(epsilon=list(eps_values), method="nearest")
    lines = ["| ε | " + " | ".join(f"ξ_ignore (tol {t:g})" for t in tols) + " |"]
    lines.append("|---|" + "---|" * len(tols))
    for i, e in enumerate(rows["epsilon"].values):
        cells = [_fmt(rows.sel(tol=t).values[i]) for t in tols]
        lines.append(f"| {e:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _fmt(x):
    return "none (not even the first column)" if np.isnan(x) else f"{x:.3g}"


def share_table(ds):
    """Markdown table of each model's share of the (eps, xi) area where it is adequate, per tol."""
    tols = ds["tol"].values
    lines = ["| model | " + " | ".join(f"adequate share, tol {t:g}" for t in tols) + " | ops/eval |"]
    lines.append("|---|" + "---|" * (len(tols) + 1))
    for m in ds["model"].values:
        cells = [f"{float(ds['area_share'].sel(tol=t, model=m)):.1%}" for t in tols]
        cost = float(ds["cost"].sel(model=m))
        lines.append(f"| `{m}` | " + " | ".join(cells) + f" | {cost:.0f} |")
    return "\n".join(lines) + "\n"


def cheapest_shares(ds):
    """Per tol, the share of grid points where each model is the recommended one (and 'none')."""
    names = [*ds["model"].values, "none"]
    out = {}
    for t in ds["tol"].values:
        best = ds["cheapest"].sel(tol=t).values.ravel()
        codes = np.where(best == NONE_ADEQUATE, len(names) - 1, best)
        counts = np.bincount(codes, minlength=len(names))
        out[float(t)] = {n: counts[i] / best.size for i, n in enumerate(names) if counts[i]}
    return out


# Typical scenes of the physical bounce-threshold table: a sphere of ``radius`` (m) and effective
# ``mass`` (kg) on a half space of effective modulus E* (Pa), pressed with ``accel`` (m/s^2).
TYPICAL_SCENES = (
    {
        "name": "steel ball on steel",
        "eps": 0.9,
        "mass": 0.0329,
        "radius": 0.01,
        "modulus": 1.154e11,
        "accel": 9.81,
        "source": "20 mm bearing ball, 7850 kg/m³; E = 210 GPa, ν = 0.3 on both sides, "
        "E* = E / (2 (1 − ν²)); ε = 0.9 assumed",
    },
    {
        "name": "rubber ball on concrete",
        "eps": 0.8,
        "mass": 0.1244,
        "radius": 0.03,
        "modulus": 6.67e6,
        "accel": 9.81,
        "source": "solid rubber, 60 mm, 1100 kg/m³; E = 5 MPa, ν = 0.5, rigid ground: "
        "E* = E / (1 − ν²); ε = 0.8 assumed",
    },
    {
        "name": "robot foot",
        "eps": 0.3,
        "mass": 1.0,
        "radius": 0.02,
        "modulus": 1.33e7,
        "accel": 39.8,
        "source": "1 kg effective leg mass, 20 mm rubber foot, E = 10 MPa, ν = 0.5 on rigid ground; "
        "a = g + 30 N leg force / 1 kg (about a quarter of a 12 kg quadruped's weight); ε = 0.3 assumed",
    },
)


@dataclass(frozen=True)
class AdequacySettings:
    """The adequacy stage's settings: the workflow's ``adequacy`` section.

    ``tols`` (delivered-eps tolerances of adequacy), ``stride`` (the mapped subgrid),
    ``report_eps`` (rows of the xi_ignore table), ``vcrit_eps`` (where the exact separation
    boundary is solved for the v_crit figure), ``scenes`` (``scene_thresholds``'s records).
    """

    tols: tuple = (0.01, 0.05)
    stride: StrideSettings = field(default_factory=StrideSettings)
    report_eps: tuple = (0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9)
    vcrit_eps: tuple = (0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99)
    scenes: tuple = TYPICAL_SCENES


@dataclass(frozen=True)
class SceneThreshold:
    """The physical bounce threshold of one typical scene."""

    name: str
    eps: float
    mass: float
    stiffness: float
    accel: float
    v_crit: float
    status: str
    v_crit_fit: float
    xi_at_physx: float
    source: str


def scene_thresholds(scenes):
    """``SceneThreshold`` of each scene (dicts: name, eps, mass, radius, modulus, accel, source)."""
    out = []
    for s in scenes:
        eps = float(check_range("eps", s["eps"], 0.0, 1.0, lo_open=True, hi_open=True))
        m, a = float(check_positive("mass", s["mass"])), float(check_positive("accel", s["accel"]))
        # The scene's modulus is the contact's effective E*: a rigid flat and nu = 0 give E* = E_1.
        k = hertz_stiffness(float(s["modulus"]), 0.0, float(s["radius"]), modulus_2=math.inf)
        A_b, status = boundary_load(eps)
        v = float(speed_for_load(A_b, m, k, a)) if np.isfinite(A_b) else np.nan
        fit = float(speed_for_load(boundary_load_fit(eps), m, k, a))
        xi = float(influence_factor(m, k, PHYSX_BOUNCE_THRESHOLD, a))
        out.append(SceneThreshold(s["name"], eps, m, k, a, v, status, fit, xi, s["source"]))
    return out


def thresholds_dataset(rows, eps_curve):
    """The scenes' thresholds and the dimensionless boundary A_b(eps) on ``eps_curve`` (exact and fit).

    ``v_crit = (a L1 / A_b)^(5/6)`` with ``L1`` the length scale at 1 m/s: ``A_b^(-5/6)`` is the
    critical speed in units of ``(a L1)^(5/6)``, the same curve for every scene.
    """
    eps_curve = np.asarray(eps_curve, dtype=float)
    solved = [boundary_load(e) for e in eps_curve]
    names = [r.name for r in rows]
    return xr.Dataset(
        {
            "load_boundary": ("eps_curve", np.array([A for A, _ in solved])),
            "load_boundary_status": ("eps_curve", np.array([st for _, st in solved], dtype=str)),
            "load_boundary_fit": ("eps_curve", boundary_load_fit(eps_curve)),
            "eps": ("scene", [r.eps for r in rows]),
            "mass": ("scene", [r.mass for r in rows]),
            "stiffness": ("scene", [r.stiffness for r in rows]),
            "accel": ("scene", [r.accel for r in rows]),
            "v_crit": ("scene", [r.v_crit for r in rows]),
            "v_crit_fit": ("scene", [r.v_crit_fit for r in rows]),
            "xi_at_physx": ("scene", [r.xi_at_physx for r in rows]),
            "source": ("scene", [r.source for r in rows]),
        },
        coords={"eps_curve": eps_curve, "scene": names},
    )


def thresholds_markdown(rows):
    """Markdown table of the scenes' critical speeds next to PhysX's 2 m/s default."""
    head = (
        "# Physical bounce threshold of typical scenes\n\n"
        "Below v_crit an impact with the exact α ends without separation (the ball stays on the ground); "
        f"PhysX drops restitution below {PHYSX_BOUNCE_THRESHOLD:g} m/s by default. "
        "ξ at 2 m/s is the load's influence factor (Eq. 10) of an impact at PhysX's threshold.\n\n"
        "| scene | ε | m (kg) | k (N/m^1.5) | a (m/s²) | v_crit (m/s) | v_crit, 6-constant fit | "
        f"PhysX / v_crit | ξ at {PHYSX_BOUNCE_THRESHOLD:g} m/s (level) | assumptions |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n"
    )
    lines = []
    for r in rows:
        ratio = PHYSX_BOUNCE_THRESHOLD / r.v_crit if r.v_crit > 0 else np.inf
        lines.append(
            f"| {r.name} | {r.eps:g} | {r.mass:.4g} | {r.stiffness:.3g} | {r.accel:.3g} | "
            f"{r.v_crit:.4g}{'' if r.status == 'ok' else ' (' + r.status + ')'} | {r.v_crit_fit:.4g} | "
            f"{ratio:.3g} | {r.xi_at_physx:.3g} ({xi_level(r.xi_at_physx)}) | {r.source.replace('|', '/')} |"
        )
    return head + "\n".join(lines) + "\n"


def summary_markdown(ds, report_eps):
    """The maps in words: area shares and costs, the recommended model's shares, xi_ignore."""
    lines = [
        "# Which model does a scene need? Adequacy over (ε, ξ)",
        "",
        f"{ds.sizes['epsilon']} ε × {ds.sizes['xi']} ξ points "
        f"({ds.attrs.get('grid_fraction', 1.0):.0%} of the surface's grid, "
        f"stride {ds.attrs.get('stride', '{}')}), computed in "
        f"{ds.attrs.get('compute_seconds', float('nan')):.1f} s. A model is adequate at a point when its α, "
        "integrated over one impact, delivers ε within tol of the target and the exact end state. "
        "Shares weigh each ξ column by its trapezoid width (the log-spaced small-ξ columns count for their "
        "own small width).",
        "",
        "## Share of the (ε, ξ) area where each model is adequate",
        "",
        share_table(ds),
        "## Recommended model (cheapest adequate; most accurate among costs within "
        f"{ds.attrs.get('cost_tie', float('nan')):g}x), share of grid points",
        "",
    ]
    for t, shares in cheapest_shares(ds).items():
        lines.append(f"- tol {t:g}: " + ", ".join(f"`{n}` {s:.1%}" for n, s in shares.items()))
    lines += [
        "",
        "## ξ_ignore(ε; tol): largest grid ξ up to which α at ξ = 0 stays adequate",
        "",
        xi_ignore_table(ds, report_eps),
    ]
    return "\n".join(lines)
