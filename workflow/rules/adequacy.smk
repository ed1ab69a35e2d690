# Stage "adequacy": which model a scene needs (issue 12). Where each registered model is adequate
# over the surface's (eps, xi) grid at each tol (results/adequacy/maps.h5, one figure per tol and
# the cheapest adequate model), xi_ignore(eps; tol) and the paper's "small xi" claim judged
# (results/adequacy/statements.md, summary.md), and the physical bounce threshold of typical
# scenes next to PhysX's 2 m/s default (results/adequacy/thresholds.md and the v_crit figure).

from contactalpha.provenance import source_hash

ADEQUACY = config["adequacy"]
ADEQUACY_TOLS = [f"{t:g}" for t in ADEQUACY["tols"]]
ADEQUACY_FIGURES = [
    *[f"adequacy_tol{t}" for t in ADEQUACY_TOLS],
    "adequacy_cheapest",
    "adequacy_xi_ignore",
    "critical_speed",
]

ALL_TARGETS += [
    "results/adequacy/maps.h5",
    "results/adequacy/statements.md",
    "results/adequacy/summary.md",
    "results/adequacy/thresholds.md",
    *expand("results/figures/{name}.{ext}", name=ADEQUACY_FIGURES, ext=["png", "pdf"]),
]


# Light jobs: on a cluster they run on the submitting node; only the maps are submitted.
localrules:
    adequacy_thresholds,
    adequacy_report,
    adequacy_figures,


rule adequacy_maps:
    input:
        surface="results/surface.h5",
        warmup=WARMUP,
    output:
        "results/adequacy/maps.h5",
    params:
        # Model shen_refit reads the shipped refit constants (rules/fit.smk): shipping new ones
        # reruns the maps; a digest, not a path, so a clone elsewhere plans nothing new.
        shipped_refit=SHIPPED_REFIT_DIGEST,
        tols=ADEQUACY["tols"],
        stride=ADEQUACY["stride"],
        code_version=source_hash("contactalpha.studies.adequacy.maps"),
    priority: LONG_JOBS
    log:
        "logs/adequacy/maps.log",
    # One pass over every model x point impact, its rows on `threads` threads (the same bits for
    # any number).  One by default: a 2-thread job waits until both cores of a `snakemake -c2`
    # run are free at once, and then the maps and their figures ended the run on one core.
    # More: --set-threads adequacy_maps=N.
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/adequacy_maps.py"


rule adequacy_thresholds:
    input:
        warmup=WARMUP_PART["models"],
    output:
        data="results/adequacy/thresholds.nc",
        table="results/adequacy/thresholds.md",
    params:
        scenes=ADEQUACY["scenes"],
        vcrit_eps=ADEQUACY["vcrit_eps"],
        code_version=source_hash("contactalpha.studies.adequacy.report"),
    priority: LONG_JOBS
    log:
        "logs/adequacy/thresholds.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/adequacy_thresholds.py"


rule adequacy_report:
    input:
        "results/adequacy/maps.h5",
    output:
        statements="results/adequacy/statements.md",
        summary="results/adequacy/summary.md",
    params:
        report_eps=ADEQUACY["report_eps"],
    log:
        "logs/adequacy/report.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/adequacy_report.py"


rule adequacy_figures:
    input:
        maps="results/adequacy/maps.h5",
        thresholds="results/adequacy/thresholds.nc",
    output:
        expand("results/figures/{name}.{ext}", name=ADEQUACY_FIGURES, ext=["png", "pdf"]),
    priority: LONG_JOBS
    log:
        "logs/adequacy/figures.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/adequacy_figures.py"
