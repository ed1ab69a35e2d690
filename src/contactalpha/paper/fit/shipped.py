"""Whether the shipped refit constants (model ``shen_refit``) are the refit of this surface.

A run writes only under ``results/``: the constants shipped in
``contactalpha/data/shen_refit.json`` change only by ``snakemake -c2 ship``.  The
same surface refit on another CPU lands within a tiny fraction of a standard
error of them (floating-point sums in another order), not on the same bits;
``shipped_agreement`` says by how much, in standard errors of the fresh refit.
Only numpy here: the check runs in a job of its own and starts fast.
"""

import numpy as np

# Largest |fresh - shipped| accepted, in standard errors of the fresh refit.  Another CPU
# moves the constants by up to ~4e-6 relative, ~1e-4 SE; a change of 1 % of a constant's
# uncertainty (an edit of the engine or of the fit) is a new refit, to ship.
SHIPPED_TOL_SE = 0.01
# What makes two refits comparable: the same grid and tolerances of the surface, the same
# reading and residuals.  (Not the solver's wording or the commit: those change with the code.)
SURFACE_KEYS = ("n_epsilon", "n_xi", "tol", "rtol", "atol")
FIT_KEYS = ("weights", "loss")


def _fresh_constants(report):
    """(name, fresh value, standard error) of every refit constant in a ``refit_report``."""
    rows = [(k, v["refit"], v["se"]) for k, v in report["eq40"]["constants"].items()]
    z = report["zero_load"]["constants"]["zero_load_exp"]
    return [*rows, ("zero_load_exp", z["refit"], z["se"])]


def _shipped_value(shipped, name):
    return shipped["zero_load_exp"] if name == "zero_load_exp" else shipped["constants"][name]


def comparable(report, shipped):
    """Differences between the fresh refit's surface and fit settings and the shipped one's (a list)."""
    out = [
        f"surface {k}: {report['surface'].get(k)} here, {shipped['surface'].get(k)} shipped"
        for k in SURFACE_KEYS
        if report["surface"].get(k) != shipped["surface"].get(k)
    ]
    out += [
        f"fit {k}: {report['settings'][k]} here, {shipped['fit'].get(k)} shipped"
        for k in FIT_KEYS
        if report["settings"][k] != shipped["fit"].get(k)
    ]
    if report["reading"]["used"] != shipped["reading"]:
        out.append(f"reading: {report['reading']['used']} here, {shipped['reading']} shipped")
    return out


def shipped_agreement(report, shipped, tol_se=SHIPPED_TOL_SE):
    """Each refit constant against the shipped one, in standard errors of the fresh refit.

    Parameters
    ----------
    report : dict
        ``refit_report``'s report (``results/fit/coefficients.json``).
    shipped : dict
        The shipped constants (``contactalpha/data/shen_refit.json``).
    tol_se : float
        Largest accepted ``|fresh - shipped| / SE``.

    Returns
    -------
    dict
        ``comparable`` (False when the shipped constants fit another surface or another
        reading: ``differences`` says which), ``rows`` (name, fresh, shipped, SE,
        ``in_se``), ``max_in_se``, ``identical`` (every constant the same bits),
        ``tol_se`` and ``stale`` (comparable, and some ``in_se`` beyond ``tol_se``; a
        constant without a standard error counts as infinitely far unless identical).
    """
    if not tol_se > 0:
        raise ValueError(f"tol_se = {tol_se!r} is outside the valid range (0, inf)")
    differences = comparable(report, shipped)
    rows = []
    for name, fresh, se in _fresh_constants(report):
        ship = float(_shipped_value(shipped, name))
        diff = abs(float(fresh) - ship)
        determined = se is not None and np.isfinite(se) and se > 0
        in_se = diff / se if determined else (0.0 if diff == 0 else np.inf)
        rows.append({"name": name, "fresh": float(fresh), "shipped": ship, "se": se, "in_se": float(in_se)})
    max_in_se = max(r["in_se"] for r in rows)
    return {
        "comparable": not differences,
        "differences": differences,
        "rows": rows,
        "max_in_se": max_in_se,
        "identical": all(r["fresh"] == r["shipped"] for r in rows),
        "tol_se": tol_se,
        "stale": bool(not differences and max_in_se > tol_se),
    }


def agreement_markdown(result):
    """The agreement as markdown: a verdict line and one row per constant."""
    if not result["comparable"]:
        head = (
            "The shipped constants are a refit of another surface or reading "
            f"({'; '.join(result['differences'])}): not compared."
        )
    elif result["identical"]:
        head = "The shipped constants are this refit, bit for bit."
    else:
        verdict = "OUTSIDE" if result["stale"] else "within"
        head = (
            f"The shipped constants differ from this refit by at most {result['max_in_se']:.2g} standard "
            f"errors, {verdict} the tolerance of {result['tol_se']:g} SE."
        )
        if result["stale"]:
            head += " They are stale: `snakemake -c2 ship` ships this refit."
    rows = ["| constant | this refit | shipped | SE | difference / SE |", "|---|---|---|---|---|"]
    rows += [
        f"| `{r['name']}` | {r['fresh']:.17g} | {r['shipped']:.17g} | {r['se']:.3g} | {r['in_se']:.3g} |"
        if r["se"] is not None
        else f"| `{r['name']}` | {r['fresh']:.17g} | {r['shipped']:.17g} | – | {r['in_se']:.3g} |"
        for r in result["rows"]
    ]
    return (
        "# Shipped refit constants (model shen_refit) against this refit\n\n"
        + head
        + "\n\n"
        + "\n".join(rows)
        + "\n"
    )
