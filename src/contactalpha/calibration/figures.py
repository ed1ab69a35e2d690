"""Figures of a calibration: e_N against impact speed with each law's curve, and the residuals.

Matplotlib is imported here only, when a figure is asked for.
"""

import numpy as np

from .hypotheses import HYPOTHESES

# Speeds on each law's curve.
CURVE_POINTS = 120


def law_curve(fit, setup, speeds):
    """e_N of the fitted law at each approach speed (NaN where a contact fails)."""
    law = HYPOTHESES[fit.law]
    out = np.full(len(speeds), np.nan)
    for i, v in enumerate(speeds):
        c = law.contact(fit.values, setup.mass, setup.accel, float(v))
        if c.status == "ok":
            out[i] = c.v_out / v
    return out


def observed_restitution(data, accel, durations=None):
    """e_N per bounce from the data: ``(approach speeds, e_N)``.

    Times: the ratio of successive flights at approach speed ``a T / 2``, a flight being an
    interval less the contact duration that opens it (``durations``, s, one per impact: the
    selected fit's; rigid contacts if None).  Heights: the square root of successive apex ratios
    at ``sqrt(2 a h)``.  Trajectories: none (the fitted curves only).
    """
    if data.kind == "times":
        dt = np.diff(data.values)
        if durations is not None:
            d = np.asarray(durations, dtype=float)[: dt.size]
            dt = dt - np.concatenate([d, np.zeros(dt.size - d.size)])
        return 0.5 * accel * dt[:-1], dt[1:] / dt[:-1]
    if data.kind == "heights":
        h = data.values
        return np.sqrt(2.0 * accel * h[:-1]), np.sqrt(h[1:] / h[:-1])
    return np.empty(0), np.empty(0)


def draw(cal, prefix):
    """Write ``PREFIX_restitution.png`` and ``PREFIX_residuals.png``; return the two paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = [f"{prefix}_restitution.png", f"{prefix}_residuals.png"]
    fig, ax = plt.subplots(figsize=(6, 4))
    durations = cal.best.sequence.durations
    v_obs, e_obs = observed_restitution(cal.data, cal.setup.accel, durations)
    if v_obs.size:
        what = "flight ratios, selected law's contact times removed" if cal.data.kind == "times" else "apexes"
        ax.plot(v_obs, e_obs, "ko", ms=4, label=f"data ({what})")
    for name, fit in cal.fits.items():
        s = fit.sequence
        top = float(s.v_in.max()) * 1.05
        speeds = np.geomspace(max(float(s.v_in.min()) * 0.8, 1e-4), top, CURVE_POINTS)
        style = "-" if name == cal.selected else "--"
        ax.plot(speeds, law_curve(fit, cal.setup, speeds), style, label=f"{HYPOTHESES[name].label}")
        sep = s.v_out > 0
        ax.plot(s.v_in[sep], s.e_n[sep], ".", ms=3, color=ax.lines[-1].get_color())
    ax.set_xscale("log")
    ax.set_xlabel("approach speed v⁻ (m/s)")
    ax.set_ylabel("e_N")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(paths[0], dpi=150)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for name, fit in cal.fits.items():
        ax.plot(np.arange(1, fit.residuals.size + 1), fit.residuals, "o-", ms=3, label=name)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("observation")
    unit = {"times": "s", "heights": "log", "trajectory": "m"}[cal.data.kind]
    ax.set_ylabel(f"observed − fitted ({unit})")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(paths[1], dpi=150)
    plt.close(fig)
    return paths
