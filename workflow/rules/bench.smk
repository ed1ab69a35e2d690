# Stage "bench" (issue 7): speed against accuracy. An explicit target, NOT in ALL_TARGETS:
#   snakemake -c2 bench
# (the same stages as `python benchmarks/bench_workprecision.py`). Tables, figures and
# summary.md go to results/bench/; the "Speed and accuracy" block of docs/performance.md is
# filled from summary.md.

BENCH = "results/bench"
BENCH_FIGURES = ["workprecision", "failure_map", "scaling"]


rule bench:
    input:
        expand(f"{BENCH}/{{name}}.{{ext}}", name=BENCH_FIGURES, ext=["png", "pdf"]),
        f"{BENCH}/summary.md",
        f"{BENCH}/page.filled",


rule bench_workprecision:
    output:
        reference=f"{BENCH}/reference.csv",
        table=f"{BENCH}/workprecision.csv",
    params:
        rtols=config["bench"]["rtols"],
        rk4_steps=config["bench"]["rk4_steps"],
        scipy_methods=config["bench"]["scipy_methods"],
        scipy_max_nfev=config["bench"]["scipy_max_nfev"],
    log:
        "logs/bench/workprecision.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_workprecision.py"


rule bench_failures:
    output:
        table=f"{BENCH}/failure_map.csv",
        counts=f"{BENCH}/failure_counts.csv",
    params:
        failure=config["bench"]["failure"],
        scipy_methods=config["bench"]["scipy_methods"],
        scipy_max_nfev=config["bench"]["scipy_max_nfev"],
    log:
        "logs/bench/failures.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_failures.py"


rule bench_scaling:
    output:
        f"{BENCH}/scaling.json",
    params:
        scaling=config["bench"]["scaling"],
    log:
        "logs/bench/scaling.log",
    # Times 1 against 2 threads: it needs both cores to itself.
    threads: 2
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_scaling.py"


rule bench_fig_workprecision:
    input:
        reference=f"{BENCH}/reference.csv",
        table=f"{BENCH}/workprecision.csv",
    output:
        png=f"{BENCH}/workprecision.png",
        pdf=f"{BENCH}/workprecision.pdf",
    log:
        "logs/bench/fig_workprecision.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_fig_workprecision.py"


rule bench_fig_failure_map:
    input:
        f"{BENCH}/failure_map.csv",
    output:
        png=f"{BENCH}/failure_map.png",
        pdf=f"{BENCH}/failure_map.pdf",
    log:
        "logs/bench/fig_failure_map.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_fig_failure_map.py"


rule bench_fig_scaling:
    input:
        f"{BENCH}/scaling.json",
    output:
        png=f"{BENCH}/scaling.png",
        pdf=f"{BENCH}/scaling.pdf",
    log:
        "logs/bench/fig_scaling.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_fig_scaling.py"


rule bench_summary:
    input:
        reference=f"{BENCH}/reference.csv",
        table=f"{BENCH}/workprecision.csv",
        counts=f"{BENCH}/failure_counts.csv",
        failures=f"{BENCH}/failure_map.csv",
        scaling=f"{BENCH}/scaling.json",
    output:
        f"{BENCH}/summary.md",
    params:
        failure=config["bench"]["failure"],
        scipy_max_nfev=config["bench"]["scipy_max_nfev"],
    log:
        "logs/bench/summary.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_summary.py"


# docs/performance.md is a tracked source file, so it is not a Snakemake output (Snakemake would
# delete it before the job); a flag file records that the bench block was refilled.
rule bench_page:
    input:
        f"{BENCH}/summary.md",
    output:
        touch(f"{BENCH}/page.filled"),
    params:
        page="docs/performance.md",
    log:
        "logs/bench/page.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/bench_page.py"
