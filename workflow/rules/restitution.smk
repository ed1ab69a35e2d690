# Stage "restitution" (issue 11, part 1): Newton's kinematic e_N beside Stronge's eps.
# The figure of e_N against eps for several xi, and the kinematic exact-alpha table, handled like
# the energetic one (rules/models.smk): the default run checks the shipped table when it was
# built with the settings of `restitution.table`, otherwise builds one under results/models/ and
# checks that; it never writes the package. `snakemake -c2 ship_kinematic_table` builds,
# checks and copies a table over config `restitution.package_table` (a maintainer's step).

from contactalpha.engine.table import KINEMATIC_FILE as SHIPPED_KINEMATIC_TABLE
from contactalpha.engine.table_build import built_with
from contactalpha.provenance import source_hash

RESTITUTION = config["restitution"]
BUILT_KINEMATIC_TABLE = "results/models/alpha_table_kinematic.npz"
# Hash of the package sources the table build and its check run: editing the engine reruns them.
KINEMATIC_CODE_VERSION = source_hash("contactalpha.engine.table_build")
# The table the run checks: the shipped one where it is what the config asks for.
KINEMATIC_TABLE_IN_USE = (
    str(SHIPPED_KINEMATIC_TABLE)
    if built_with(SHIPPED_KINEMATIC_TABLE, RESTITUTION["table"])
    else BUILT_KINEMATIC_TABLE
)

ALL_TARGETS += [
    "results/restitution/kinematic_table_check.md",
    "results/restitution/restitution_kinematic.nc",
    *expand("results/figures/restitution_kinematic.{ext}", ext=["png", "pdf"]),
]


# Data and figure in one job: a few hundred solves, cheaper than a second Python start-up.
rule restitution_figure:
    input:
        warmup=WARMUP,
    output:
        data="results/restitution/restitution_kinematic.nc",
        png="results/figures/restitution_kinematic.png",
        pdf="results/figures/restitution_kinematic.pdf",
    params:
        curves=RESTITUTION["curves"],
    log:
        "logs/restitution/figure.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/restitution_figure.py"


rule kinematic_table:
    input:
        warmup=WARMUP,
    output:
        BUILT_KINEMATIC_TABLE,
    params:
        table=RESTITUTION["table"],
        code_version=KINEMATIC_CODE_VERSION,
    log:
        "logs/restitution/kinematic_table.log",
    threads: 2
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/restitution_table.py"


rule kinematic_table_check:
    input:
        KINEMATIC_TABLE_IN_USE,
        warmup=WARMUP,
    output:
        "results/restitution/kinematic_table_check.md",
    params:
        check=RESTITUTION["check"],
        code_version=KINEMATIC_CODE_VERSION,
    log:
        "logs/restitution/kinematic_table_check.log",
    # One thread, as table_check (rules/models.smk).
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/restitution_table_check.py"


# The check of a freshly built table, before shipping copies it into the package.
use rule kinematic_table_check as kinematic_table_check_built with:
    input:
        BUILT_KINEMATIC_TABLE,
    output:
        "results/restitution/alpha_table_kinematic_check.md",
    log:
        "logs/restitution/alpha_table_kinematic_check.log",


# Not in ALL_TARGETS: a maintainer's explicit command, like the rules of rules/ship.smk.
rule ship_kinematic_table:
    input:
        source=BUILT_KINEMATIC_TABLE,
        check="results/restitution/alpha_table_kinematic_check.md",
    output:
        "results/ship/alpha_table_kinematic.json",
    params:
        destination=RESTITUTION["package_table"],
    log:
        "logs/ship/alpha_table_kinematic.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ship.py"
