"""Tables of the engine round trips and of case A, as markdown generated from the result files."""

import json

import numpy as np

from contactalpha.engine.codes import END_STATES, STATE_CODES
from contactalpha.studies.engines.compute import EXACT_RUNS, verdicts

# Markers of the generated block in docs/engines/index.md.
PAGE_START = "<!-- engines:start -->"
PAGE_END = "<!-- engines:end -->"
# Column heads of the runs in the round-trip table.
RUN_HEADS = {
    "opensim_exact": "OpenSim, ours",
    "exudyn_exact": "Exudyn, ours",
    "exudyn_exact_implicit": "Exudyn gen-α, ours",
    "opensim_hunt_crossley": "OpenSim, HC 3(1−ε)/2",
    "exudyn_model1": "Exudyn model 1",
    "exudyn_model2": "Exudyn model 2",
}
SEP = STATE_CODES["separation"]


def _eps_cell(ds, run, j, k):
    r = ds.sel(run=run).isel(epsilon=j, force=k)
    eps = float(r["eps_measured"])
    sep = int(r["state_measured"]) == SEP or float(r["left_ground_after_end"]) > 0
    return f"{eps:.4f}" + ("" if sep else " ns")


def roundtrip_table(datasets):
    """Markdown table: for every (F, eps) the exact alpha, the expected end and each run's delivered eps.

    ``datasets`` are round-trip Datasets (any engines, same grid).  "ns" marks an impact that
    did not separate in the engine.
    """
    first = datasets[0]
    runs = [(ds, r) for name in RUN_HEADS for ds in datasets for r in ds["run"].values if r == name]
    head = ["F (N)", "ξ", "ε target", "α exact", "end (package)", "e_N (package)"]
    head += [f"{RUN_HEADS[r]} ε" for _, r in runs] + ["OpenSim, ours e_N"] * any(
        r == "opensim_exact" for _, r in runs
    )
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for k, force in enumerate(first["force"].values):
        for j, eps in enumerate(first["epsilon"].values):
            p = first.isel(epsilon=j, force=k)
            row = [
                f"{force:g}",
                f"{float(p['xi']):.4f}",
                f"{eps:g}",
                f"{float(p['alpha_exact']):.4f}",
                END_STATES[int(p["state_expected"])],
                f"{float(p['e_n_expected']):.4f}",
            ]
            row += [_eps_cell(ds, r, j, k) for ds, r in runs]
            for ds, r in runs:
                if r == "opensim_exact":
                    row.append(f"{float(ds.sel(run=r).isel(epsilon=j, force=k)['e_n_measured']):.4f}")
            lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def error_summary(datasets, eps_tol):
    """Markdown list: worst restitution error of every run, the verdicts, and the time per drop."""
    lines = []
    for ds in datasets:
        checks = verdicts(ds, eps_tol)
        sep = (ds["state_expected"] == SEP).values
        for run in ds["run"].values:
            r = ds.sel(run=run)
            err = np.abs(r["eps_measured"] - r["epsilon"]).values
            vs_pkg = np.nanmax(np.abs(r["eps_measured"] - r["eps_package"]).values)
            ms = 1e3 * float(r["seconds"].mean())
            text = (
                f"- {RUN_HEADS[str(run)]}: max |ε − target| {np.nanmax(err[sep]):.2e} over the "
                f"{int(sep.sum())} impacts that separate with the exact α ({np.nanmax(err):.2e} over all); "
                f"max |ε − package integrator at the same α| {vs_pkg:.1e}; {ms:.0f} ms per drop."
            )
            if run in EXACT_RUNS:
                c = checks[str(run)]
                text += (
                    f" Target ≤ {eps_tol:g}: {'met' if c['separating_ok'] else 'NOT met'}; "
                    f"{c['nonseparating_points']} impacts the exact α predicts non-separating: "
                    f"{'none separates' if c['nonseparating_ok'] else 'SOME SEPARATE'} in the engine."
                )
            lines.append(text)
    return "\n".join(lines) + "\n"


def static_table(ds):
    """Markdown table of the static penetration checks."""
    head = ["F (N)", "(m a / k)^(2/3) (m)", *[f"{e}: relative error" for e in ds["engine"].values]]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for k, force in enumerate(ds["force"].values):
        row = [f"{force:g}", f"{float(ds['delta_predicted'][k]):.6e}"]
        row += [f"{float(ds['relative_error'][i, k]):.1e}" for i in range(ds.sizes["engine"])]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def case_a_table(ds):
    """Markdown table of case A: collisions, rebounds and time to rest, OpenSim against the package."""
    a = ds.attrs
    rest = a["opensim_rest_time"]
    rows = [
        ("OpenSim, c reset at every touchdown", a["opensim_count"], a["opensim_rebounds"], rest),
        (
            "OpenSim, c of the first impact kept",
            a["frozen_count"],
            a["frozen_rebounds"],
            a["frozen_rest_time"],
        ),
        (
            "package (`scene.ball.simulate`)",
            a["package_count"],
            a["package_rebounds"],
            a["package_rest_time"],
        ),
    ]
    lines = ["| run | collisions | rebounds | time to rest (s) |", "|---|---|---|---|"]
    for name, count, reb, t in rows:
        t_text = f"{t:.9f}" if np.isfinite(t) else "still bouncing at t_end"
        lines.append(f"| {name} | {count} | {reb} | {t_text} |")
    diff = abs(rest - a["package_rest_time"])
    eps_dev = np.nanmax(np.abs(ds["opensim_eps"].values - float(_scene_eps(ds))))
    lines.append("")
    left = "LEAVES" if a["opensim_left_ground_after_rest"] else "never leaves"
    lines.append(
        f"Time to rest differs by {diff:.1e} s; every OpenSim contact delivers ε within {eps_dev:.1e} of "
        f"the target. After resting, the ball {left} the ground up to t_end and sits at "
        f"δ = {a['opensim_rest_delta']:.6e} m against (m a / k)^(2/3) = {a['rest_deformation']:.6e} m. "
        f"OpenSim took {a['opensim_seconds']:.2f} s, the package {a['package_seconds']:.3f} s."
    )
    return "\n".join(lines) + "\n"


def _scene_eps(ds):
    return json.loads(ds.attrs["scene"])["eps"]


def summary_markdown(roundtrips, static, case, eps_tol):
    """The engines page's block: round-trip table, error summary, static checks and case A."""
    versions = {}
    for ds in [*roundtrips, case]:
        versions.update(json.loads(ds.attrs["engine_versions"]))
    parts = [
        "Generated by `snakemake -c2 engines` from `results/engines/` "
        f"({', '.join(f'{k} {v}' for k, v in sorted(versions.items()))}).\n",
        "Round trips (first impact of the paper's ball, v⁻ = 0.5 m/s; delivered Stronge ε; "
        "ns: no separation):\n",
        roundtrip_table(roundtrips),
        error_summary(roundtrips, eps_tol),
        "Static penetration (stiffness conversion):\n",
        static_table(static),
        f"Case A of Sect. 6 (ε = {_scene_eps(case):g}, exact α per impact):\n",
        case_a_table(case),
    ]
    return "\n".join(parts)
