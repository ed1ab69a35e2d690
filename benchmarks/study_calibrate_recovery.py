"""Recovery study of issue 28: 100 noisy replicates of >= 3 scenes, coverage and bias of hc_eps fits.

Run: PYTHONPATH=src nice -n 10 python benchmarks/study_calibrate_recovery.py [REPLICATES] [OUT.json]
Each replicate: the package's own bounce prediction (scene.bounces.predict_bounces), 0.1 ms
Gaussian jitter on every impact time, a profile-likelihood fit; then the selection study (AIC,
hc_eps against constant_e data) and the heights study (1 % noise on 12 heights, eps scored).
Done when each parameter's 95 % interval covers the truth in >= 90 of 100 replicates and
|bias| < a tenth of the mean width.
"""

import json
import sys
import time

from contactalpha.calibration.recovery import SCENES, heights_study, selection_study, study


def main():
    replicates = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    results = []
    for i, scene in enumerate(SCENES):
        start = time.perf_counter()
        r = study(scene, replicates=replicates, seed=i)
        r["seconds"] = time.perf_counter() - start
        results.append(r)
        for k in ("eps", "stiffness"):
            q = r[k]
            print(
                f"scene {i} {k:9s} covered {q['covered']:3d}/{replicates}  bias {q['bias']:+.3g}  "
                f"width {q['mean_width']:.3g}  bias/width {q['bias_over_width']:.3f}"
            )
        print(f"scene {i}: {r['impacts']} impacts, {r['seconds']:.1f} s")
    for i, scene in enumerate(SCENES):
        start = time.perf_counter()
        s = selection_study(scene, replicates=min(replicates, 50), seed=100 + i)
        s["seconds"] = time.perf_counter() - start
        results.append(s)
        print(
            f"scene {i} selection: hc_eps data -> hc_eps {s['right']['hc_eps']}/{s['replicates']}, "
            f"constant_e data -> constant_e {s['right']['constant_e']}/{s['replicates']}, "
            f"median AIC gaps {s['median_aic_gap']}, {s['seconds']:.1f} s"
        )
    for i, scene in enumerate(SCENES):
        h = heights_study(scene, replicates=replicates, seed=200 + i)
        results.append(h)
        q = h["eps"]
        print(
            f"scene {i} heights (1 % noise, {h['heights']} heights): "
            f"eps covered {q['covered']}/{replicates}  "
            f"bias/width {q['bias_over_width']:.3f}"
        )
    if len(sys.argv) > 2:
        with open(sys.argv[2], "w") as fh:
            json.dump(results, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
