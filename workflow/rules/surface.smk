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
    fig4_alpha_surface,
    fig5_alpha_section,
    end_states_map,
    surface_summary,


wildcard_constraints:
    chunk=r"\d+",


rule surface_chunk:
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
    log:
        "logs/surface/merge.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/surface_merge.py"


rule fig4_alpha_surface:
    input:
        "results/surface.h5",
    output:
        png="results/figures/fig4_alpha_surface.png",
        pdf="results/figures/fig4_alpha_surface.pdf",
    log:
        "logs/surface/fig4_alpha_surface.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fig4_alpha_surface.py"


rule fig5_alpha_section:
    input:
        "results/surface.h5",
    output:
        png="results/figures/fig5_alpha_section.png",
        pdf="results/figures/fig5_alpha_section.pdf",
    params:
        figures=config["surface"]["figures"],
    log:
        "logs/surface/fig5_alpha_section.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fig5_alpha_section.py"


rule end_states_map:
    input:
        "results/surface.h5",
    output:
        png="results/figures/end_states.png",
        pdf="results/figures/end_states.pdf",
    log:
        "logs/surface/end_states.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/end_states_map.py"


rule surface_summary:
    input:
        surface="results/surface.h5",
        chunks=expand("results/surface/chunks/chunk_{chunk}.h5", chunk=SURFACE_CHUNKS),
    output:
        "results/summary.md",
    params:
        figures=config["surface"]["figures"],
    log:
        "logs/surface/summary.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/surface_summary.py"
