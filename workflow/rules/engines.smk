# Stage "engines" (issue 11, part 3): our alpha inside real multibody engines, OpenSim (Simbody)
# and Exudyn. An explicit target, NOT in ALL_TARGETS (it needs the optional engines:
# pip install -e ".[engines]"):
#   snakemake -c2 engines
# Round trips over the (eps, F) grid, static penetration checks and case A of Sect. 6 in OpenSim
# go to results/engines/; the figure to results/figures/; the generated block of docs/engines/index.md
# is filled from results/engines/summary.md.

ENGINES = config["engines"]
ENGINES_DIR = "results/engines"
ENGINE_NAMES = ["opensim", "exudyn"]
# Stepping engines (issue 27): each one's round trips at its own step; a missing one is skipped.
STEPPING_ENGINES = ["mujoco", "drake", "pybullet"]
# The engine pages' figures (docs/engines/*.md, shown by docs/hooks.py): one per engine, and the
# round trips' figure of docs/engines/index.md (`snakemake -c2 docs_figures`; also in `engines`).
PAGE_FIGURE_ENGINES = ENGINE_NAMES + STEPPING_ENGINES


rule docs_figures:
    input:
        expand("results/figures/engine_{engine}.{ext}", engine=PAGE_FIGURE_ENGINES, ext=["png", "pdf"]),
        "results/figures/engines_roundtrip.png",


rule engines:
    input:
        f"{ENGINES_DIR}/summary.md",
        f"{ENGINES_DIR}/page.filled",
        expand("results/figures/engines_roundtrip.{ext}", ext=["png", "pdf"]),
        expand("results/figures/engines_stepping.{ext}", ext=["png", "pdf"]),
        "docs/engines-table.md",
        rules.docs_figures.input,


rule engines_roundtrip:
    output:
        f"{ENGINES_DIR}/roundtrip_{{engine}}.nc",
    params:
        scene=config["ball"]["scene"],
        grid=ENGINES["grid"],
        settings=lambda w: ENGINES[w.engine],
    wildcard_constraints:
        engine="|".join(ENGINE_NAMES),
    log:
        "logs/engines/roundtrip_{engine}.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_roundtrip.py"


rule engines_static:
    output:
        f"{ENGINES_DIR}/static.nc",
    params:
        scene=config["ball"]["scene"],
        forces=ENGINES["grid"]["forces"],
    log:
        "logs/engines/static.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_static.py"


rule engines_case_a:
    output:
        f"{ENGINES_DIR}/case_A_opensim.nc",
    params:
        scene=config["ball"]["scene"],
        cases=config["ball"]["cases"],
        model=ENGINES["case_a_model"],
        settings=ENGINES["opensim"],
    log:
        "logs/engines/case_A_opensim.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_case_a.py"


rule engines_summary:
    input:
        roundtrips=expand(f"{ENGINES_DIR}/roundtrip_{{engine}}.nc", engine=ENGINE_NAMES),
        static=f"{ENGINES_DIR}/static.nc",
        case_a=f"{ENGINES_DIR}/case_A_opensim.nc",
    output:
        f"{ENGINES_DIR}/summary.md",
    params:
        eps_tol=ENGINES["eps_tol"],
    log:
        "logs/engines/summary.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_summary.py"


rule engines_page:
    input:
        f"{ENGINES_DIR}/summary.md",
    output:
        touch(f"{ENGINES_DIR}/page.filled"),
    params:
        page="docs/engines/index.md",
    log:
        "logs/engines/page.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_page.py"


rule engines_fig_roundtrip:
    input:
        expand(f"{ENGINES_DIR}/roundtrip_{{engine}}.nc", engine=ENGINE_NAMES),
    output:
        png="results/figures/engines_roundtrip.png",
        pdf="results/figures/engines_roundtrip.pdf",
    log:
        "logs/engines/fig_roundtrip.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_fig_roundtrip.py"


rule engines_stepping:
    output:
        f"{ENGINES_DIR}/stepping_{{engine}}.nc",
    wildcard_constraints:
        engine="|".join(STEPPING_ENGINES),
    log:
        "logs/engines/stepping_{engine}.log",
    threads: 1
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_stepping.py"


rule engines_stepping_report:
    input:
        expand(f"{ENGINES_DIR}/stepping_{{engine}}.nc", engine=STEPPING_ENGINES),
    output:
        png="results/figures/engines_stepping.png",
        pdf="results/figures/engines_stepping.pdf",
        table="docs/engines-table.md",
    log:
        "logs/engines/stepping_report.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_stepping_report.py"


rule engines_page_figure:
    input:
        lambda w: f"{ENGINES_DIR}/{'roundtrip' if w.engine in ENGINE_NAMES else 'stepping'}_{w.engine}.nc",
    output:
        png="results/figures/engine_{engine}.png",
        pdf="results/figures/engine_{engine}.pdf",
    wildcard_constraints:
        engine="|".join(PAGE_FIGURE_ENGINES),
    log:
        "logs/engines/page_figure_{engine}.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/engines_page_figure.py"


# Issue 33: restitution at an engine's step, in MuJoCo's map (no engine needed):
#   snakemake -c1 stepping_figures
rule stepping_figures:
    output:
        phase_png="results/figures/stepping_phase.png",
        phase_pdf="results/figures/stepping_phase.pdf",
        map_png="results/figures/stepping_step_map.png",
        map_pdf="results/figures/stepping_step_map.pdf",
    log:
        "logs/engines/stepping_figures.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/stepping_figures.py"
