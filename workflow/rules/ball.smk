# Stage "ball": the bouncing ball of the paper's Sect. 6. Cases A and B (Figs. 11-12, with the
# counts and end states in results/ball/cases.md), the first collision for every force, eps and
# model (Figs. 13-21 and results/ball/first_collision.md) and the check of the paper's
# statements (results/ball/statements.md).

BALL = config["ball"]
# The shipped refit of Eq. 40 is rewritten by the fit stage; runs that may use shen_refit wait
# for it, so they never read a copy that is about to change.
BALL_MODEL_DATA = [config["fit"]["package_coefficients"]] if "fit" in config else []
# Figures 13-21: one per (kind, force); numbering as in the paper, kinds in this order.
BALL_KINDS = ["deformation", "velocity", "hysteresis"]
BALL_FIRST_FIG = 13
BALL_N_FORCES = len(BALL["first_collision"]["forces"])
BALL_FIGURES = [
    "fig11_ball_motion",
    "fig12_ball_energy",
    *[
        f"fig{BALL_FIRST_FIG + k * BALL_N_FORCES + i}_ball_{kind}"
        for k, kind in enumerate(BALL_KINDS)
        for i in range(BALL_N_FORCES)
    ],
]

ALL_TARGETS += [
    "results/ball/cases.md",
    "results/ball/first_collision.md",
    "results/ball/statements.md",
    *expand("results/figures/{name}.{ext}", name=BALL_FIGURES, ext=["png", "pdf"]),
]


wildcard_constraints:
    num=r"\d+",
    kind="|".join(BALL_KINDS),


rule ball_cases:
    input:
        BALL_MODEL_DATA,
    output:
        case_a="results/ball/case_A.nc",
        case_b="results/ball/case_B.nc",
        summary="results/ball/cases.md",
    params:
        scene=BALL["scene"],
        cases=BALL["cases"],
        new_model=BALL["new_model"],
        numerics=BALL["numerics"],
    log:
        "logs/ball/cases.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_cases.py"


rule ball_first_collision:
    input:
        BALL_MODEL_DATA,
    output:
        data="results/ball/first_collision.nc",
        table="results/ball/first_collision.md",
    params:
        scene=BALL["scene"],
        first_collision=BALL["first_collision"],
        new_model=BALL["new_model"],
        numerics=BALL["numerics"],
    log:
        "logs/ball/first_collision.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_first.py"


rule ball_statements:
    input:
        case_a="results/ball/case_A.nc",
        case_b="results/ball/case_B.nc",
        first="results/ball/first_collision.nc",
    output:
        "results/ball/statements.md",
    log:
        "logs/ball/statements.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_statements.py"


rule fig11_ball_motion:
    input:
        case_a="results/ball/case_A.nc",
        case_b="results/ball/case_B.nc",
    output:
        png="results/figures/fig11_ball_motion.png",
        pdf="results/figures/fig11_ball_motion.pdf",
    log:
        "logs/ball/fig11_ball_motion.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_fig_motion.py"


rule fig12_ball_energy:
    input:
        case_a="results/ball/case_A.nc",
        case_b="results/ball/case_B.nc",
    output:
        png="results/figures/fig12_ball_energy.png",
        pdf="results/figures/fig12_ball_energy.pdf",
    log:
        "logs/ball/fig12_ball_energy.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_fig_energy.py"


rule ball_first_figure:
    input:
        "results/ball/first_collision.nc",
    output:
        png="results/figures/fig{num}_ball_{kind}.png",
        pdf="results/figures/fig{num}_ball_{kind}.pdf",
    params:
        kind=lambda w: w.kind,
        force_index=lambda w: int(w.num) - BALL_FIRST_FIG - BALL_KINDS.index(w.kind) * BALL_N_FORCES,
    log:
        "logs/ball/fig{num}_ball_{kind}.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/ball_fig_first.py"
