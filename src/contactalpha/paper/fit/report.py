"""The refit study as data: every fit of ``fit.py`` on one surface, compared with the paper.

``refit_report(ds, ...)`` runs the fits and returns a JSON-ready dict (the
content of ``results/fit/coefficients.json``); ``comparison_markdown`` and
``readings_markdown`` turn it into the tables of ``results/fit/``;
``package_coefficients`` is what ``contactalpha.models`` ships as ``shen_refit``.
All numbers in the markdown come from the dict, none are typed by hand.
"""

import multiprocessing
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import asdict, dataclass, field, fields
from datetime import UTC, datetime

import numpy as np

from contactalpha.io import jsonable
from contactalpha.models import shen
from contactalpha.paper.fit import compute as fit
from contactalpha.version import __version__


@dataclass(frozen=True)
class FitSettings:
    """Settings of ``refit_report``; the defaults are the workflow's ``fit`` section's.

    ``max_nfev``, ``reading_max_nfev``, ``coarse_stride`` and ``jacobian`` are library-only
    (not in the config): the evaluation budget of each Eq. 40 fit and of each other reading's
    (``fit.fit_eq40_alternative``), the main refit's continuation (``fit.fit_eq40_surface``)
    and the Jacobian of the Eq. 40 and Eq. 39 fits (``fit.JACOBIANS``).
    """

    readings: tuple = tuple(shen.READINGS)
    weights: str = "area"
    loss: str = "linear"
    verdict_k: float = fit.VERDICT_K
    eq26: dict | None = field(default_factory=lambda: {"xi": 0.2, "eps_max": fit.EQ26_EPS_MAX})
    restitution: bool = True
    max_nfev: int = fit.MAX_NFEV
    reading_max_nfev: int = fit.READING_MAX_NFEV
    coarse_stride: int = fit.COARSE_STRIDE
    jacobian: str = "exact"


# Chunks of per-section fits per worker process (refit_report with workers > 1): a few each, so
# that the processes finish together although sections cost unequally.
SECTION_CHUNKS_PER_WORKER = 3

# Order and labels of the models in the comparison table.
MODEL_LABELS = {
    "published": "Eq. 40 as published (beta = 1 as printed)",
    "published_beta": "Eq. 40 as published, only the lost beta refit",
    "refit": "Eq. 40, every constant refit",
    "slices": "Eq. 39 fitted per xi section (lambda measured)",
}


def _model_stats(alpha, points, restitution):
    return fit.error_stats(alpha, points, with_restitution=restitution)


class _Inline:
    """``submit`` runs at once, in this process: ``refit_report`` with one worker."""

    def submit(self, fn, *args, **kwargs):
        done: Future = Future()
        done.set_result(fn(*args, **kwargs))
        return done

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def _executor(workers):
    if workers == 1:
        return _Inline()
    # fork: the workers share the imports and loaded kernels instead of repeating them
    return ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"))


def refit_report(ds, workers=1, **settings):
    """Run every fit of the issue on the surface ``ds`` and compare with the published constants.

    Parameters
    ----------
    ds : xarray.Dataset
        The alpha surface.
    workers : int
        Processes for the fits after the main refit (the other readings and the per-section
        fits, each fit whole in one process): the report is the same bits for any number.
        Each process should run its BLAS on one thread (``workflow/scripts/fit_refit.py``).
    **settings
        Overrides of ``FitSettings``: ``readings`` (keys of ``shen.READINGS``
        refitted for the evidence), ``weights``, ``loss``, ``verdict_k``,
        ``eq26`` (``{"xi", "eps_max"}`` or None to skip), ``restitution``
        (measure the error as restitution through the engine), ``max_nfev``
        (evaluation budget of each Eq. 40 fit), ``reading_max_nfev`` (of each other
        reading's, ``fit.fit_eq40_alternative``), ``coarse_stride`` (continuation
        of the Eq. 40 fits, ``fit.fit_eq40_surface``; 1 for none), ``jacobian``
        (``fit.JACOBIANS``).

    Returns
    -------
    report : dict
        JSON-ready.
    fits : dict
        The ``FitResult`` objects (``eq40``, ``readings``, ``slices``, ...).

    Raises
    ------
    FitNotConverged
        If any fit whose constants are reported did not converge.
    ValueError
        For unknown settings, or a surface without valid loaded points.
    """
    if not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers = {workers!r} is outside the valid range: an integer >= 1")
    valid = {f.name for f in fields(FitSettings)}
    unknown = set(settings) - valid
    if unknown:
        raise ValueError(f"unknown fit settings {sorted(unknown)}; valid: {sorted(valid)}")
    cfg = asdict(FitSettings(**settings))
    cfg["readings"] = list(cfg["readings"])
    for r in cfg["readings"]:
        shen.check_reading(r)
    loaded, unloaded, excluded = fit.surface_points(ds, weights=cfg["weights"])
    if len(loaded) == 0:
        raise ValueError(f"the surface has no valid point with xi > 0 to fit; {excluded.describe()}")
    reading = shen.BEST_READING
    k = float(cfg["verdict_k"])

    opts = {"loss": cfg["loss"], "max_nfev": int(cfg["max_nfev"]), "jacobian": cfg["jacobian"]}
    surface_opts = {**opts, "weights": cfg["weights"], "coarse_stride": int(cfg["coarse_stride"])}
    eq40 = fit.fit_eq40_surface(ds, reading, **surface_opts)
    fit.require_converged(eq40)  # fail fast: the main result
    budget = min(int(cfg["reading_max_nfev"]), int(cfg["max_nfev"]))
    other_opts = {**opts, "weights": cfg["weights"], "max_nfev": budget}
    # The independent fits, in as many processes as asked; the sections in contiguous chunks.
    sections = np.array_split(
        np.unique(loaded.xi), 1 if workers == 1 else SECTION_CHUNKS_PER_WORKER * workers
    )
    with _executor(workers) as pool:
        others = {
            r: pool.submit(fit.fit_eq40_alternative, ds, r, eq40, **other_opts)
            for r in cfg["readings"]
            if r != reading
        }
        parts = [pool.submit(fit.fit_eq39_slices, ds, xs, jacobian=cfg["jacobian"]) for xs in sections]
        beta_only = fit.fit_eq40(loaded, reading, start={"beta": shen.PUBLISHED["beta"]}, **opts)
        beta_only.label = f"Eq. 40 ({reading}), beta only"
        zero = fit.fit_zero_load(np.unique(np.concatenate([unloaded.eps, loaded.eps])))
        s21 = fit.fit_s21()
        eq26 = None if cfg["eq26"] is None else fit.fit_eq26(ds, **cfg["eq26"])
        readings = {r: eq40 if r == reading else others[r].result() for r in cfg["readings"]}
        slices = [f for part in parts for f in part.result()]
    readings.setdefault(reading, eq40)
    fits = {"eq40": eq40, "beta_only": beta_only, "zero_load": zero, "s21": s21, "readings": readings}
    if eq26 is not None:
        fits["eq26"] = eq26
    fit.require_converged(beta_only, zero, s21, *([eq26] if eq26 is not None else []))
    evidence = fit.reading_evidence(slices)
    fits["slices"] = slices

    models = {
        "published": fit.eq40_model(loaded, {}, reading),
        "published_beta": fit.eq40_model(loaded, beta_only.values(), reading),
        "refit": fit.eq40_model(loaded, eq40.values(), reading),
        "slices": fit.slice_model(loaded, slices),
    }
    report = {
        "generated": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "contactalpha_version": __version__,
        "surface": surface_info(ds),
        "settings": cfg,
        "points": {"fitted": len(loaded), "zero_load": len(unloaded), "excluded": _exclusions(excluded)},
        "reading": {"used": reading, "text": shen.READINGS[reading], "evidence": evidence},
        "eq40": _fit_entry(eq40, fit.verdicts(eq40, shen.PUBLISHED, k, shen.UNDETERMINED)),
        "eq40_beta_only": _fit_entry(
            beta_only, fit.verdicts(beta_only, shen.PUBLISHED, k, shen.UNDETERMINED)
        ),
        "zero_load": _fit_entry(zero, fit.verdicts(zero, {"zero_load_exp": shen.ZERO_LOAD_EXP}, k)),
        "s21": _fit_entry(s21, fit.verdicts(s21, {"s21_coef": shen.S21_COEF}, k)),
        "readings": {r: _reading_entry(f, loaded) for r, f in readings.items()},
        "slices": [_slice_entry(f) for f in slices],
        "models": {m: _model_stats(a, loaded, cfg["restitution"]) for m, a in models.items()},
        "zero_load_models": {
            "published": _model_stats(shen.zero_load(unloaded.eps), unloaded, False),
            "refit": _model_stats(shen.zero_load(unloaded.eps, zero.x[0]), unloaded, False),
        },
        "lambda": _lambda_entry(loaded, eq40.values()),
    }
    if "eq26" in fits:
        report["eq26"] = _fit_entry(fits["eq26"], fit.verdicts(fits["eq26"], shen.EQ26_PUBLISHED, k))
        report["eq26"]["xi"] = fits["eq26"].extra["xi"]
        report["eq26"]["eps_max"] = fits["eq26"].extra["eps_max"]
    return jsonable(report), fits


def surface_info(ds):
    """The surface's provenance and grid size, as the report and the shipped constants record them."""
    keys = ("git_commit", "solver", "tol", "rtol", "atol", "contactalpha_version")
    info = {k: ds.attrs[k] for k in keys if k in ds.attrs}
    info.update(n_epsilon=int(ds.sizes["epsilon"]), n_xi=int(ds.sizes["xi"]))
    return info


def _exclusions(excluded):
    rows = [
        {"eps": float(e), "xi": float(x), "reason": r}
        for e, x, r in zip(excluded.eps, excluded.xi, excluded.reason, strict=True)
    ]
    return {"count": excluded.count, "by_reason": excluded.counts(), "points": rows}


def _fit_entry(f, verdicts):
    return {
        "label": f.label,
        "converged": f.converged,
        "message": f.message,
        "nfev": f.nfev,
        "n_points": f.n_points,
        "loss": f.loss,
        "rms_residual": f.rms,
        "coarse_stage": f.extra.get("coarse"),
        "constants": verdicts,
    }


def _reading_entry(f, points):
    published = fit.eq40_model(points, {}, f.extra["reading"])
    rel = np.abs(published / points.alpha - 1.0)
    return {
        "text": shen.READINGS[f.extra["reading"]],
        "converged": f.converged,
        "message": f.message,
        "nfev": f.nfev,
        "published_rms_area": fit.rms_area(rel, points.weight),
        "published_max": float(np.nanmax(rel)),
        "refit_rms_area": f.rms,
        "refit": f.values(),
    }


def _slice_entry(f):
    return {
        "xi": f.extra["xi"],
        "converged": f.converged,
        "rms": f.rms,
        "at_bound": f.extra["at_bound"],
        "constants": f.values(),
        "se": dict(zip(f.names, f.se.tolist(), strict=True)),
    }


def _lambda_entry(points, refit):
    out: dict[str, dict[str, float] | float] = {}
    for name, c in (("published", shen.PUBLISHED), ("refit", {**shen.PUBLISHED, **refit})):
        d = shen.lambda_eq40(points.eps, points.xi, c) - points.lam
        ok = np.isfinite(d)
        out[name] = {"abs_max": float(np.max(np.abs(d[ok]))), "abs_rms": float(np.sqrt(np.mean(d[ok] ** 2)))}
    separated = points.lam == 0
    predicted = shen.lambda_eq40(points.eps, points.xi) == 0
    out["end_state_agreement"] = float(np.mean(separated == predicted))
    return out


def package_coefficients(report):
    """The refit constants shipped as ``contactalpha/data/shen_refit.json`` (model ``shen_refit``)."""
    constants = dict(shen.PUBLISHED)
    constants.update({k: v["refit"] for k, v in report["eq40"]["constants"].items()})
    return {
        "description": "Eq. 40 of Shen et al. with every constant refit to the computed alpha surface",
        "reading": report["reading"]["used"],
        "constants": constants,
        "zero_load_exp": report["zero_load"]["constants"]["zero_load_exp"]["refit"],
        "fit": {k: report["settings"][k] for k in ("weights", "loss")},
        "surface": report["surface"],
        "generated": report["generated"],
    }


def _fmt(x, digits=4):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "–"
    return f"{x:.{digits}g}"


def constants_table(section):
    """Markdown rows: constant, published, refit, SE, relative change, verdict."""
    rows = ["| constant | published | refit | SE | rel. change | verdict |", "|---|---|---|---|---|---|"]
    for name, v in section["constants"].items():
        rel = None if v["rel_change"] is None else 100 * v["rel_change"]
        rows.append(
            f"| `{name}` | {_fmt(v['published'])} | {_fmt(v['refit'])} | {_fmt(v['se'], 2)} | "
            f"{_fmt(rel, 3)} % | {v['verdict']} |"
        )
    return "\n".join(rows)


def models_table(report):
    """Markdown rows: the error of each model in alpha and as restitution."""
    rows = [
        "| model | points | max rel. err. α | RMS rel. err. α (area) "
        "| max abs. err. ε | RMS abs. err. ε (area) |",
        "|---|---|---|---|---|---|",
    ]
    for name, label in MODEL_LABELS.items():
        s = report["models"][name]
        rows.append(
            f"| {label} | {s['n'] - s['n_invalid']} | {_fmt(s['alpha_rel_max'], 3)} | "
            f"{_fmt(s['alpha_rel_rms_area'], 3)} | {_fmt(s.get('eps_abs_max'), 3)} | "
            f"{_fmt(s.get('eps_abs_rms_area'), 3)} |"
        )
    return "\n".join(rows)


def comparison_markdown(report):
    """The comparison of ``results/fit/comparison.md``: constants, verdicts and model errors."""
    p = report["points"]
    ex = p["excluded"]
    k = report["settings"]["verdict_k"]
    parts = [
        "# Eq. 40 of Shen et al. refit to the computed surface",
        "",
        f"Surface: {report['surface'].get('n_epsilon')} × {report['surface'].get('n_xi')} grid, "
        f"commit `{report['surface'].get('git_commit', 'unknown')}`. "
        f"Fitted: {p['fitted']} points with ξ > 0, "
        f"{p['zero_load']} at ξ = 0; excluded: {ex['count']} ({_reasons(ex)}).",
        "",
        f"Residuals: relative in α, loss `{report['settings']['loss']}`, "
        f"weights `{report['settings']['weights']}` (area: trapezoidal cell areas of the grid, "
        "normalised to mean 1). SE from the Jacobian at the optimum; "
        f"a published constant is *consistent* when |refit − published| ≤ {k:g} SE.",
        "",
        f"Reading of the damaged first term: `{report['reading']['used']}`: {report['reading']['text']} "
        "(evidence: `eq40_readings.md`).",
        "",
        "## Eq. 40, every constant free (start: the published values)",
        "",
        constants_table(report["eq40"]),
        "",
        f"Converged: {report['eq40']['converged']} ({report['eq40']['message']}; "
        f"{report['eq40']['nfev']} evaluations). {_coarse(report['eq40'].get('coarse_stage'))}",
        "",
        "## Models: error in α and as restitution (the ε that α produces through the engine)",
        "",
        models_table(report),
        "",
        _worst_points(report),
        "",
        "## ξ = 0 branch 3(1−ε)/(2ε^p) against the exact relation",
        "",
        constants_table(report["zero_load"]),
        "",
        "Max relative error in α at ξ = 0: "
        f"published {_fmt(report['zero_load_models']['published']['alpha_rel_max'], 3)}, "
        f"refit {_fmt(report['zero_load_models']['refit']['alpha_rel_max'], 3)}.",
        "",
        "## Eq. 34: s21 = c S against s1 (Eq. 31, quadrature), on 0 ≤ ξ ≤ 0.99",
        "",
        constants_table(report["s21"]),
    ]
    if "eq26" in report:
        e = report["eq26"]
        parts += [
            "",
            f"## Eq. 26 at ξ = {e['xi']:g} (region I: ε ≤ {e['eps_max']:g})",
            "",
            constants_table(e),
        ]
    lam = report["lambda"]
    parts += [
        "",
        "## λ = x_end / x_max: Eq. 40's formula against the surface",
        "",
        f"Max |Δλ|: published {_fmt(lam['published']['abs_max'], 3)}, "
        f"refit {_fmt(lam['refit']['abs_max'], 3)}; "
        f"RMS: published {_fmt(lam['published']['abs_rms'], 3)}, refit {_fmt(lam['refit']['abs_rms'], 3)}. "
        f"Separation (λ = 0) predicted right at {100 * lam['end_state_agreement']:.1f} % of the points.",
        "",
    ]
    return "\n".join(parts)


def _worst_points(report):
    parts = []
    for name in ("published", "refit"):
        m = report["models"][name]
        ea, xa = m["alpha_rel_worst"]
        ee, xe = m.get("eps_abs_worst", (np.nan, np.nan))
        parts.append(f"{name}: α worst at (ε, ξ) = ({ea:g}, {xa:.3g}), ε worst at ({ee:g}, {xe:.3g})")
    return (
        "Worst points: " + "; ".join(parts) + ". The max relative error in α is capped at 1 for a model "
        "that only underestimates α, so the restitution error is the fairer worst case."
    )


def _coarse(stage):
    if not stage:
        return "Fitted on all points directly."
    return (
        f"Fitted by continuation: first on {stage['points']} points (a sub-grid; RMS {stage['rms']:.3g}), "
        "then on all points from that optimum."
    )


def _reasons(ex):
    return "; ".join(f"{n} {r}" for r, n in ex["by_reason"].items()) or "none"


def readings_markdown(report):
    """The evidence note ``results/fit/eq40_readings.md``: which reading of Eq. 40 the surface supports."""
    ev = report["reading"]["evidence"]
    rows = [
        "| reading | text | published RMS rel. err. (area) | published max | refit RMS (area) "
        "| refit evaluations | refit converged |",
        "|---|---|---|---|---|---|---|",
    ]
    for r, v in report["readings"].items():
        rows.append(
            f"| `{r}` | {v['text']} | {_fmt(v['published_rms_area'], 3)} | {_fmt(v['published_max'], 3)} | "
            f"{_fmt(v['refit_rms_area'], 3)} | {v['nfev']} | "
            f"{'yes' if v['converged'] else 'no: ' + v['message']} |"
        )
    srows = [
        "| ξ | τ | σ | β | b | η | 0.1568 ξ^0.9 | 1 − ξ^0.05 | RMS | on bound |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in report["slices"]:
        c, x = s["constants"], s["xi"]
        srows.append(
            f"| {x:.4g} | {_fmt(c['tau'], 3)} | {_fmt(c['sigma'], 3)} | {_fmt(c['beta'], 3)} "
            f"| {_fmt(c['b'], 3)} | {_fmt(c['eta'], 3)} | {_fmt(shen.printed_width(x), 3)} "
            f"| {_fmt(shen.printed_tau(x), 3)} | {_fmt(s['rms'], 3)} | "
            f"{', '.join(s['at_bound']) or '–'} |"
        )
    role = ev["role"]
    verdict = {
        "sigma": "the printed `0.1568 ξ^0.9` is the width σ of the exponential; β is not printed (lost)",
        "beta": "the printed `0.1568 ξ^0.9` is the divisor β; σ is not printed",
        "none": "no section constrains the first term: the role cannot be decided on this surface",
    }[role]
    return "\n".join(
        [
            "# Which reading of Eq. 40's damaged first term does the surface support?",
            "",
            "The OCR'd first term reads `e^{−(ε+1−ξ^{0.05})²}`, `0.1568 ξ^{0.9}` and a duplicated `(1−ε)^6`;",
            "Eq. 39's generic form is `e^{−(ε+τ)²/σ}(1−ε)^a/β`"
            " (docs/science.md, 'Reading the damaged equations').",
            "",
            "## 1. Per-ξ fits of Eq. 39 (a = 6 held, λ from the surface, η_c = 1)",
            "",
            "Sections that pin the first term (converged, no constant on a bound, first term ≥ 10 % of α "
            f"at the smallest ε): {len(ev['sections'])}. Median |ln(fit / 0.1568 ξ^0.9)|: "
            f"as σ {_fmt(ev['sigma_score'], 3)}, "
            f"as β {_fmt(ev['beta_score'], 3)}. Median |τ − (1 − ξ^0.05)|: {_fmt(ev['tau_score'], 3)}.",
            "",
            f"**Verdict: {verdict}.**",
            "",
            "## 2. Eq. 40 under each reading, as published and refit (every constant free)",
            "",
            f"`{report['reading']['used']}` is the main refit (`comparison.md`). The other readings are "
            "refit on all points from their published first term and the main refit's second term, "
            f"with at most {min(report['settings']['reading_max_nfev'], report['settings']['max_nfev'])} "
            "evaluations each: the beta readings drift without converging, their RMS is where the "
            "budget ends.",
            "",
            *rows,
            "",
            "What cannot be recovered: the value of β under the σ reading (it is not printed; the",
            "published model uses β = 1, the refit determines it from our surface), and whether the",
            "duplicated (1−ε)^6 was one factor or a typesetting echo (a = 6 versus a = 0: compare the rows",
            "above).",
            "",
            "## 3. The per-section constants",
            "",
            *srows,
            "",
        ]
    )
