# Stage "closedform" (issue 13): the closed form alpha(eps, xi) (model closed_form) judged in the
# restitution it delivers, beside Eq. 40 as published and as refit, on the points of
# results/surface.h5: results/closedform/comparison.json and a Fig. 8-style error map.
# The default run judges the SHIPPED constants (no refit). `snakemake -c2 closedform_refit`
# refits them to this run's surface (results/closedform/constants.json); copying that file into
# the package (closedform.package_constants) is the maintainer's `snakemake -c2 closedform_ship`.

import hashlib

from contactalpha.models.closed_form import CONSTANTS_FILE as CLOSED_FORM_FILE
from contactalpha.models.shen import REFIT_FILE as SHEN_REFIT_FILE
from contactalpha.provenance import PACKAGE_DIR

# The shipped constants the judged models read, by content digest (as rules/fit.smk does for the
# refit): shipping new ones reruns the comparison; a clone elsewhere plans nothing new.
CLOSED_FORM_SHIPPED = [
    hashlib.sha256((PACKAGE_DIR / "data" / f).read_bytes()).hexdigest()
    for f in (CLOSED_FORM_FILE, SHEN_REFIT_FILE)
]

ALL_TARGETS += [
    "results/closedform/comparison.json",
    *expand("results/figures/closedform_error_map.{ext}", ext=["png", "pdf"]),
]


rule closedform_compare:
    input:
        surface="results/surface.h5",
        warmup=WARMUP,
    output:
        comparison="results/closedform/comparison.json",
        figure=multiext("results/figures/closedform_error_map", ".png", ".pdf"),
    params:
        shipped=CLOSED_FORM_SHIPPED,
        models=config["closedform"]["models"],
    log:
        "logs/closedform/compare.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/closedform_compare.py"


rule closedform_refit:
    input:
        "results/surface.h5",
        warmup=WARMUP,
    output:
        "results/closedform/constants.json",
    params:
        refit=config["closedform"]["refit"],
    log:
        "logs/closedform/refit.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/closedform_refit.py"


# The maintainer's step (not in ALL_TARGETS): copy the refit over the package's constants,
# with the shared ship script (rules/ship.smk); commit the package file afterwards.
rule closedform_ship:
    input:
        source="results/closedform/constants.json",
    output:
        "results/ship/closed_form.json",
    params:
        destination=config["closedform"]["package_constants"],
    log:
        "logs/ship/closed_form.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ship.py"
