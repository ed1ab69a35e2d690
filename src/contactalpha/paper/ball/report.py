"""Tables and the statement check of the bouncing ball (Sect. 6), as markdown built from results.

Every number here is read from the study Datasets (``ball_study``); nothing is
typed in.  ``statements`` lists the paper's Sect. 6 claims one by one, each
with a criterion stated in words, our numbers, and a verdict.
"""

import json

import numpy as np

from contactalpha.engine.codes import SEPARATION
from contactalpha.paper.statements import Statement, not_checked, verdict
from contactalpha.paper.statements import statements_markdown as render_statements

from .study import model_label, state_names

# Two models give "close"/"similar" responses when their post-restitution
# coefficients differ by at most this much and their end states agree.
CLOSE_EPS = 0.05
# The paper's rounded influence factors of F = 0.1, 60, 495 N (Sect. 6).
PAPER_XI = (0.021, 0.233, 0.799)
# The paper's count of collisions in case A (Sect. 6).
PAPER_COUNT_A = 10
# Collisions after which the paper says the accumulated loss error peaks.
PAPER_PEAK_AFTER = 3


def loss_error(case_a, case_b):
    """Per-collision damping-work difference ``dE_A,i - dE_B,i`` (J) over the collisions both cases have."""
    n = min(case_a.sizes["collision"], case_b.sizes["collision"])
    return case_a["c_damping_work"].values[:n] - case_b["c_damping_work"].values[:n]


def _fmt(x, digits=3):
    return f"{x:.{digits}f}"


def first_collision_table(ds):
    """Markdown table: post-restitution eps and end state for every force, eps and model."""
    names = list(ds["model"].values)
    head = "| F (N) | xi | eps | " + " | ".join(model_label(n) for n in names) + " |"
    rule = "|" + "---|" * (3 + len(names))
    rows = [head, rule]
    states = state_names(ds["state"].values)
    for i, force in enumerate(ds["force"].values):
        for j, eps in enumerate(ds["epsilon"].values):
            cells = [f"{_fmt(ds['eps_post'].values[i, j, k])} ({states[i, j, k]})" for k in range(len(names))]
            rows.append(f"| {force:g} | {_fmt(ds['xi'].values[i])} | {eps:g} | " + " | ".join(cells) + " |")
    if "eps_boundary" in ds:
        rows += [
            "",
            "Exact separation boundary: a contact that restitutes exactly the ε asked separates iff ε > ε_b.",
        ]
        rows += [
            f"- F = {f:g} N (ξ = {_fmt(x)}): ε_b = {_fmt(e)}"
            for f, x, e in zip(ds["force"].values, ds["xi"].values, ds["eps_boundary"].values, strict=True)
        ]
    return "\n".join(rows) + "\n"


def case_row(ds):
    """One markdown row summarising a run Dataset."""
    a = ds.attrs
    last = int(ds.sizes["collision"]) - 1
    state = state_names(ds["c_state"].values[last : last + 1])[0]
    return (
        f"| {a['case']} | {model_label(a['model'])} (`{a['model']}`) | {a['collisions']} | {a['rebounds']} | "
        f"{a['rebounds_above_rest_deformation']} | {a['end_state']} | {a['end_time']:.4f} | {state} | "
        f"{ds['c_xi'].values[last]:.3f} | {ds['c_delta_end'].values[last] * 1e6:.3f} | "
        f"{np.max(np.abs(ds['c_eps_post'].values - json.loads(a['scene'])['eps'])):.4f} |"
    )


CASE_HEADER = (
    "| case | model | collisions | rebounds | rebounds above δ_eq | end state | end time (s) | "
    "last contact | ξ of last contact | δ at its end (µm) | largest abs(post-ε − ε) |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|"
)


def cases_markdown(runs, skipped=()):
    """Markdown summary of case runs, with the counting rules and skipped models."""
    lines = ["# Bouncing ball, cases A and B (Sect. 6, Figs. 11-12)", ""]
    if runs:
        a = runs[0].attrs
        lines += [
            f"Counting rule: {a['counting_rule']}. Rebounds are the contacts that end with the ball "
            "leaving the ground. 'Rebounds above δ_eq' counts rebounds whose apex exceeds the static "
            f"deformation δ_eq = (m a / k)^(2/3) = {a['rest_deformation'] * 1e6:.2f} µm of the resting "
            "ball: case B never rests (its contact ignores the load and separates at every impact "
            "with the same velocity ratio), so only the time limit ends it, and bounces lower than the "
            "static sag are an artefact of leaving the load out.",
            "Case A keeps gravity and F in the contact equation (Eq. 24) and takes α from the model "
            "at each impact's ξ; case B leaves them out during contact (Eq. 43, scaled load A = 0) and "
            "takes α from the same model at ξ = 0. In case B the total energy inside a contact dips by "
            "the left-out m a δ as well; that term is zero again at separation.",
            "",
            "Energy ledger: the largest gap |E_in − E_out − D| over the contacts of a run, relative to "
            "the initial energy, with the damping work D integrated independently by SciPy: "
            + ", ".join(
                f"case {ds.attrs['case']} ({ds.attrs['model']}) {ds.attrs['ledger_closure']:.1e}"
                for ds in runs
                if "ledger_closure" in ds.attrs
            )
            + ".",
            "",
            CASE_HEADER,
            *[case_row(ds) for ds in runs],
            "",
        ]
    for name, why in skipped:
        lines.append(f"- `{name}` skipped: {why}")
    return "\n".join(lines) + "\n"


def _state(ds, force_i, eps, model):
    j = int(np.argmin(np.abs(ds["epsilon"].values - eps)))
    k = list(ds["model"].values).index(model)
    return ds["state"].values[force_i, j, k], ds["eps_post"].values[force_i, j, k]


def _reference_state(ds, force_i, eps):
    """Text naming the exact reference's end state, if the study has one."""
    ref = ds.attrs.get("reference")
    if ref not in list(ds["model"].values):
        return ""
    state, _ = _state(ds, force_i, eps, ref)
    text = f"; reference ({model_label(ref)}): {state_names([state])[0]}"
    if "eps_boundary" in ds:
        eps_b = float(ds["eps_boundary"].values[force_i])
        text += f"; the exact contact separates for every ε > {_fmt(eps_b)} at this ξ"
    return text


def _has_eps(ds, eps):
    return bool(np.any(np.isclose(ds["epsilon"].values, eps)))


def _first_collision_statements(ds, new, classical):
    out = []
    xi = ds["xi"].values
    forces = ds["force"].values
    if len(xi) == len(PAPER_XI):
        ours = ", ".join(_fmt(x, 4) for x in xi)
        ok = bool(np.all(np.abs(xi - np.array(PAPER_XI)) <= 1e-3))
        out.append(
            Statement(
                "The forces F = " + ", ".join(f"{f:g}" for f in forces) + " N give ξ = 0.021, 0.233, 0.799.",
                "abs(ξ − paper) ≤ 1e-3",
                f"ξ = {ours}",
                verdict([ok]),
            )
        )
    else:
        out.append(
            not_checked(
                "The forces F = 0.1, 60, 495 N give ξ = 0.021, 0.233, 0.799.",
                "abs(ξ − paper) ≤ 1e-3",
                f"{len(xi)} forces instead of the paper's {len(PAPER_XI)}",
            )
        )
    models_ = list(ds["model"].values)
    sep = ds["state"].values == SEPARATION

    def spread(i, j, names):
        ks = [models_.index(n) for n in names]
        e = ds["eps_post"].values[i, j, ks]
        st = ds["state"].values[i, j, ks]
        return float(np.ptp(e)), bool(np.all(st == st[0]))

    close_set = [n for n in ("flores", "hu_guo") if n in models_] + [new]
    small = int(np.argmin(xi))
    rows = [spread(small, j, close_set) for j in range(ds.sizes["epsilon"])]
    worst = max(r[0] for r in rows)
    out.append(
        Statement(
            f"At ξ = {_fmt(xi[small])} Flores, Hu–Guo and the new model give close results.",
            f"for every ε: spread of post-ε ≤ {CLOSE_EPS} and equal end states",
            f"largest spread {_fmt(worst)}; end states equal: {all(r[1] for r in rows)}",
            verdict([worst <= CLOSE_EPS and all(r[1] for r in rows)]),
        )
    )
    mid = int(np.argmin(np.abs(xi - PAPER_XI[1])))
    if "hunt_crossley" in models_ and _has_eps(ds, 0.3):
        states = {m: _state(ds, mid, 0.3, m)[0] for m in classical + [new]}
        ok = states["hunt_crossley"] == SEPARATION and all(
            s != SEPARATION for m, s in states.items() if m != "hunt_crossley"
        )
        out.append(
            Statement(
                f"At ξ = {_fmt(xi[mid])}, ε = 0.3 every model but Hunt–Crossley ends without separation.",
                "Hunt–Crossley separates, all others do not",
                ", ".join(f"{model_label(m)}: {state_names([s])[0]}" for m, s in states.items())
                + _reference_state(ds, mid, 0.3),
                verdict([ok]),
            )
        )
    else:
        out.append(
            not_checked(
                f"At ξ = {_fmt(xi[mid])}, ε = 0.3 every model but Hunt–Crossley ends without separation.",
                "Hunt–Crossley separates, all others do not",
                "Hunt–Crossley or ε = 0.3",
            )
        )
    if _has_eps(ds, 0.5):
        states = {m: _state(ds, mid, 0.5, m)[0] for m in classical + [new]}
        ok = states[new] != SEPARATION and all(s == SEPARATION for m, s in states.items() if m != new)
        out.append(
            Statement(
                f"At ξ = {_fmt(xi[mid])}, ε = 0.5 only the new model ends without separation.",
                "the new model does not separate, all others do",
                ", ".join(f"{model_label(m)}: {state_names([s])[0]}" for m, s in states.items())
                + _reference_state(ds, mid, 0.5),
                verdict([ok]),
            )
        )
    else:
        out.append(
            not_checked(
                f"At ξ = {_fmt(xi[mid])}, ε = 0.5 only the new model ends without separation.",
                "the new model does not separate, all others do",
                "ε = 0.5",
            )
        )
    pairs = [n for n in ("flores", "hu_guo") if n in models_]
    js = [j for j, e in enumerate(ds["epsilon"].values) if e >= 0.7 - 1e-12]
    if pairs and js:
        rows = [spread(mid, j, pairs + [new]) for j in js]
        worst = max(r[0] for r in rows)
        out.append(
            Statement(
                f"At ξ = {_fmt(xi[mid])}, ε ≥ 0.7, Flores and Hu–Guo respond like the new model.",
                f"spread of post-ε ≤ {CLOSE_EPS} and equal end states",
                f"largest spread {_fmt(worst)}; end states equal: {all(r[1] for r in rows)}",
                verdict([worst <= CLOSE_EPS and all(r[1] for r in rows)]),
            )
        )
    else:
        out.append(
            not_checked(
                f"At ξ = {_fmt(xi[mid])}, ε ≥ 0.7, Flores and Hu–Guo respond like the new model.",
                f"spread of post-ε ≤ {CLOSE_EPS} and equal end states",
                "Flores and Hu–Guo" if not pairs else "ε ≥ 0.7",
            )
        )
    big = int(np.argmax(xi))
    ks = [models_.index(m) for m in classical + [new]]
    nonsep = int(np.sum(~sep[big][:, ks]))
    total = sep[big][:, ks].size
    out.append(
        Statement(
            f"At ξ = {_fmt(xi[big], 4)} almost all results of the four models end without separation.",
            "more than half of the (model, ε) runs do not separate",
            f"{nonsep} of {total} do not separate",
            verdict([nonsep > total / 2]),
        )
    )
    eps_grid = ds["epsilon"].values
    differs = []
    for m in classical:
        for j in range(eps_grid.size):
            d, same = spread(big, j, [m, new])
            differs.append((m, eps_grid[j], d > CLOSE_EPS or not same))
    n_diff = sum(x[2] for x in differs)
    close_pairs = ", ".join(f"{model_label(m)} at ε = {e:g}" for m, e, x in differs if not x)
    out.append(
        Statement(
            f"At ξ = {_fmt(xi[big], 4)} all responses of Hunt–Crossley, Flores and Hu–Guo err obviously"
            " against the new model, even at ε close to 1.",
            f"for every ε, each of the three is not close to the new model (post-ε differs by > {CLOSE_EPS}"
            " or the end state differs)",
            f"{n_diff} of {len(differs)} (model, ε) responses differ"
            + (f"; close: {close_pairs}" if close_pairs else ""),
            verdict([n_diff == len(differs)]),
        )
    )
    four = classical + [new]
    err = np.abs(ds["eps_post"].values[:, :, [models_.index(m) for m in four]] - eps_grid[None, :, None])
    best = np.argmin(err, axis=2) == len(four) - 1
    out.append(
        Statement(
            "Conclusion: the described model is more suitable for impact analysis.",
            "in every (ξ, ε) of the study, the new model's post-ε is the closest of the four to the ε asked",
            f"closest in {int(best.sum())} of {best.size}; largest error of the new model "
            f"{_fmt(err[:, :, -1].max())}, of the best classical model per case "
            f"{_fmt(err[:, :, :-1].min(axis=2).max())}",
            verdict([bool(best.all())]),
        )
    )
    mono = {}
    for m in classical + [new]:
        s = sep[:, :, models_.index(m)][np.argsort(xi)][:, np.argsort(ds["epsilon"].values)]
        # separating must stay separating towards smaller xi and larger eps
        ok_xi = bool(np.all(np.diff(s.astype(int), axis=0) <= 0))
        ok_eps = bool(np.all(np.diff(s.astype(int), axis=1) >= 0))
        mono[m] = ok_xi and ok_eps
    out.append(
        Statement(
            "The larger ξ or the smaller ε, the harder the ball separates.",
            "for every model, separation at (ξ, ε) implies separation at smaller ξ and at larger ε",
            ", ".join(f"{model_label(m)}: {'monotone' if v else 'not monotone'}" for m, v in mono.items()),
            verdict([all(mono.values())]),
        )
    )
    ns = ~sep & (ds["status"].values == 0)
    zero_v = bool(np.all(ds["v_out"].values[ns] == 0.0))
    open_loop = bool(np.all(ds["delta_end"].values[ns] > 0.0))
    out.append(
        Statement(
            "Nonseparation gives zero separation velocity and an incomplete hysteresis loop.",
            "every non-separating contact ends with rebound speed 0 and deformation > 0",
            f"{int(ns.sum())} non-separating contacts; speed 0: {zero_v}; deformation > 0: {open_loop}",
            verdict([zero_v and open_loop]),
        )
    )
    return out


def _case_statements(case_a, case_b):
    out = []
    na, nb = case_a.attrs["collisions"], case_b.attrs["collisions"]
    ra = case_a.attrs["rebounds"]
    out.append(
        Statement(
            f"{PAPER_COUNT_A} collisions occur in case A.",
            "our count (final non-separating contact included), or our rebounds (excluded), equals 10",
            f"{na} collisions, {ra} rebounds; end state: {case_a.attrs['end_state']}",
            verdict([PAPER_COUNT_A in (na, ra)]),
        )
    )
    nb_phys = case_b.attrs["rebounds_above_rest_deformation"]
    out.append(
        Statement(
            "More collisions are needed in case B.",
            "case B's count exceeds case A's, by both counts",
            f"case B: {nb} collisions to t_end = {case_b.attrs['end_time']:.3f} s "
            f"(end state: {case_b.attrs['end_state']}), {nb_phys} rebounds above δ_eq; case A: {na}",
            verdict([nb > na and nb_phys > case_a.attrs["rebounds_above_rest_deformation"]]),
        )
    )
    d = loss_error(case_a, case_b)
    acc = np.cumsum(d)
    out.append(
        Statement(
            "The first collision loses more energy in case A than in case B.",
            "ΔE_A,1 > ΔE_B,1",
            f"ΔE_A,1 = {case_a['c_damping_work'].values[0] * 1e3:.4f} mJ, "
            f"ΔE_B,1 = {case_b['c_damping_work'].values[0] * 1e3:.4f} mJ",
            verdict([d[0] > 0]),
        )
    )
    k = PAPER_PEAK_AFTER
    late = (
        (
            "The loss errors of the first three collisions are > 0 and the accumulated error peaks right"
            " after the third.",
            "ΔE_A,i − ΔE_B,i > 0 for i ≤ 3 and the accumulated error is largest after collision 3",
        ),
        (
            "From the fourth collision the approach speed in case B is greater than in case A.",
            "v_B,i > v_A,i for every i ≥ 4 that both cases have",
        ),
        (
            "From the fourth collision the accumulated loss error decreases constantly.",
            "the accumulated error falls at every collision i ≥ 4 that both cases have",
        ),
    )
    if d.size <= k:
        out += [not_checked(*claim, f"only {d.size} collisions in both cases") for claim in late]
    else:
        peak = int(np.argmax(acc)) + 1
        out.append(
            Statement(
                *late[0],
                "errors (mJ): "
                + ", ".join(f"{x * 1e3:.4f}" for x in d[: k + 1])
                + f", ...; peak after collision {peak}",
                verdict([bool(np.all(d[:k] > 0)) and peak == k]),
            )
        )
        va = case_a["c_v_in"].values[k : d.size]
        vb = case_b["c_v_in"].values[k : d.size]
        ratio = vb / va
        out.append(
            Statement(
                *late[1],
                f"v_B/v_A from {ratio.min():.3f} to {ratio.max():.3f}",
                verdict([bool(np.all(ratio > 1.0))]),
            )
        )
        out.append(
            Statement(
                *late[2],
                f"accumulated error (mJ) after collision 3: {acc[k - 1] * 1e3:.4f}, "
                f"after collision {d.size}: {acc[-1] * 1e3:.4f}",
                verdict([bool(np.all(np.diff(acc[k - 1 :]) < 0))]),
            )
        )
    return out


def statements(first, case_a, case_b, new, classical):
    """The paper's Sect. 6 statements, each a ``statements.Statement``."""
    rows = []
    if case_a is not None and case_b is not None:
        rows += _case_statements(case_a, case_b)
    else:
        rows.append(not_checked("Cases A and B (Figs. 11-12).", "the case statements", "cases A and B"))
    rows += _first_collision_statements(first, new, list(classical))
    return rows


def statements_markdown(rows, notes=()):
    """Markdown table of the checked Sect. 6 statements."""
    return render_statements(rows, "The paper's Sect. 6 statements, checked against our numbers", notes)
