"""What each contact model really delivers: post- versus pre-restitution (paper Fig. 9).

Take a "pre-restitution" eps, compute alpha with a model, integrate Eq. 24 at
the load xi with the impact engine, and measure Stronge's eps: the
"post-restitution" coefficient.  A perfect model gives post = pre.  The
checks of the paper's statements about Fig. 9 (end of Sect. 5) are written
here as explicit, numeric criteria.
"""

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from contactalpha.engine.codes import END_STATES, NONSEPARATION, STATE_CODES
from contactalpha.engine.driver import impact
from contactalpha.io import json_text
from contactalpha.models import MODELS, alpha
from contactalpha.paper.statements import Statement, not_checked, verdict

# The classical models the paper compares, in its order (derived without external forces).
CLASSICAL = ("hunt_crossley", "lankarani_nikravesh", "flores", "hu_guo")
# A deviation |post - pre| above this counts as "obvious" in the statement checks.
OBVIOUS = 0.05
# "Low" restitution in the statement checks.
LOW_EPS = 0.3
# "Close to unity" in the statement checks.
HIGH_EPS = 0.9


@dataclass(frozen=True)
class Fig9Settings:
    """Settings of Fig. 9; the defaults are the ``models.fig9`` section's (the paper's panels).

    ``eps`` is a range ``{start, stop, step}`` of pre-restitution coefficients.
    """

    xi: tuple = (0.0, 0.016, 0.227, 0.429, 0.665, 0.91)
    models: tuple = (*CLASSICAL, "shen_published", "shen_refit", "closed_form")
    new_model: str = "shen_published"
    reference: str = "exact"
    eps: dict = field(default_factory=lambda: {"start": 0.01, "stop": 0.99, "step": 0.01})
    rtol: float = 1e-12
    atol: float = 1e-14

    def eps_values(self):
        """The pre-restitution coefficients of the ``eps`` range, ends included (rounded to 10 digits)."""
        r = self.eps
        return np.round(np.arange(r["start"], r["stop"] + 0.5 * r["step"], r["step"]), 10)


def post_vs_pre(models, xis, eps_pre, *, rtol=Fig9Settings.rtol, atol=Fig9Settings.atol):
    """Post-restitution eps for every (model, xi, eps_pre).

    Returns
    -------
    xarray.Dataset
        Dims ``model``, ``xi``, ``eps_pre``; variables ``alpha``, ``eps_post``,
        ``state`` (int8 end-state code, legend in attrs) and ``status`` (str).
    """
    eps_pre = np.asarray(eps_pre, dtype=float)
    shape = (len(models), len(xis), eps_pre.size)
    a = np.full(shape, np.nan)
    post = np.full(shape, np.nan)
    state = np.zeros(shape, dtype=np.int8)
    status = np.empty(shape, dtype=object)
    for i, name in enumerate(models):
        for j, xi in enumerate(xis):
            a[i, j] = alpha(eps_pre, xi, model=name)
            r = impact(a[i, j], xi, rtol=rtol, atol=atol)
            post[i, j] = r.eps
            state[i, j] = [STATE_CODES[s] for s in np.atleast_1d(r.state)]
            status[i, j] = np.atleast_1d(r.status)
    return xr.Dataset(
        {
            "alpha": (
                ("model", "xi", "eps_pre"),
                a,
                {"long_name": "damping factor from the model", "units": "1"},
            ),
            "eps_post": (
                ("model", "xi", "eps_pre"),
                post,
                {"long_name": "Stronge restitution produced (post-restitution)", "units": "1"},
            ),
            "state": (
                ("model", "xi", "eps_pre"),
                state,
                {"long_name": "end state", "legend": json_legend(), "units": "1"},
            ),
            "status": (("model", "xi", "eps_pre"), status.astype(str), {"long_name": "integrator status"}),
        },
        coords={"model": list(models), "xi": list(xis), "eps_pre": eps_pre},
    )


def json_legend():
    """End-state legend as a JSON string, for dataset attributes."""
    return json_text(END_STATES)


def max_deviation(ds):
    """Largest ``|post - pre|`` per model and panel, and the pre-restitution eps where it occurs."""
    dev = np.abs(ds.eps_post - ds.eps_pre)
    worst = dev.fillna(-1.0).argmax("eps_pre")
    return dev.max("eps_pre"), ds.eps_pre[worst]


def deviation_table(ds):
    """Markdown table of ``max |post - pre|`` (at which eps) per model (rows) and xi (columns)."""
    dmax, where = max_deviation(ds)
    xis = [float(x) for x in ds.xi.values]
    lines = ["| model | " + " | ".join(f"ξ = {x:g}" for x in xis) + " |", "|---|" + "---|" * len(xis)]
    for m in ds.model.values:
        label = MODELS[str(m)].label if str(m) in MODELS else str(m)
        cells = [
            f"{float(dmax.sel(model=m, xi=x)):.3f} (ε={float(where.sel(model=m, xi=x)):.2f})" for x in xis
        ]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _dev(ds, model, xi, eps_sel=None):
    d = np.abs(ds.eps_post.sel(model=model, xi=xi) - ds.eps_pre)
    if eps_sel is not None:
        d = d.where(eps_sel(ds.eps_pre), drop=True)
    return float(d.max())


def fig9_statements(ds, *, new=Fig9Settings.new_model, reference=Fig9Settings.reference):
    """The paper's conclusions about Fig. 9, each checked on ``ds`` (needs ``reference`` in ds.model).

    Returns a list of ``statements.Statement``: "holds" when the criterion is met for every
    model and panel it names, "partly" for some, "does not hold" for none, "not checked" when
    the panels or models it names are not in ``ds``.
    """
    out = []
    classical = [m for m in CLASSICAL if m in ds.model.values]
    small = [x for x in (0.0, 0.016) if x in ds.xi.values]
    large = [x for x in ds.xi.values if x >= 0.2]
    big = [x for x in (0.665, 0.91) if x in ds.xi.values]
    low = lambda e: e <= LOW_EPS  # noqa: E731
    high = lambda e: e >= HIGH_EPS  # noqa: E731
    no_classical = "no classical model" if not classical else ""

    def check(claim, criterion, missing, judge):
        """``judge()`` -> (evidence, verdict) when nothing the claim needs is ``missing``."""
        missing = "; ".join(m for m in missing if m)
        if missing:
            out.append(not_checked(claim, criterion, missing))
        else:
            out.append(Statement(claim, criterion, *judge()))

    def low_eps():
        ev = {(m, x): _dev(ds, m, x, low) for m in classical for x in small}
        text = "; ".join(f"{MODELS[m].label} ξ={x:g}: {v:.3f}" for (m, x), v in ev.items())
        return text, verdict(v > OBVIOUS for v in ev.values())

    check(
        "Fig. 9(a, b): classical models misdescribe dissipation at low restitution.",
        f"every classical model has max |post − pre| > {OBVIOUS} over ε ≤ {LOW_EPS} at ξ = 0 and 0.016",
        [no_classical, "" if small else "no panel at ξ = 0 or 0.016"],
        low_eps,
    )

    def new_better():
        ev_new = {x: _dev(ds, new, x) for x in small}
        ev_best = {x: min(_dev(ds, m, x) for m in classical) for x in small}
        text = "; ".join(f"ξ={x:g}: new {ev_new[x]:.3f}, best classical {ev_best[x]:.3f}" for x in small)
        return text, verdict(ev_new[x] < ev_best[x] for x in small)

    check(
        "For ξ small or zero the new model does better over the whole range of ε.",
        "new model's max |post − pre| over all ε is below every classical model's, at ξ = 0 and 0.016",
        [
            "" if new in ds.model.values else f"model {new}",
            no_classical,
            "" if small else "no panel at ξ = 0 or 0.016",
        ],
        new_better,
    )

    def large_load():
        ev_s = {m: max(_dev(ds, m, x) for x in small) for m in classical}
        ev_l = {m: max(_dev(ds, m, x) for x in large) for m in classical}
        text = "; ".join(f"{MODELS[m].label}: {ev_s[m]:.3f} → {ev_l[m]:.3f}" for m in classical)
        return text, verdict(ev_l[m] > ev_s[m] and ev_l[m] > OBVIOUS for m in classical)

    check(
        "Fig. 9(c–f): the errors are great when the influence factor is large.",
        f"each classical model's max |post − pre| over ξ ≥ 0.2 exceeds its max over ξ ≤ 0.016, "
        f"and exceeds {OBVIOUS}",
        [no_classical, "" if small else "no panel at ξ = 0 or 0.016", "" if large else "no panel at ξ ≥ 0.2"],
        large_load,
    )

    def fixed_alpha():
        same = {
            m: not MODELS[m].uses_xi
            and bool(np.allclose(ds.alpha.sel(model=m), ds.alpha.sel(model=m).isel(xi=0)))
            for m in classical
        }
        fixed = all(same.values())
        return ("α(ε) identical in every panel" if fixed else "α varies with ξ"), verdict(same.values())

    check(
        "Classical models keep α fixed when ε is fixed and ξ varies.",
        "α of each classical model is identical across the panels",
        [no_classical, "" if ds.sizes["xi"] > 1 else "one panel only"],
        fixed_alpha,
    )

    def high_eps():
        ev_h = {(m, x): _dev(ds, m, x, high) for m in classical for x in big}
        text = "; ".join(f"{MODELS[m].label} ξ={x:g}: {v:.3f}" for (m, x), v in ev_h.items())
        return text, verdict(v > OBVIOUS for v in ev_h.values())

    check(
        "Fig. 9(e, f): fixed α misdescribes dissipation even for ε close to 1.",
        f"every classical model has max |post − pre| > {OBVIOUS} over ε ≥ {HIGH_EPS} at ξ = 0.665 and 0.91",
        [no_classical, "" if big else "no panel at ξ = 0.665 or 0.91"],
        high_eps,
    )

    def wrong_state():
        ref_state = ds.state.sel(model=reference)
        wrong = {m: int((ds.state.sel(model=m) != ref_state).sum()) for m in classical}
        total = int(ref_state.size)
        text = "; ".join(f"{MODELS[m].label}: {wrong[m]} of {total}" for m in classical)
        return text, verdict([any(v > 0 for v in wrong.values())])

    check(
        "The incorrect dissipation may cause a wrong impact end state.",
        "some classical model ends in another state than the exact α does at the same (ε, ξ)",
        ["" if reference in ds.model.values else f"reference model {reference}", no_classical],
        wrong_state,
    )
    return out


def nonseparation_mask(ds):
    """True where the impact ended without separating: non-separation, creep or no restitution."""
    return ds.state >= NONSEPARATION
