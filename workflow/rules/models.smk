# Stage "models": the exact-alpha table the package ships (checked against the solver), and
# Fig. 9 (post- versus pre-restitution).
#
# The default run never writes the package's files (issue 15, item 6). It checks the shipped
# table when it was built with the settings of `models.table`; with other settings it builds a
# table under results/models/ and checks that one. `snakemake -c2 ship` (rules/ship.smk)
# builds, checks and copies a table into the package.

import json

import numpy as np

from contactalpha.engine.table import DEFAULT_FILE as SHIPPED_TABLE
from contactalpha.provenance import source_hash

BUILT_TABLE = "results/models/alpha_table.npz"
# Hash of the package sources the table build and its check run: editing the engine reruns them.
TABLE_CODE_VERSION = source_hash("contactalpha.engine.table_build")


def table_built_with(path, settings):
    """Whether the table file at ``path`` was built with ``settings`` (a ``models.table`` section).

    Its metadata records the grid and tolerances; ``refine_n`` through the size of region N,
    ``refine_n (n_p - 1) + 1`` columns (``table_build.build_table``), where an older file does
    not record it.
    """
    try:
        with np.load(path) as z:
            meta = json.loads(str(z["meta"]))
    except (OSError, KeyError, ValueError):
        return False
    recorded = {k: meta.get(k) for k in ("n_eta", "n_p", "tol", "rtol", "atol")}
    recorded["refine_n"] = meta.get("refine_n", (meta.get("n_p_region_n", 0) - 1) / max(meta.get("n_p", 2) - 1, 1))
    return all(recorded[k] == settings[k] for k in settings)


# The table the run checks: the shipped one where it is what the config asks for.
TABLE_IN_USE = (
    str(SHIPPED_TABLE) if table_built_with(SHIPPED_TABLE, config["models"]["table"]) else BUILT_TABLE
)

ALL_TARGETS += [
    "results/models/table_check.md",
    "results/models/fig9.h5",
    "results/models/fig9_max_deviation.md",
    "results/models/fig9_statements.md",
    *expand("results/figures/fig9_post_vs_pre.{ext}", ext=["png", "pdf"]),
]


rule table:
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
        TABLE_IN_USE,
    output:
        "results/models/table_check.md",
    params:
        check=config["models"]["check"],
        code_version=TABLE_CODE_VERSION,
    log:
        "logs/models/table_check.log",
    threads: 2
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_table_check.py"


# The check of a freshly built table, before `ship` copies it into the package.
use rule table_check as table_check_built with:
    input:
        BUILT_TABLE,
    output:
        "results/models/alpha_table_check.md",
    log:
        "logs/models/alpha_table_check.log",


# Data, table, statements and figure in one job: one Python start-up instead of two.
rule fig9:
    input:
        # Model shen_refit reads the shipped constants: shipping new ones reruns Fig. 9.
        SHIPPED_REFIT,
    output:
        data="results/models/fig9.h5",
        table="results/models/fig9_max_deviation.md",
        statements="results/models/fig9_statements.md",
        png="results/figures/fig9_post_vs_pre.png",
        pdf="results/figures/fig9_post_vs_pre.pdf",
    params:
        fig9=config["models"]["fig9"],
    log:
        "logs/models/fig9.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/models_fig9.py"
