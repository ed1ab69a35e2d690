# Stage "surface": the alpha(eps, xi) surface, in chunks of xi columns, merged into
# results/surface.h5; Fig. 4 (the surface), Fig. 5 (the xi = 0.2 section), the end-state map
# and results/summary.md.

from contactalpha.provenance import source_hash

SURFACE_CHUNKS = range(config["surface"]["chunks"])
SURFACE_FIGURES = ["fig4_alpha_surface", "fig5_alpha_section", "end_states"]

ALL_TARGETS += [
    "results/surface.h5",
    "results/summary.md",
    *expand("results/figures/{name}.{ext}", name=SURFACE_FIGURES, ext=["png", "pdf"]),
]


# Light jobs: on a cluster they run on the submitting node, only the chunks are submitted.
localrules:
    surface_merge,
    surface_figures,
    surface_report,


wildcard_constraints:
    chunk=r"\d+",


rule surface_chunk:
    input:
        warmup=WARMUP,
    output:
        "results/surface/chunks/chunk_{chunk}.h5",
    params:
        epsilon=config["surface"]["epsilon"],
        xi=config["surface"]["xi"],
        solver=config["surface"]["solver"],
        chunks=config["surface"]["chunks"],
        # Hash of the package sources the solver runs: editing the engine reruns the surface.
        code_version=source_hash("contactalpha.paper.surface.compute"),
    log:
        "logs/surface/chunk_{chunk}.log",
    threads: 1
    priority: CRITICAL_PATH
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/surface_chunk.py"


rule surface_merge:
    input:
        expand("results/surface/chunks/chunk_{chunk}.h5", chunk=SURFACE_CHUNKS),
    output:
        "results/surface.h5",
    params:
        # The settings that make the surface, stored in its attrs (not the figure settings:
        # editing those must not rebuild the surface).
        surface={key: config["surface"][key] for key in ("epsilon", "xi", "solver", "chunks")},
    priority: CRITICAL_PATH
    log:
        "logs/surface/merge.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/surface_merge.py"


# Several figures per job: one Python start-up and one set of imports for all of them. Fig. 5
# and the summary use surface.figures, Fig. 4 and the end-state map do not: a figure setting
# reruns only the job that uses it.
rule surface_figures:
    input:
        surface="results/surface.h5",
    output:
        fig4=multiext("results/figures/fig4_alpha_surface", ".png", ".pdf"),
        end_states=multiext("results/figures/end_states", ".png", ".pdf"),
    log:
        "logs/surface/figures.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/surface_figures.py"


rule surface_report:
    input:
        surface="results/surface.h5",
        chunks=expand("results/surface/chunks/chunk_{chunk}.h5", chunk=SURFACE_CHUNKS),
    output:
        summary="results/summary.md",
        fig5=multiext("results/figures/fig5_alpha_section", ".png", ".pdf"),
    params:
        figures=config["surface"]["figures"],
    log:
        "logs/surface/report.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/surface_figures.py"
