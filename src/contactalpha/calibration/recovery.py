"""Recovery study: noisy drop tests made by the package's own bounce prediction, fitted back.

For each scene (eps, stiffness, mass, first approach speed) the exact touchdown times come from
``scene.bounces.predict_bounces`` (model "exact", case A: the ``hc_eps`` law); each replicate
adds independent Gaussian jitter to every time and fits ``hc_eps`` with profile-likelihood
intervals.  Coverage counts the replicates whose interval holds the truth; bias is the mean
estimate minus the truth, compared with the mean interval width (stiffness in log10).
"""

from dataclasses import dataclass

import numpy as np

from contactalpha.scene.ball import GRAVITY, Scene
from contactalpha.scene.bounces import predict_bounces

from .data import from_arrays
from .fit import Setup, fit_hypothesis
from .hypotheses import HYPOTHESES
from .sequence import simulate


@dataclass(frozen=True)
class RecoveryScene:
    """A scene of the study: eps, stiffness (N/m^1.5), mass (kg), first approach speed (m/s)."""

    eps: float
    stiffness: float
    mass: float
    speed: float


SCENES = (
    RecoveryScene(0.8, 1e8, 0.05, 2.0),
    RecoveryScene(0.6, 1e9, 0.2, 3.0),
    RecoveryScene(0.9, 1e7, 0.01, 1.5),
)
# Impacts per sequence: a 20-bounce recording (fewer if the ball rests first).
IMPACTS = 21
JITTER = 1e-4


def prediction(scene):
    """``predict_bounces`` of ``scene`` (exact alpha; solved where the table's xi <= 0.99 ends)."""
    s = Scene(
        mass=scene.mass, stiffness=scene.stiffness, approach_speed=scene.speed, force=0.0, eps=scene.eps
    )
    try:
        return predict_bounces(s, "exact")
    except ValueError:  # a last contact beyond the alpha table's xi <= 0.99: solve alpha there
        return predict_bounces(s, "exact_solve")


def exact_times(scene, impacts=IMPACTS):
    """Touchdown times (s) of the first ``impacts`` contacts predicted for ``scene``, from 0."""
    p = prediction(scene)
    gaps = p.contact_durations[:-1] + p.flight_durations
    t = np.concatenate([[0.0], np.cumsum(gaps)])
    return t[: min(impacts, t.size)]


def replicate(scene, rng, jitter=JITTER, impacts=IMPACTS, times=None):
    """One noisy replicate fitted with ``hc_eps``: the ``LawFit`` (``times``: the exact ones, if known)."""
    t = exact_times(scene, impacts) if times is None else times
    noisy = t + rng.normal(0.0, jitter, t.size)
    return fit_hypothesis(
        HYPOTHESES["hc_eps"], from_arrays("times", values=noisy), Setup(scene.mass, GRAVITY)
    )


def study(scene, replicates=100, seed=0, jitter=JITTER, impacts=IMPACTS):
    """Coverage and bias of ``replicates`` fits of ``scene``; a dict of plain numbers."""
    rng = np.random.default_rng(seed)
    truth = {"eps": scene.eps, "stiffness": np.log10(scene.stiffness)}
    est: dict[str, list[float]] = {k: [] for k in truth}
    lo: dict[str, list[float]] = {k: [] for k in truth}
    hi: dict[str, list[float]] = {k: [] for k in truth}
    times = exact_times(scene, impacts)
    for _ in range(replicates):
        f = replicate(scene, rng, jitter, impacts, times)
        for k in truth:
            a, b = f.intervals[k]
            v = f.values[k]
            if k == "stiffness":
                a, b, v = np.log10(a), np.log10(b), np.log10(v)
            est[k].append(v)
            lo[k].append(a)
            hi[k].append(b)
    out = {
        "scene": scene.__dict__,
        "replicates": replicates,
        "jitter": jitter,
        "impacts": len(exact_times(scene, impacts)),
    }
    for k, true in truth.items():
        e, a, b = np.array(est[k]), np.array(lo[k]), np.array(hi[k])
        width = float(np.mean(b - a))
        bias = float(np.mean(e) - true)
        out[k] = {
            "truth": true,
            "covered": int(np.sum((a <= true) & (true <= b))),
            "bias": bias,
            "mean_width": width,
            "bias_over_width": abs(bias) / width,
        }
    return out


def selection_study(scene, replicates=50, seed=0, jitter=JITTER, impacts=IMPACTS):
    """How often AIC picks the law that made the data, ``hc_eps`` against ``constant_e``.

    Each replicate makes two noisy sequences of the scene: one by the package's prediction
    (``hc_eps``, gravity in the contact) and one by ``constant_e`` with ``e = eps``; both laws
    are fitted to each (no intervals).  Returns the counts of right picks and the median AIC gaps.
    """
    rng = np.random.default_rng(seed)
    truth_hc = exact_times(scene, impacts)
    null = simulate(
        HYPOTHESES["constant_e"],
        {"e": scene.eps, "stiffness": scene.stiffness},
        scene.mass,
        GRAVITY,
        scene.speed,
        0.0,
        truth_hc.size,
    )
    setup = Setup(scene.mass, GRAVITY)
    right = {"hc_eps": 0, "constant_e": 0}
    gaps: dict[str, list[float]] = {"hc_eps": [], "constant_e": []}
    for _ in range(replicates):
        for made, t in (("hc_eps", truth_hc), ("constant_e", null.touchdowns)):
            data = from_arrays("times", values=t + rng.normal(0.0, jitter, t.size))
            aic = {n: fit_hypothesis(HYPOTHESES[n], data, setup, intervals=False).aic for n in right}
            other = "constant_e" if made == "hc_eps" else "hc_eps"
            right[made] += int(aic[made] < aic[other])
            gaps[made].append(aic[other] - aic[made])
    return {
        "scene": scene.__dict__,
        "replicates": replicates,
        "right": right,
        "median_aic_gap": {k: float(np.median(v)) for k, v in gaps.items()},
    }


def heights_study(scene, replicates=100, seed=0, noise=0.01, apexes=11):
    """Coverage of ``eps`` from the drop height and ``apexes`` rebound apexes with relative ``noise``.

    The exact apexes come from the package's prediction (``predict_bounces``); each replicate
    multiplies every height by ``exp(N(0, noise))`` and fits ``hc_eps``.  Heights see the
    stiffness only through the load factor, so only eps is scored.
    """
    p = prediction(scene)
    accel = p.scene.accel
    h = np.concatenate([[scene.speed**2 / (2.0 * accel)], p.rebound_speeds[:apexes] ** 2 / (2.0 * accel)])
    h = h[h > 0.0]
    rng = np.random.default_rng(seed)
    est, covered, widths = [], 0, []
    for _ in range(replicates):
        noisy = h * np.exp(rng.normal(0.0, noise, h.size))
        f = fit_hypothesis(
            HYPOTHESES["hc_eps"], from_arrays("heights", values=noisy), Setup(scene.mass, accel)
        )
        lo, hi = f.intervals["eps"]
        covered += int(lo <= scene.eps <= hi)
        est.append(f.values["eps"])
        widths.append(hi - lo)
    bias = float(np.mean(est) - scene.eps)
    width = float(np.mean(widths))
    return {
        "scene": scene.__dict__,
        "replicates": replicates,
        "noise": noise,
        "heights": int(h.size),
        "eps": {"covered": covered, "bias": bias, "mean_width": width, "bias_over_width": abs(bias) / width},
    }
