"""The speed-and-accuracy benchmark stage (issue 7): its runs, tables, figures and docs text.

``run_workprecision``, ``run_failures`` and ``run_scaling`` run the measurements of
``workprecision`` and write ``results/bench/*.csv`` and ``scaling.json`` (long runs resume
from a fingerprinted checkpoint).  The summary, figures and the block of docs/performance.md between
``PAGE_START`` and ``PAGE_END`` are made from those files only, so quoted numbers
cannot drift from the measured ones.
"""

import json
import os
import platform
import re
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from contactalpha.io import json_text, jsonable, write_atomic, write_json_atomic, write_text_atomic
from contactalpha.paper.bench import workprecision
from contactalpha.plotting import new_figure, save_figure
from contactalpha.provenance import result_attrs, settings_fingerprint

from .workprecision import CATEGORIES, METHODS, REGIMES, SCIPY_MAX_NFEV, SCIPY_METHODS, cost_to_reach


@dataclass(frozen=True)
class FailureSettings:
    """The failure maps' grids and settings: the workflow's ``bench.failure`` section.

    Engine and RK4 run on the fine ``eps x xi`` grid, the SciPy methods (10 ms to 10 s a solve)
    on the coarse ``eps_coarse x xi_coarse`` one; every adaptive method at ``rtol``, RK4 with
    step ``rk4_step`` (scaled time).
    """

    rtol: float = 1e-8
    rk4_step: float = 1e-3
    eps: tuple = (0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99)
    # Dense below 0.01 for the stiff ridge at small xi.
    xi: tuple = (0.0, 1e-4, 3e-4, 1e-3, 3e-3, 0.005, 0.01, 0.03, 0.1, 0.2, 0.4, 0.6, 0.8, 0.9, 0.95, 0.99)
    eps_coarse: tuple = (0.01, 0.1, 0.5, 0.9)
    xi_coarse: tuple = (0.0, 0.005, 0.1, 0.5, 0.9, 0.99)


@dataclass(frozen=True)
class ScalingSettings:
    """The scaling study's settings: the workflow's ``bench.scaling`` section.

    ``sizes`` (approximate square-grid sizes timed), ``thread_points`` (the 1- against 2-thread
    grid), ``stiff_xi`` (load of the cost-against-alpha runs), ``alphas`` (the engine's damping
    factors there), ``scipy_methods``, ``scipy_rtol`` and ``scipy_alphas`` (SciPy's runs), and
    ``alpha_fit_min`` (smallest alpha in the fit nfev = c alpha^p).
    """

    sizes: tuple = (100, 1000, 10000, 100000)
    thread_points: int = 10000
    stiff_xi: float = 0.005
    # Half-decades from 1 to 1e6.
    alphas: tuple = (1, 3.16, 10, 31.6, 100, 316, 1000, 3160, 10000, 31600, 100000, 316000, 1000000)
    scipy_methods: tuple = ("RK45", "Radau")
    scipy_rtol: float = 1e-8
    scipy_alphas: tuple = (1, 10, 100, 1000, 10000, 100000)
    alpha_fit_min: float = 100


@dataclass(frozen=True)
class BenchSettings:
    """The benchmark stage's settings: the workflow's ``bench`` section.

    ``rtols`` (adaptive methods, atol = ``ATOL_RATIO`` rtol) and ``rk4_steps`` are the settings of
    the work-precision chart; ``scipy_methods`` the SciPy methods compared, each impact limited to
    ``scipy_max_nfev`` RHS evaluations; ``failure`` and ``scaling`` the other two studies'.
    """

    # Decades from 1e-3 to 1e-13.
    rtols: tuple = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13)
    rk4_steps: tuple = (0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 0.0005, 0.0002)
    scipy_methods: tuple = SCIPY_METHODS
    scipy_max_nfev: int = SCIPY_MAX_NFEV
    failure: FailureSettings = field(default_factory=FailureSettings)
    scaling: ScalingSettings = field(default_factory=ScalingSettings)


# Markers of the generated block in docs/performance.md.
PAGE_START = "<!-- bench:start -->"
PAGE_END = "<!-- bench:end -->"
# The module whose source closure (every engine and baseline it runs) a checkpoint's rows depend on.
BENCH_CODE = "contactalpha.paper.bench.workprecision"
# Accuracy levels (relative error of alpha) at which costs are compared.
TARGETS = (1e-6, 1e-10)
# Lowest error drawn on log axes: errors of 0 (the reference itself) sit here.
ERROR_FLOOR = 1e-16
# One colour and marker per method, in ``METHODS`` order.
STYLE = dict(
    zip(
        METHODS,
        [
            ("k", "o"),
            ("tab:purple", "*"),
            ("tab:gray", "x"),
            ("tab:blue", "s"),
            ("tab:orange", "^"),
            ("tab:green", "D"),
            ("tab:red", "v"),
        ],
        strict=True,
    )
)
# Colours of the failure categories, in ``CATEGORIES`` order.
CATEGORY_COLOURS = ("#d9f0d3", "#fdb863", "#b2abd2", "#e66101", "#5e3c99", "#000000", "#969696")


def machine_info():
    """A one-line description of the machine the benchmark ran on."""
    import numba

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numba {numba.__version__}, {platform.system()}"
    )


def plot_work_precision(wp, references, paths):
    """Error against cost, one curve per method; columns are the regimes.

    Rows: time per alpha solve and RHS evaluations against the relative error
    of alpha, and time against the error of the eps produced.  The dotted line
    is the spread of the independent confirmations of the reference.
    """
    regimes = list(REGIMES)
    fig, axes = new_figure(len(regimes), 3, aspect=0.8, sharey="row")
    rows = (
        ("err_alpha", "seconds", "time per α solve [s]"),
        ("err_alpha", "nfev", "RHS evaluations"),
        ("err_eps", "seconds", "time per α solve [s]"),
    )
    for c, regime in enumerate(regimes):
        ref = references[references.regime == regime].iloc[0]
        for r, (err, cost, label) in enumerate(rows):
            ax = axes[r, c]
            for method in METHODS:
                d = wp[(wp.regime == regime) & (wp.method == method) & (wp.status == "ok")]
                if d.empty:
                    continue
                d = d.sort_values("setting")
                colour, marker = STYLE[method]
                ax.loglog(
                    np.maximum(d[err], ERROR_FLOOR),
                    d[cost],
                    marker=marker,
                    color=colour,
                    ms=3,
                    lw=0.8,
                    label=method,
                )
            if err == "err_alpha" and ref.spread > 0:
                ax.axvline(ref.spread, color="k", ls=":", lw=0.7)
            if r == 0:
                ax.set_title(f"{regime}\nε={ref.eps:g}, ξ={ref.xi:g}")
            if c == 0:
                ax.set_ylabel(label)
            ax.set_xlabel("rel. error of α" if err == "err_alpha" else "error of ε")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=4)
    save_figure(fig, paths)


def _grid_image(ax, d, title):
    eps = np.sort(d.eps.unique())
    xi = np.sort(d.xi.unique())
    img = np.full((eps.size, xi.size), np.nan)
    codes = {name: k for k, name in enumerate(CATEGORIES)}
    for row in d.itertuples():
        img[np.searchsorted(eps, row.eps), np.searchsorted(xi, row.xi)] = codes[row.category]
    from matplotlib.colors import ListedColormap

    ax.imshow(
        img,
        origin="lower",
        cmap=ListedColormap(CATEGORY_COLOURS),
        vmin=-0.5,
        vmax=len(CATEGORIES) - 0.5,
        aspect="auto",
        interpolation="nearest",
    )
    ax.set_xticks(range(xi.size), [f"{x:g}" for x in xi], rotation=90, fontsize=5)
    ax.set_yticks(range(eps.size), [f"{e:g}" for e in eps], fontsize=5)
    ax.set_xlabel("ξ (grid index; values marked)")
    ax.set_ylabel("ε")
    ax.set_title(title, fontsize=8)


def plot_failure_map(failures, paths):
    """One panel per method: each grid point coloured by its failure category."""
    methods = [m for m in METHODS if m in set(failures.method)]
    ncols = 3
    nrows = -(-len(methods) // ncols)
    fig, axes = new_figure(ncols, nrows, aspect=0.4 * nrows)
    axes = np.atleast_1d(axes).ravel()
    for ax, method in zip(axes, methods, strict=False):
        d = failures[failures.method == method]
        _grid_image(ax, d, f"{method} ({_setting_label(method, d.setting.iloc[0])})")
    for ax in axes[len(methods) :]:
        ax.set_visible(False)
    from matplotlib.patches import Patch

    handles = [Patch(color=c, label=n) for c, n in zip(CATEGORY_COLOURS, CATEGORIES, strict=True)]
    fig.legend(handles=handles, loc="outside lower center", ncol=len(CATEGORIES), fontsize=6)
    save_figure(fig, paths)


def _setting_label(method, setting):
    return f"h = {setting:g}" if method == "rk4" else f"rtol = {setting:g}"


def plot_scaling(scaling, paths):
    """Grid time against points, 1 against 2 threads, and impact cost against alpha (stiff regime)."""
    fig, (a, b, c) = new_figure(3, 1, aspect=0.33)
    g = scaling["grid"]
    n = np.array([r["n"] for r in g])
    t = np.array([r["seconds"] for r in g])
    a.loglog(n, t, "ko")
    p, k = scaling["grid_fit"]["exponent"], scaling["grid_fit"]["prefactor"]
    a.loglog(n, k * n**p, "k-", lw=0.8, label=f"fit: t ∝ n^{p:.2f}")
    a.set_xlabel("grid points")
    a.set_ylabel("wall time [s]")
    a.legend()
    th = scaling["threads"]
    b.bar([str(r["threads"]) for r in th], [r["seconds"] for r in th], color="0.6")
    b.set_xlabel(f"numba threads ({th[0]['n']} points)")
    b.set_ylabel("wall time [s]")
    for label, rows in scaling["cost_vs_alpha"].items():
        ok = [r for r in rows if r["status"] == "ok"]
        fit = scaling["alpha_fits"].get(label)
        text = f"{label}: p = {fit['exponent']:.2f}" if fit else label
        c.loglog([r["alpha"] for r in ok], [r["nfev"] for r in ok], marker="o", ms=3, lw=0.8, label=text)
    c.set_xlabel("α")
    c.set_ylabel("RHS evaluations per impact")
    c.legend(fontsize=6)
    save_figure(fig, paths)


def ratio_table(wp):
    """Rows ``(regime, method, target, seconds, engine seconds, ratio)``: cost to reach each target."""
    rows = []
    records = wp.to_dict("records")
    for regime in REGIMES:
        sub = [r for r in records if r["regime"] == regime]
        for target in TARGETS:
            ours = cost_to_reach(sub, "engine", target)
            for method in METHODS[1:]:
                theirs = cost_to_reach(sub, method, target)
                rows.append(
                    {
                        "regime": regime,
                        "method": method,
                        "target": target,
                        "seconds": theirs,
                        "engine_seconds": ours,
                        "ratio": theirs / ours,
                    }
                )
    return rows


def _fmt_ratio(x):
    if not np.isfinite(x):
        return "not reached"
    return f"{x:,.0f}×" if x >= 10 else f"{x:.2g}×"


# What each curve is; static text, the numbers below it are generated.
METHODS_NOTE = (
    "Methods: *engine* is the adaptive DOP853 engine with Newton on its sensitivities "
    '(`solve_alpha(..., guess="formula", exact_at_zero=False)`), started like every other method from '
    "the exact unloaded α (from Hu & Guo's α on the ξ = 0 column, where that is the answer); "
    "*engine-table* is `solve_alpha`'s default, started from the shipped exact table (often one "
    "confirming impact); *rk4* is fixed-step classical RK4 with naive events "
    "(`contactalpha.baselines.fixedstep`); *scipy-X* is `solve_ivp(method=X)` with events. "
    "rk4 and SciPy find "
    "α by bracketing and Brent's method. The root tolerance equals the integrator's rtol (atol = "
    "rtol/100); rk4's Brent tolerance is 1e-14."
)


def failure_details(failures):
    """One sentence per failure kind: which end states were confused, which statuses, worst error."""
    out = []
    wrong = failures[failures.category == "wrong end state"]
    if len(wrong):
        pairs = wrong.groupby(["state", "true_state"]).size().sort_values(ascending=False)
        out.append(
            "Wrong end states (reported → true at the same α): "
            + ", ".join(f"{a} → {b} ×{n}" for (a, b), n in pairs.items())
            + f"; the largest relative α error among them is {wrong.err_alpha.max():.1e}."
        )
    other = failures[failures.category.isin(["other", "missed event", "step limit", "no root bracketed"])]
    if len(other):
        statuses = other.status.str.split(":").str[0].value_counts()
        out.append("Statuses of failed solves: " + ", ".join(f"{k} ×{n}" for k, n in statuses.items()) + ".")
    errs = failures[failures.category == "error > 1e-6"]
    if len(errs):
        out.append(
            "Errors above 1e-6 at (ε, ξ) = "
            + ", ".join(f"({r.eps:g}, {r.xi:g}) {r.method} {r.err_alpha:.1e}" for r in errs.itertuples())
            + "."
        )
    return " ".join(out)


def thread_cores_note(row):
    """What a 2-thread timing row says about its cores: busy cores, and whether they were free."""
    load = ", ".join(f"{x:.1f}" for x in row.get("load_average", [])) or "?"
    note = f"the 2-thread run kept {row['cores_busy']:.2f} cores busy, load average {load}"
    if not row["cores_free"]:
        note += (
            "; it did not get its second core (other work held it), so this speed-up is the "
            "machine's, not the library's: rerun on an idle machine"
        )
    return note


def summary_markdown(wp, references, counts, scaling, grids, failures=None):
    """The performance page's block: machine, headline ratios, references, failure counts, scaling."""
    info = scaling["machine"]
    lines = [
        f"Measured on {info} (shared by other jobs while it ran; times are the best of "
        "repeated batches, one thread, per α solve; the engine's per point of a 64-point call).",
        "",
        METHODS_NOTE,
        "",
    ]
    ratios = ratio_table(wp)
    lines += [
        "**Cost of SciPy and fixed-step RK4 relative to the engine at equal accuracy** "
        "(least time per α solve reaching a relative α error ≤ target; ratio = method / engine):",
        "",
    ]
    methods = [m for m in METHODS[1:] if m in set(wp.method)]
    lines += [
        "| regime | target | engine | " + " | ".join(methods) + " |",
        "|---|---|---|" + "---|" * len(methods),
    ]
    for regime in REGIMES:
        for target in TARGETS:
            sel = [
                r
                for r in ratios
                if r["regime"] == regime and r["target"] == target and r["method"] in methods
            ]
            ours = sel[0]["engine_seconds"]
            ours_txt = "not reached" if not np.isfinite(ours) else f"{ours * 1e3:.3g} ms"
            cells = [_fmt_ratio(r["ratio"]) if np.isfinite(ours) else "–" for r in sel]
            lines.append(f"| {regime} | {target:g} | {ours_txt} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "References: ξ = 0 from the exact relation; elsewhere the engine at rtol = 1e-13, "
        "confirmed by SciPy DOP853 (rtol 1e-13) and fixed-step RK4 (h = 1e-4); relative deviation of "
        "their α from it (DOP853, RK4): "
        + ", ".join(
            f"{r.regime} {abs(r.alpha_scipy / r.alpha - 1):.1e}, {abs(r.alpha_rk4 / r.alpha - 1):.1e}"
            for r in references.itertuples()
        )
        + ". The dotted lines on the chart mark the larger of the two: errors below it are not resolved.",
        "",
    ]
    lines += [
        f"**Failures** over the (ε, ξ) grid ({grids}):",
        "",
        "| method | setting | " + " | ".join(CATEGORIES) + " |",
        "|---|---|" + "---|" * len(CATEGORIES),
    ]
    for c in counts:
        lines.append(
            f"| {c['method']} | {_setting_label(c['method'], c['setting'])} | "
            + " | ".join(str(c[k]) for k in CATEGORIES)
            + " |"
        )
    if failures is not None:
        lines += ["", failure_details(failures)]
    g = scaling["grid_fit"]
    th = {r["threads"]: r["seconds"] for r in scaling["threads"]}
    two = next(r for r in scaling["threads"] if r["threads"] == 2)
    fits = scaling["alpha_fits"]
    ridge = scaling["ridge"]
    lines += [
        "",
        f"**Scaling.** Grid time grows as n^{g['exponent']:.2f} from {scaling['grid'][0]['n']} to "
        f"{scaling['grid'][-1]['n']} points ({scaling['grid'][-1]['seconds']:.1f} s for the largest). "
        f"{scaling['threads'][0]['n']} points take {th[1]:.2f} s on 1 thread and {th[2]:.2f} s on 2 "
        f"(speed-up {th[1] / th[2]:.2f}; {thread_cores_note(two)}). Cost of one impact against α, "
        "fitted exponent p in nfev ∝ α^p for α ≥ "
        + f"{scaling['alpha_fit_min']:g}: "
        + "; ".join(f"{k} p = {v['exponent']:.2f}" for k, v in fits.items())
        + ". "
        f"The ridge (ε < 0.1, 0 < ξ < 0.1) holds {100 * ridge['share_points']:.0f}% of the surface "
        f"grid's points and takes {100 * ridge['share_nfev']:.0f}% of its RHS evaluations and "
        f"{100 * ridge['share_seconds']:.0f}% of its time.",
    ]
    return "\n".join(lines) + "\n"


def fill_page(page, text, start=PAGE_START, end=PAGE_END):
    """Replace the text between the markers ``start`` and ``end`` in ``page`` (atomically)."""
    page = Path(page)
    old = page.read_text(encoding="utf-8")
    pattern = re.compile(re.escape(start) + ".*?" + re.escape(end), re.S)
    if not pattern.search(old):
        raise ValueError(f"{page} has no {start} ... {end} block; add the markers once")
    new = pattern.sub(lambda _: f"{start}\n{text}{end}", old)
    write_text_atomic(page, new)
    return new


# --- stages: config section in, files out (called by the workflow and the benchmark) ---


def _write_csv(rows, path):
    write_atomic(path, lambda tmp: pd.DataFrame(rows).to_csv(tmp, index=False))


def _fields(settings, names):
    """The named fields of ``settings`` as plain JSON-ready values (what a checkpoint or a file records)."""
    return {name: jsonable(asdict(settings)[name]) for name in names}


def _read_csv(path):
    return pd.read_csv(path, keep_default_na=True)


def method_settings(settings):
    """Method name -> its settings on the work-precision chart (rtols or RK4 steps) of ``BenchSettings``."""
    rtols, steps = list(settings.rtols), list(settings.rk4_steps)
    out = {"engine": rtols, "engine-table": rtols, "rk4": steps}
    out.update({f"scipy-{m}": rtols for m in settings.scipy_methods})
    return out


def checkpoint(path, settings, log=print):
    """Rows saved by an interrupted run of the same stage (``<path>.partial``, JSON lines), and an appender.

    The file's first line is the fingerprint of ``settings`` and of the benchmark's code
    (``provenance.settings_fingerprint``): rows written under other settings or by other code
    are discarded, never resumed.

    Returns
    -------
    done : list of dict
    save : callable appending a list of rows
    partial : Path
    """
    path = Path(str(path) + ".partial")
    stamp = {"fingerprint": settings_fingerprint(settings, BENCH_CODE)}
    done = []
    if path.exists():
        lines = path.read_text().splitlines()
        if lines and json.loads(lines[0]) == stamp:
            done = [json.loads(line) for line in lines[1:]]
        else:
            log(f"{path.name}: written with other settings or code; its rows are discarded")
            path.unlink()

    def save(rows):
        with open(path, "a", encoding="utf-8") as fh:
            if fh.tell() == 0:
                fh.write(json_text(stamp) + "\n")
            for row in rows:
                fh.write(json_text(row) + "\n")

    return done, save, path


def run_workprecision(settings, reference_csv, workprecision_csv, log=print):
    """References of every regime, then error against cost of every method and setting.

    ``settings`` is a ``BenchSettings``: its ``rtols``, ``rk4_steps``, ``scipy_methods`` and
    ``scipy_max_nfev`` are used.  Long: each (regime, method) block is appended to ``<table>.partial`` as it
    finishes, and a rerun after an interruption (same settings) skips blocks
    found there; the file is removed when the table is written.
    """
    refs = workprecision.reference_rows()
    for r in refs:
        log(f"reference {r['regime']}: alpha = {r['alpha']:.15g}, spread {r['spread']:.2e}")
    _write_csv(refs, reference_csv)
    keys = ("rtols", "rk4_steps", "scipy_methods", "scipy_max_nfev")
    rows, save, partial = checkpoint(workprecision_csv, _fields(settings, keys), log)
    done = {(r["regime"], r["method"]) for r in rows}
    for ref in refs:
        for method, values in method_settings(settings).items():
            if (ref["regime"], method) in done:
                log(f"{ref['regime']} {method}: taken from {partial.name}")
                continue
            part = workprecision.work_precision(
                ref["eps"], ref["xi"], ref["alpha"], {method: values}, max_nfev=settings.scipy_max_nfev
            )
            part = [{"regime": ref["regime"], **r} for r in part]
            save(part)
            rows += part
            log(
                f"{ref['regime']} {method}: {sum(r['status'] == 'ok' for r in part)}/{len(part)} ok, "
                f"{sum(r['seconds'] for r in part):.1f} s"
            )
    _write_csv(rows, workprecision_csv)
    partial.unlink(missing_ok=True)


def run_failures(settings, failure_csv, counts_csv, log=print):
    """Failure maps: engine and RK4 on the fine grid, the SciPy methods on the coarse one.

    ``settings`` is a ``BenchSettings``: its ``failure``, ``scipy_methods`` and ``scipy_max_nfev``
    are used.
    """
    f = settings.failure
    fine, coarse = (list(f.eps), list(f.xi)), (list(f.eps_coarse), list(f.xi_coarse))
    plan = [(m, f.rtol, *fine) for m in ("engine", "engine-table")]
    plan += [("rk4", f.rk4_step, *fine)]
    plan += [(f"scipy-{m}", f.rtol, *coarse) for m in settings.scipy_methods]
    keys = ("failure", "scipy_methods", "scipy_max_nfev")
    rows, save, partial = checkpoint(failure_csv, _fields(settings, keys), log)
    counts = []
    for method, setting, eps, xi in plan:
        part = [r for r in rows if r["method"] == method]
        if part:
            log(f"failures {method}: taken from {partial.name}")
        else:
            part = workprecision.failure_rows(method, setting, eps, xi, max_nfev=settings.scipy_max_nfev)
            save(part)
            rows += part
        n = workprecision.category_counts([workprecision.CATEGORIES.index(r["category"]) for r in part])
        n_err = sum(1 for r in part if (r["err_alpha"] or 0.0) > workprecision.FAIL_ERROR)
        counts.append(
            {"method": method, "setting": setting, "points": len(part), **n, "any error > 1e-6": n_err}
        )
        log(f"failures {method}: {n}")
    _write_csv(rows, failure_csv)
    _write_csv(counts, counts_csv)
    partial.unlink(missing_ok=True)


def run_scaling(settings, scaling_json, log=print):
    """Scaling study (``workprecision.scaling_study``) plus the machine, as JSON.

    ``settings`` is a ``BenchSettings``: its ``scaling`` is used (and recorded).
    """
    s = settings.scaling
    alphas, scipy_alphas = list(s.alphas), list(s.scipy_alphas)
    runs = {
        f"engine ξ={s.stiff_xi:g}": ("engine", 1e-12, s.stiff_xi, alphas),
        "engine ξ=0": ("engine", 1e-12, 0.0, alphas),
    }
    for m in s.scipy_methods:
        runs[f"scipy-{m} ξ={s.stiff_xi:g}"] = (f"scipy-{m}", s.scipy_rtol, s.stiff_xi, scipy_alphas)
    eps = np.round(np.arange(1, 100) * 0.01, 2)
    xi = np.unique(np.concatenate([np.round(np.arange(0, 100) * 0.01, 2), np.geomspace(1e-5, 1e-2, 25)]))
    out = workprecision.scaling_study(list(s.sizes), s.thread_points, runs, s.alpha_fit_min, eps, xi)
    out["machine"] = machine_info()
    out["ridge_grid"] = f"{eps.size} x {xi.size} (the surface stage's default grid)"
    out.update(result_attrs(_fields(settings, ("scaling",)), "bench: scaling"))
    log(f"scaling: grid exponent {out['grid_fit']['exponent']:.3f}, ridge {out['ridge']}")
    write_json_atomic(scaling_json, out)


def grid_description(settings):
    """Text naming the failure-map grids of ``settings`` (a ``BenchSettings``)."""
    f = settings.failure
    fine = f"{len(f.eps)} × {len(f.xi)} points for engine and rk4"
    coarse = f"{len(f.eps_coarse)} × {len(f.xi_coarse)} for SciPy"
    return (
        f"{fine}, {coarse}; ε ∈ {{{', '.join(f'{e:g}' for e in f.eps_coarse)}}}, "
        f"ξ ∈ {{{', '.join(f'{x:g}' for x in f.xi_coarse)}}} on the coarse grid; "
        f"SciPy's step limit is {settings.scipy_max_nfev:,} RHS evaluations per impact"
    )


def run_summary(
    settings,
    reference_csv,
    workprecision_csv,
    counts_csv,
    scaling_json,
    summary_md,
    page=None,
    failure_csv=None,
):
    """Write the generated markdown and, if ``page`` is given, put it between that page's markers.

    ``settings`` is a ``BenchSettings``: its ``failure`` grids and ``scipy_max_nfev`` are named.
    """
    wp = _read_csv(workprecision_csv)
    refs = _read_csv(reference_csv)
    counts = _read_csv(counts_csv).to_dict("records")
    scaling = json.loads(Path(scaling_json).read_text())
    failures = None if failure_csv is None else _read_csv(failure_csv)
    text = summary_markdown(wp, refs, counts, scaling, grid_description(settings), failures)
    write_text_atomic(summary_md, text)
    if page is not None:
        fill_page(page, text)
    return text


def run_figures(folder):
    """All three benchmark figures (PNG and PDF) from the tables in ``folder``."""
    folder = Path(folder)
    refs = _read_csv(folder / "reference.csv")
    plot_work_precision(
        _read_csv(folder / "workprecision.csv"),
        refs,
        [folder / "workprecision.png", folder / "workprecision.pdf"],
    )
    plot_failure_map(
        _read_csv(folder / "failure_map.csv"), [folder / "failure_map.png", folder / "failure_map.pdf"]
    )
    scaling = json.loads((folder / "scaling.json").read_text())
    plot_scaling(scaling, [folder / "scaling.png", folder / "scaling.pdf"])
