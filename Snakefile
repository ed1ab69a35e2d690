# contactalpha workflow: `snakemake -c2` rebuilds every result under results/.
# Stages live in workflow/rules/<stage>.smk; each appends its default targets to ALL_TARGETS.
# Every rule declares `conda: "../envs/contactalpha.yaml"`, so that `snakemake --lint` is clean.
from snakemake.utils import validate

from contactalpha.config import check_config


configfile: "config.yaml"


validate(config, "workflow/schemas/config.schema.yaml")
check_config(config)

ALL_TARGETS = []


include: "workflow/rules/surface.smk"
include: "workflow/rules/fit.smk"
include: "workflow/rules/models.smk"
include: "workflow/rules/ball.smk"
include: "workflow/rules/bench.smk"
include: "workflow/rules/engines.smk"


rule all:
    input:
        ALL_TARGETS,
