# Stage "ship" (issue 15, item 6): a maintainer's explicit command, NOT in ALL_TARGETS.
#   snakemake -c2 ship          # all; or ship_fit (refit constants), ship_table (the table),
#                               # closedform_ship (closed-form constants, rules/closedform.smk)
# A default run writes only under results/. Shipping copies the Eq. 40 refit of this run's
# surface (results/fit/shen_refit.json) and a freshly built, checked exact-alpha table
# (results/models/alpha_table.npz, results/models/alpha_table_check.md) over the package's
# files (config fit.package_coefficients, models.package_table); commit them afterwards.
# Records of what was copied go to results/ship/. The docs pages' generated blocks have their
# own targets (`bench`, `engines`).


rule ship:
    input:
        "results/ship/shen_refit.json",
        "results/ship/alpha_table.json",
        "results/ship/closed_form.json",


rule ship_fit:
    input:
        source="results/fit/shen_refit.json",
    output:
        "results/ship/shen_refit.json",
    params:
        destination=config["fit"]["package_coefficients"],
    log:
        "logs/ship/shen_refit.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ship.py"


rule ship_table:
    input:
        source=BUILT_TABLE,
        check="results/models/alpha_table_check.md",
    output:
        "results/ship/alpha_table.json",
    params:
        destination=config["models"]["package_table"],
    log:
        "logs/ship/alpha_table.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ship.py"
