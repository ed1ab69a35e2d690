# Stage "warmup": compile every numba kernel once, before the jobs that run them (issue 14, item 6).
# On a fresh clone the numba cache is empty: without this job the first jobs (surface chunks,
# Fig. 9, the ball) would each compile the same kernels at the same time. The jobs take its
# outputs as plain inputs: the warm-up reruns when any package source it reaches changes, and
# then so do they. Not ancient(): with ancient inputs Snakemake (9.27) planned the warm-up after
# an engine edit but not the jobs whose code_version params had changed, so the surface stayed
# stale (test_an_engine_edit_reruns_the_surface_and_the_table).
# It runs as two jobs at once (contactalpha.warmup.PARTS: kernels built on the impact kernel, the rest);
# results/warmup/<part>.json records the compile (or cache load) time of each kernel family.

from contactalpha.provenance import source_hash
from contactalpha.warmup import PARTS

# Priority of the jobs on the main job's critical path (warm-up, surface, refit, Figs. 6-8):
# Snakemake starts them before other ready jobs (default priority 0).
CRITICAL_PATH = 10
# Priority of the longest jobs off that path (the ball's and the adequacy maps' chains, whose
# figure jobs take 10-20 s): started before the short ones, so that the run does not end with
# one core idle while the other finishes a long job (longest job first).
LONG_JOBS = 5

# One part's output: a job whose kernels are all in one part starts when that part is done. The
# ball's two simulation jobs and the bounce thresholds need only "models" (with an empty cache
# beside it they compiled nothing), which finishes several seconds before "engine": they fill the
# core it leaves idle. A job that came to need a kernel of the other part would compile it itself
# (the same results, only slower); tests/test_warmup.py checks their calls after "models" alone.
WARMUP_PART = {part: f"results/warmup/{part}.json" for part in PARTS}
WARMUP = list(WARMUP_PART.values())

ALL_TARGETS += WARMUP


rule numba_warmup:
    output:
        "results/warmup/{part}.json",
    params:
        # The warm-up's closure is every kernel the jobs run: an edit of any recompiles here.
        code_version=source_hash("contactalpha.warmup"),
    log:
        "logs/warmup/{part}.log",
    threads: 1
    priority: CRITICAL_PATH
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/numba_warmup.py"
