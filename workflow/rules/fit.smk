# Stage "fit": Shen et al.'s closed form refit to results/surface.h5 (issue 4): the comparison
# with the published constants (results/fit/), the check that the shipped constants (model
# shen_refit) are this refit, and Figs. 6-8 with lambda and the dissipation ratios.
# The refit constants are written to results/fit/shen_refit.json only: `snakemake -c2 ship`
# (rules/ship.smk) copies them into the package.

import hashlib

from contactalpha.models.shen import REFIT_FILE
from contactalpha.paper.fit.shipped import SHIPPED_TOL_SE
from contactalpha.provenance import PACKAGE_DIR

# The refit constants that model shen_refit reads (contactalpha/data/): the shipped ones. Rules
# whose results use that model have their digest as a parameter, so that shipping reruns them
# (by content, not path: a clone elsewhere has the same results); no rule of the default run
# writes the file.
SHIPPED_REFIT_DIGEST = hashlib.sha256((PACKAGE_DIR / "data" / REFIT_FILE).read_bytes()).hexdigest()

# Figures from the surface alone (drawn while the refit runs), and from the refit.
FIT_SURFACE_FIGURES = {"fig7": "fig7_sa_s1", "eta": "fit_eta"}
FIT_REFIT_FIGURES = {"fig6": "fig6_s1_s21", "fig8": "fig8_fit_errors", "lambda": "fit_lambda"}

ALL_TARGETS += [
    "results/fit/coefficients.json",
    "results/fit/comparison.md",
    "results/fit/eq40_readings.md",
    "results/fit/shen_refit.json",
    "results/fit/shipped_check.md",
    *expand(
        "results/figures/{name}.{ext}",
        name=[*FIT_SURFACE_FIGURES.values(), *FIT_REFIT_FIGURES.values()],
        ext=["png", "pdf"],
    ),
]


localrules:
    fit_shipped_check,


rule fit_refit:
    input:
        "results/surface.h5",
        warmup=WARMUP,
    output:
        coefficients="results/fit/coefficients.json",
        comparison="results/fit/comparison.md",
        readings="results/fit/eq40_readings.md",
        package="results/fit/shen_refit.json",
    params:
        readings=config["fit"]["readings"],
        weights=config["fit"]["weights"],
        loss=config["fit"]["loss"],
        verdict_k=config["fit"]["verdict_k"],
        eq26=config["fit"]["eq26"],
        restitution=config["fit"]["restitution"],
    # Worker processes for the fits after the main refit (each fit single-threaded, the same bits
    # for any number): about 10 s wall with 2 instead of 18 s with 1. One by default: in a
    # `snakemake -c2` run a 2-thread job waits until both cores are free at once, which happened
    # only when the queue drained (measured: the refit started 60 s after the surface was ready).
    # With more cores: `--set-threads fit_refit=2`.
    threads: 1
    # On the critical path (surface, refit, Figs. 6-8): scheduled before the other ready jobs.
    priority: CRITICAL_PATH
    log:
        "logs/fit/refit.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_refit.py"


rule fit_shipped_check:
    input:
        report="results/fit/coefficients.json",
    output:
        "results/fit/shipped_check.md",
    params:
        tol_se=SHIPPED_TOL_SE,
        shipped_refit=SHIPPED_REFIT_DIGEST,
    log:
        "logs/fit/shipped_check.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_shipped_check.py"


# Several figures per job: one Python start-up and one set of imports for all of them.
rule fit_surface_figures:
    input:
        surface="results/surface.h5",
    output:
        **{key: multiext(f"results/figures/{name}", ".png", ".pdf") for key, name in FIT_SURFACE_FIGURES.items()},
    log:
        "logs/fit/surface_figures.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_figures.py"


rule fit_figures:
    input:
        surface="results/surface.h5",
        coefficients="results/fit/coefficients.json",
    output:
        **{key: multiext(f"results/figures/{name}", ".png", ".pdf") for key, name in FIT_REFIT_FIGURES.items()},
    params:
        restitution=config["fit"]["restitution"],
    priority: CRITICAL_PATH
    log:
        "logs/fit/figures.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_figures.py"
