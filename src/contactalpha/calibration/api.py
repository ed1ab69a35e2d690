"""``calibrate``: a drop test in, each law's fitted parameters, the selected law and engine inputs out."""

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from contactalpha.laws import get_law
from contactalpha.scene.ball import GRAVITY
from contactalpha.validation import check_positive, check_range

from . import data as data_mod
from . import family  # noqa: F401  (registers the contact-law family's laws)
from .band import METHOD
from .engines import engine_lines, engine_parameters
from .fit import LEVEL, Setup, fit_hypothesis
from .hypotheses import HYPOTHESES, hypothesis_names

# Laws whose AIC is more than this above the best get no intervals (their Akaike weight is below
# 5e-5: intervals of a law the data reject would only cost time).
INTERVAL_AIC_GAP = 20.0
# Laws whose AIC is within this of the lowest tie with it (Burnham and Anderson's "substantial
# support", an Akaike weight ratio above exp(-1) = 0.37): the report names a tie, not a choice.
TIE_AIC_GAP = 2.0


@dataclass
class Calibration:
    """Result of ``calibrate``.

    Attributes
    ----------
    data : data.DropData fitted.
    setup : fit.Setup (mass, acceleration).
    radius : m, or None.
    fits : law name -> fit.LawFit, in the order asked.
    selected : name of the law with the lowest AIC.
    tied : the laws within ``TIE_AIC_GAP`` of the lowest AIC, lowest first (the selected one alone
        when no other is that close): two or more are a tie, which the report prints as one.
    weights : law name -> Akaike weight (relative likelihood of the laws asked).
    engines : law name -> engine parameters (``engine_parameters``).
    notes : what was done to the data before the fit (a cap on the observations).
    """

    data: data_mod.DropData
    setup: Setup
    radius: object
    fits: dict
    selected: str
    weights: dict
    engines: dict
    notes: list = field(default_factory=list)
    tied: list = field(default_factory=list)

    @property
    def best(self):
        """The selected law's ``LawFit``."""
        return self.fits[self.selected]

    def to_dict(self):
        """Everything as plain data (the JSON report)."""
        from contactalpha.version import __version__

        return {
            "contactalpha": __version__,
            "data": {"kind": self.data.kind, "source": self.data.source, "count": self.data.count},
            "notes": self.notes,
            "given": self.setup.given,
            "mass": self.setup.mass,
            "accel": self.setup.accel,
            "radius": self.radius,
            "noise_model": NOISE_MODELS[self.data.kind],
            "interval_method": "profile likelihood, F(1, n - p) threshold",
            "selected": self.selected,
            "selection": "lowest AIC = n log(RSS/n) + 2 (p + 1)",
            "tied": self.tied,
            "tie_aic_gap": TIE_AIC_GAP,
            "laws": {
                name: _fit_dict(f, self.weights[name], self.engines[name]) for name, f in self.fits.items()
            },
        }

    def to_json(self, path=None):
        """The report as JSON text; written to ``path`` too when given."""
        from contactalpha.io import json_text, write_text_atomic

        text = json_text(self.to_dict(), indent=1) + "\n"
        if path is not None:
            write_text_atomic(path, text)
        return text

    def figures(self, prefix):
        """Write ``PREFIX_restitution.png`` and ``PREFIX_residuals.png``; returns their paths."""
        from .figures import draw

        return draw(self, prefix)


NOISE_MODELS = {
    "times": "independent Gaussian error of unknown sigma (s) on every impact time",
    "heights": "independent Gaussian error of unknown sigma on the log of every height (relative)",
    "trajectory": "independent Gaussian error of unknown sigma (m) on every tracked height",
}


def _fit_dict(f, weight, engines):
    s = f.sequence
    return {
        "values": f.values,
        "intervals": {k: list(v) for k, v in f.intervals.items()},
        "interval_closed": {k: list(v) for k, v in f.bounded.items()},
        "level": f.level,
        "fixed": list(f.fixed),
        "nuisance": f.nuisance,
        "given": list(f.given),
        "e_n_at_recorded_speeds": {
            "v_in": f.sequence.v_in[: len(f.e_n_band[0])],
            "e_n": f.e_n_band[0],
            "lo": f.e_n_band[1],
            "hi": f.e_n_band[2],
            "method": METHOD,
        },
        "rss": f.rss,
        "sigma": f.sigma,
        "n": f.n,
        "p": f.p,
        "aic": f.aic,
        "bic": f.bic,
        "akaike_weight": weight,
        "status": f.status,
        "per_contact": {
            "v_in": s.v_in,
            "e_n": s.e_n,
            "duration": s.durations,
            "touchdown": s.touchdowns,
        },
        "residuals": f.residuals,
        "engines": engines,
    }


def stiffness_from_moduli(radius, moduli, poisson=(0.0, 0.0)):
    """Hertz stiffness (N/m^1.5) of a ball of ``radius`` on a flat from both moduli (Pa) and Poissons."""
    from contactalpha.scene.hertz import hertz_stiffness

    (e1, e2), (n1, n2) = moduli, poisson
    for name, nu in (("poisson[0]", n1), ("poisson[1]", n2)):
        check_range(name, nu, -1.0, 0.5, lo_open=True, hi_open=True)
    e1, e2 = float(check_positive("moduli[0]", e1)), float(check_positive("moduli[1]", e2))
    return float(hertz_stiffness(e1, float(n1), float(radius), modulus_2=e2, poisson_2=float(n2)))


def _as_data(source, kind, t, tolerance):
    if isinstance(source, data_mod.DropData):
        return source
    if isinstance(source, str | Path):
        return data_mod.read_drop(source, tolerance)
    if kind is None:
        raise ValueError("give kind ('times', 'heights' or 'trajectory') with array data")
    return data_mod.from_arrays(
        kind, t=t, values=np.asarray(source, dtype=float), interval_tolerance=tolerance
    )


def calibrate(
    data: "str | Path | data_mod.DropData | np.ndarray",
    *,
    mass: float,
    radius: float | None = None,
    kind: str | None = None,
    t: "np.ndarray | None" = None,
    hypotheses: "str | list[str] | None" = None,
    gravity: float = GRAVITY,
    force: float = 0.0,
    stiffness: float | None = None,
    moduli: "tuple[float, float] | None" = None,
    poisson: tuple[float, float] = (0.3, 0.3),
    level: float = LEVEL,
    intervals: bool = True,
    interval_tolerance: float | None = None,
    impedance: float | None = None,
    progress: "Callable[[str], None] | None" = None,
) -> "Calibration":
    """Fit restitution laws to a drop test and select one.

    Parameters
    ----------
    data : str, Path, DropData or array_like
        A CSV file (``calibration.data`` describes its columns), checked data, or an array of
        impact times, heights, or trajectory heights ``z`` (then ``kind``, and ``t`` for a
        trajectory).
    mass : float
        Ball mass, kg (> 0).
    radius : float, optional
        Ball radius, m; needed for OpenSim's per-geometry stiffness and for ``moduli``.
    kind : {"times", "heights", "trajectory"}, optional
        For array data.
    t : array_like, optional
        Sample times of a trajectory, s.
    hypotheses : sequence of str or "all", optional
        Restitution hypotheses, names in ``calibration.hypotheses.HYPOTHESES``; default
        ``hypotheses.DEFAULT_HYPOTHESES`` (the three Hunt–Crossley n = 3/2 ones); ``"all"`` adds
        one per contact law of the family (slower: seconds each).  ``laws=`` is its old name.
    gravity, force : float
        m/s^2, and a constant extra push towards the ground, N (>= 0).
    stiffness : float, optional
        A stiffness guess, N/m^1.5, to start from (else several decades are tried).
    moduli, poisson : pair of float, optional
        Young's moduli (Pa) and Poisson ratios of ball and ground: the Hertz stiffness guess.
    level : float
        Confidence level of the intervals, in (0, 1).
    intervals : bool
        False skips the profile-likelihood intervals; they are computed for every law whose AIC is
        within ``INTERVAL_AIC_GAP`` of the best.
    interval_tolerance : float, optional
        s; an impact interval longer than the one before by more than this is refused (a missed
        or spurious impact); by default derived from the recording's timing scatter, at least
        ``data.INTERVAL_TOLERANCE`` (``data.interval_tolerance_for``).
    impedance : float, optional
        MuJoCo's constant impedance d in [0, 1) of the recording, for the laws that have one
        (``mujoco_soft_damping``); default the law's (0.9).  It is given, not fitted, and reported.
    progress : callable, optional
        Called with a line of text at each stage (the command line prints them on stderr).

    Returns
    -------
    Calibration
    """
    m = float(check_positive("mass", mass))
    g = float(check_range("gravity", gravity, 0.0, np.inf, hi_open=True))
    f = float(check_range("force", force, 0.0, np.inf, hi_open=True))
    check_range("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    if radius is not None:
        radius = float(check_positive("radius", radius))
    if g + f / m <= 0.0:
        raise ValueError("gravity + force / mass must be > 0: the ball would not come back")
    if moduli is not None:
        if radius is None:
            raise ValueError("moduli need the ball's radius")
        stiffness = stiffness_from_moduli(radius, moduli, poisson)
    elif stiffness is not None:
        stiffness = float(check_positive("stiffness", stiffness))
    tol = interval_tolerance
    if tol is not None:
        tol = float(check_range("interval_tolerance", tol, 0.0, np.inf, hi_open=True))
    say = progress or (lambda line: None)
    names = hypothesis_names(hypotheses)
    given = _given(names, impedance)
    d, note = data_mod.capped(_as_data(data, kind, t, tol))
    if note:
        say(note)
    setup = Setup(m, g + f / m, given)
    kw = {"stiffness_guess": stiffness, "level": level}
    fits = {}
    for i, n in enumerate(names):
        say(f"fitting {n} ({i + 1}/{len(names)})")
        fits[n] = fit_hypothesis(HYPOTHESES[n], d, setup, intervals=False, **kw)
    best_aic = min(f.aic for f in fits.values())
    for n in names:
        gap = fits[n].aic - best_aic
        if intervals and gap <= INTERVAL_AIC_GAP:
            say(f"profile-likelihood intervals of {n}")
            fits[n] = fit_hypothesis(HYPOTHESES[n], d, setup, intervals=True, **kw)
        elif intervals:
            fits[n].status += f"; no intervals: AIC {gap:.1f} above the best law's"
    aic = np.array([fits[n].aic for n in names])
    rel = np.exp(-0.5 * (aic - aic.min()))
    weights = dict(zip(names, (rel / rel.sum()).tolist(), strict=True))
    selected = names[int(np.argmin(aic))]
    tied = sorted((n for n in names if fits[n].aic - best_aic < TIE_AIC_GAP), key=lambda n: fits[n].aic)
    say("engine inputs, each checked at its engine's default step")
    engines = {n: engine_parameters(fits[n], setup, radius) for n in names}
    return Calibration(d, setup, radius, fits, selected, weights, engines, [note] if note else [], tied)


def _given(names, impedance):
    """The given settings of the laws ``names`` (checked); ValueError if no law there takes them."""
    if impedance is None:
        return {}
    takers = [n for n in names if "impedance" in HYPOTHESES[n].given]
    if not takers:
        having = [n for n, law in HYPOTHESES.items() if "impedance" in law.given]
        raise ValueError(
            f"impedance = {impedance!r} is given but no law fitted has one ({', '.join(names)}); "
            f"laws with one: {', '.join(having)}"
        )
    d = get_law(HYPOTHESES[takers[0]].contact_law, impedance=impedance).impedance
    return {"impedance": d}


# The text report lists every contact's e_N up to this many, else the first and last few.
SHOWN_CONTACTS = 12


def format_calibration(cal):
    """Text summary: each law's parameters with intervals, e_N at the recorded speeds, AIC, engines."""
    lines = [f"{cal.data.kind}: {cal.data.count} observations from {cal.data.source}"]
    lines += [f"note: {n}" for n in cal.notes]
    for name, f in cal.fits.items():
        # "*" the selected law; "=" each law of a tie (within TIE_AIC_GAP of the lowest AIC).
        tie = len(cal.tied) > 1
        mark = ("=" if name in cal.tied else " ") if tie else ("*" if name == cal.selected else " ")
        lines.append(
            f"{mark} {name:12s} AIC {f.aic:10.2f}  BIC {f.bic:10.2f}  sigma {f.sigma:.3g}  {f.status}"
        )
        units = {p.name: p.unit for p in HYPOTHESES[name].params}
        for key, value in f.values.items():
            lo, hi = f.intervals.get(key, (math.nan, math.nan))
            closed = f.bounded.get(key, (True, True))
            lo_t = f"{lo:.6g}" if closed[0] else f"<={lo:.6g}"
            hi_t = f"{hi:.6g}" if closed[1] else f">={hi:.6g}"
            span = f"{int(100 * f.level)}% [{lo_t}, {hi_t}]" if np.isfinite([lo, hi]).all() else ""
            held = "  (held: the data cannot see it)" if key in f.fixed else ""
            held = "  (given, not fitted)" if key in f.given else held
            unit = units.get(key, "1")
            lines.append(f"    {key:10s} {value:.6g} {'' if unit == '1' else unit}  {span}{held}")
        lines += _e_n_lines(f)
        lines += engine_lines(cal.engines[name])
    lines.append(_selection_line(cal))
    return "\n".join(lines)


def _selection_line(cal):
    if len(cal.tied) < 2:
        return f"selected: {cal.selected} (lowest AIC)"
    return (
        f"selected: none, a tie: {', '.join(cal.tied)} are within {TIE_AIC_GAP:g} of the lowest AIC "
        f"({cal.selected}'s): the data do not tell them apart"
    )


def _e_n_lines(f):
    e, lo, hi = f.e_n_band
    if not len(e):
        return []
    v = f.sequence.v_in[: len(e)]
    shown = list(range(len(e)))
    if len(e) > SHOWN_CONTACTS:
        shown = shown[: SHOWN_CONTACTS - 3] + [-1] + shown[-3:]
    head = f"    e_N at the recorded approach speeds ({int(100 * f.level)}% {METHOD}):"
    if not np.isfinite(lo).any():
        head = "    e_N at the recorded approach speeds (no interval):"
    out = [head]
    for i in shown:
        if i < 0:
            out.append(f"      ... {len(e) - SHOWN_CONTACTS + 1} more contacts ...")
            continue
        band = f"  [{lo[i]:.6f}, {hi[i]:.6f}]" if np.isfinite([lo[i], hi[i]]).all() else ""
        out.append(f"      contact {i + 1:3d}  v- {v[i]:.6g} m/s  e_N {e[i]:.6f}{band}")
    return out
