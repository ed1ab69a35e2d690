# Stage "models": the exact-alpha table the package ships (checked against the solver), and
# Fig. 9 (post- versus pre-restitution).
#
# The default run never writes the package's files (issue 15, item 6). It checks the shipped
# table when it was built with the settings of `models.table`; with other settings it builds a
# table under results/models/ and checks that one. `snakemake -c2 ship` (rules/ship.smk)
# builds, checks and copies a table into the package.

import hashlib

from contactalpha.engine.table import DEFAULT_FILE as SHIPPED_TABLE
from contactalpha.engine.table_build import built_with
from contactalpha.provenance import source_hash

BUILT_TABLE = "results/models/alpha_table.npz"
# Hash of the package sources the table build and its check run: editing the engine reruns them.
TABLE_CODE_VERSION = source_hash("contactalpha.engine.table_build")
TABLE_SETTINGS = config["models"]["table"]
# The settings as the table's metadata records them: refine_n as the column count of region N,
# refine_n (n_p - 1) + 1 (table_build.build_table).
TABLE_META = {
    **{k: v for k, v in TABLE_SETTINGS.items() if k != "refine_n"},
    "n_p_region_n": TABLE_SETTINGS["refine_n"] * (TABLE_SETTINGS["n_p"] - 1) + 1,
}
# The run checks the shipped table where it is what the config asks for. The shipped file is
# known by its content, not its path: a clone elsewhere has the same results.
CHECK_SHIPPED_TABLE = built_with(SHIPPED_TABLE, TABLE_META)
SHIPPED_TABLE_DIGEST = hashlib.sha256(SHIPPED_TABLE.read_bytes()).hexdigest() if CHECK_SHIPPED_TABLE else None

ALL_TARGETS += [
    "results/models/table_check.md",
    "results/models/fig9.h5",
    "results/models/fig9_max_deviation.md",
    "results/models/fig9_statements.md",
    *expand("results/figures/fig9_post_vs_pre.{ext}", ext=["png", "pdf"]),
]


rule table:
    input:
        warmup=WARMUP,
    output:
        BUILT_TABLE,
    params:
        table=config["models"]["table"],
        code_version=TABLE_CODE_VERSION,
    log:
        "logs/models/table.log",
    threads: 2
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_table.py"


rule table_check:
    input:
        # No table: the shipped one (the script finds it), rerun when its digest changes.
        **({} if CHECK_SHIPPED_TABLE else {"table": BUILT_TABLE}),
        warmup=WARMUP,
    output:
        "results/models/table_check.md",
    params:
        check=config["models"]["check"],
        code_version=TABLE_CODE_VERSION,
        shipped_table=SHIPPED_TABLE_DIGEST,
    log:
        "logs/models/table_check.log",
    # One thread: in a `snakemake -c2` run a 2-thread job waits until both cores are free at
    # once, which pushed this 1 s check to the end of the run.  More: --set-threads table_check=N.
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_table_check.py"


# The check of a freshly built table, before `ship` copies it into the package.
use rule table_check as table_check_built with:
    input:
        table=BUILT_TABLE,
        warmup=WARMUP,
    output:
        "results/models/alpha_table_check.md",
    params:
        check=config["models"]["check"],
        code_version=TABLE_CODE_VERSION,
        shipped_table=None,
    log:
        "logs/models/alpha_table_check.log",


# Data, table, statements and figure in one job: one Python start-up instead of two.
rule fig9:
    input:
        warmup=WARMUP,
    output:
        data="results/models/fig9.h5",
        table="results/models/fig9_max_deviation.md",
        statements="results/models/fig9_statements.md",
        png="results/figures/fig9_post_vs_pre.png",
        pdf="results/figures/fig9_post_vs_pre.pdf",
    params:
        fig9=config["models"]["fig9"],
        # Model shen_refit reads the shipped constants: shipping new ones reruns Fig. 9.
        shipped_refit=SHIPPED_REFIT_DIGEST,
    log:
        "logs/models/fig9.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_fig9.py"
