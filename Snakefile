# contactalpha workflow: `snakemake -c2` rebuilds every result under results/ and writes nothing
# else (`snakemake -c2 ship`, rules/ship.smk, updates the files shipped with the package).
# Stages live in workflow/rules/<stage>.smk; each appends its default targets to ALL_TARGETS.
# Every rule declares `conda: "../envs/contactalpha.yaml"`, so that `snakemake --lint` is clean.
import os
import sys

from snakemake.utils import validate

from contactalpha.config import check_config, read_yaml
from contactalpha.io import ANOTHER_RUN, claim_workdir, other_run_alive

# The job server is workflow machinery: it lives beside the scripts that use it.
sys.path.insert(0, os.path.join(workflow.basedir, "workflow", "scripts"))
from prefork import start_server, stop_server  # noqa: E402

SCHEMA = "workflow/schemas/config.schema.yaml"

# Snakemake reads config.yaml (from the working directory, if there) without saying where a
# malformed one breaks; read_yaml names the line and column.
if os.path.exists("config.yaml"):
    read_yaml("config.yaml")


configfile: "config.yaml"


validate(config, SCHEMA)
check_config(config, os.path.join(workflow.basedir, SCHEMA))

# Resume after kill -9 with the same command: with no other run alive here, the killed run's
# Snakemake lock and half-written temporaries are cleared (profiles/default sets rerun-incomplete).
if workflow.is_main_process:
    held, _ = claim_workdir()
    # A second run here would get Snakemake's lock error and its advice to --unlock.
    if not held and not workflow.dryrun and other_run_alive():
        sys.exit(ANOTHER_RUN.format(workdir=os.getcwd()))

ALL_TARGETS = []

# Local runs: the jobs' scripts run in forks of one process that has imported numpy, xarray,
# numba, Matplotlib and the package once (workflow/scripts/prefork.py), about 1.5 s of CPU less
# per job.  Cluster jobs, --sdm conda/apptainer jobs (their own Python) and --touch run without it.
PREFORK = []


onstart:
    if (
        workflow.is_main_process
        and workflow.local_exec
        and not workflow.touch
        and not workflow.deployment_settings.deployment_method
    ):
        PREFORK.append(start_server())


onsuccess:
    for server in PREFORK:
        stop_server(server)


onerror:
    for server in PREFORK:
        stop_server(server)



include: "workflow/rules/warmup.smk"
include: "workflow/rules/surface.smk"
include: "workflow/rules/fit.smk"
include: "workflow/rules/models.smk"
include: "workflow/rules/ball.smk"
include: "workflow/rules/bench.smk"
include: "workflow/rules/closedform.smk"
include: "workflow/rules/engines.smk"
include: "workflow/rules/adequacy.smk"
include: "workflow/rules/restitution.smk"
include: "workflow/rules/laws.smk"
include: "workflow/rules/ship.smk"


rule all:
    input:
        ALL_TARGETS,
