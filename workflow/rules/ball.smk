# Stage "ball": the bouncing ball of the paper's Sect. 6. Cases A and B (Figs. 11-12, with the
# counts and end states in results/ball/cases.md), the first collision for every force, eps and
# model (Figs. 13-21 and results/ball/first_collision.md) and the check of the paper's
# statements (results/ball/statements.md).

BALL = config["ball"]
# Figures 13-21: one per (kind, force); numbering as in the paper, kinds in this order.
BALL_KINDS = ["deformation", "velocity", "hysteresis"]
BALL_FIRST_FIG = 13
BALL_N_FORCES = len(BALL["first_collision"]["forces"])
# name -> (kind, force index) of the first-collision figures.
BALL_FIRST_FIGURES = {
    f"fig{BALL_FIRST_FIG + k * BALL_N_FORCES + i}_ball_{kind}": (kind, i)
    for k, kind in enumerate(BALL_KINDS)
    for i in range(BALL_N_FORCES)
}
BALL_FIGURES = ["fig11_ball_motion", "fig12_ball_energy", *BALL_FIRST_FIGURES]

ALL_TARGETS += [
    "results/ball/cases.md",
    "results/ball/first_collision.md",
    "results/ball/statements.md",
    *expand("results/figures/{name}.{ext}", name=BALL_FIGURES, ext=["png", "pdf"]),
]


rule ball_cases:
    input:
        warmup=WARMUP_PART["models"],
    output:
        case_a="results/ball/case_A.nc",
        case_b="results/ball/case_B.nc",
        summary="results/ball/cases.md",
    params:
        scene=BALL["scene"],
        cases=BALL["cases"],
        new_model=BALL["new_model"],
        numerics=BALL["numerics"],
        # Model shen_refit reads the shipped constants (rules/fit.smk): shipping new ones reruns
        # this. The default run never writes them, so nothing waits for the refit.
        shipped_refit=SHIPPED_REFIT_DIGEST,
    priority: LONG_JOBS
    log:
        "logs/ball/cases.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_cases.py"


rule ball_first_collision:
    input:
        warmup=WARMUP_PART["models"],
    output:
        data="results/ball/first_collision.nc",
        table="results/ball/first_collision.md",
    params:
        scene=BALL["scene"],
        first_collision=BALL["first_collision"],
        new_model=BALL["new_model"],
        numerics=BALL["numerics"],
        # Model shen_refit reads the shipped constants (rules/fit.smk): shipping new ones reruns
        # this. The default run never writes them, so nothing waits for the refit.
        shipped_refit=SHIPPED_REFIT_DIGEST,
    priority: LONG_JOBS
    log:
        "logs/ball/first_collision.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_first.py"


# The statements and every figure in one job: one Python start-up and one set of imports.
rule ball_report:
    input:
        case_a="results/ball/case_A.nc",
        case_b="results/ball/case_B.nc",
        first="results/ball/first_collision.nc",
    output:
        statements="results/ball/statements.md",
        **{name: multiext(f"results/figures/{name}", ".png", ".pdf") for name in BALL_FIGURES},
    params:
        first_figures=BALL_FIRST_FIGURES,
    priority: LONG_JOBS
    log:
        "logs/ball/report.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_report.py"
