# Stage "models": the exact-alpha table shipped with the package (built here, checked against
# the shipped copy and against the solver), and Fig. 9 (post- versus pre-restitution).

from contactalpha.provenance import source_hash

ALL_TARGETS += [
    "results/models/alpha_table.npz",
    "results/models/table_check.md",
    "results/models/fig9.h5",
    "results/models/fig9_max_deviation.md",
    "results/models/fig9_statements.md",
    *expand("results/figures/fig9_post_vs_pre.{ext}", ext=["png", "pdf"]),
]


localrules:
    fig9_figure,


rule table:
    output:
        "results/models/alpha_table.npz",
    params:
        table=config["models"]["table"],
        # Hash of the package sources the build runs: editing the engine rebuilds the table.
        code_version=source_hash("contactalpha.engine.table_build"),
    log:
        "logs/models/table.log",
    threads: 2
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_table.py"


rule table_check:
    input:
        "results/models/alpha_table.npz",
    output:
        "results/models/table_check.md",
    params:
        check=config["models"]["check"],
    log:
        "logs/models/table_check.log",
    threads: 2
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_table_check.py"


rule fig9:
    input:
        # shen_refit reads the constants the fit stage ships: wait for them.
        [config["fit"]["package_coefficients"]] if "fit" in config else [],
    output:
        data="results/models/fig9.h5",
        table="results/models/fig9_max_deviation.md",
        statements="results/models/fig9_statements.md",
    params:
        fig9=config["models"]["fig9"],
    log:
        "logs/models/fig9.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_fig9.py"


rule fig9_figure:
    input:
        "results/models/fig9.h5",
    output:
        png="results/figures/fig9_post_vs_pre.png",
        pdf="results/figures/fig9_post_vs_pre.pdf",
    log:
        "logs/models/fig9_figure.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_fig9_figure.py"
