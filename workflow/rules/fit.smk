# Stage "fit": Shen et al.'s closed form refit to results/surface.h5 (issue 4): the comparison
# with the published constants (results/fit/), the refit constants shipped with the package,
# and Figs. 6-8 with lambda and the dissipation ratios.

FIT_FIGURES = ["fig6_s1_s21", "fig7_sa_s1", "fig8_fit_errors", "fit_lambda", "fit_eta"]

ALL_TARGETS += [
    "results/fit/coefficients.json",
    "results/fit/comparison.md",
    "results/fit/eq40_readings.md",
    "results/fit/shen_refit.json",
    config["fit"]["package_coefficients"],
    *expand("results/figures/{name}.{ext}", name=FIT_FIGURES, ext=["png", "pdf"]),
]


localrules:
    fit_ship,
    fit_fig6,
    fit_fig7,
    fit_lambda,
    fit_eta,


rule fit_refit:
    input:
        "results/surface.h5",
    output:
        coefficients="results/fit/coefficients.json",
        comparison="results/fit/comparison.md",
        readings="results/fit/eq40_readings.md",
        package="results/fit/shen_refit.json",
    params:
        readings=config["fit"]["readings"],
        weights=config["fit"]["weights"],
        loss=config["fit"]["loss"],
        verdict_k=config["fit"]["verdict_k"],
        eq26=config["fit"]["eq26"],
        restitution=config["fit"]["restitution"],
    log:
        "logs/fit/refit.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_refit.py"


# A separate step, so the shipped file is replaced only after a successful refit (Snakemake
# removes a job's outputs before it runs and after it fails).
rule fit_ship:
    input:
        "results/fit/shen_refit.json",
    output:
        config["fit"]["package_coefficients"],
    log:
        "logs/fit/ship.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_ship.py"


rule fit_fig6:
    input:
        "results/fit/coefficients.json",
    output:
        png="results/figures/fig6_s1_s21.png",
        pdf="results/figures/fig6_s1_s21.pdf",
    log:
        "logs/fit/fig6.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_fig6.py"


rule fit_fig7:
    input:
        "results/surface.h5",
    output:
        png="results/figures/fig7_sa_s1.png",
        pdf="results/figures/fig7_sa_s1.pdf",
    log:
        "logs/fit/fig7.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_fig7.py"


rule fit_fig8:
    input:
        surface="results/surface.h5",
        coefficients="results/fit/coefficients.json",
    output:
        png="results/figures/fig8_fit_errors.png",
        pdf="results/figures/fig8_fit_errors.pdf",
    params:
        restitution=config["fit"]["restitution"],
    log:
        "logs/fit/fig8.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_fig8.py"


rule fit_lambda:
    input:
        surface="results/surface.h5",
        coefficients="results/fit/coefficients.json",
    output:
        png="results/figures/fit_lambda.png",
        pdf="results/figures/fit_lambda.pdf",
    log:
        "logs/fit/lambda.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_lambda.py"


rule fit_eta:
    input:
        "results/surface.h5",
    output:
        png="results/figures/fit_eta.png",
        pdf="results/figures/fit_eta.pdf",
    log:
        "logs/fit/eta.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/fit_eta.py"
