# Stage "laws" (issue 26): the contact laws engines use, each exact under a load.  For every law, the
# engines' usual restitution mapping and the exact inverse, judged by the e_N the law delivers across
# the target and the load: a figure and a Markdown table (contactalpha.studies.laws).

from contactalpha.provenance import source_hash

# Hash of the package sources the study runs (the laws, the models): editing them reruns it.
LAWS_CODE_VERSION = source_hash("contactalpha.studies.laws.compute")

ALL_TARGETS += [
    "results/laws/delivered.nc",
    "results/laws/delivered.md",
    *expand("results/figures/laws_delivered.{ext}", ext=["png", "pdf"]),
]


rule laws_delivered:
    input:
        warmup=WARMUP,
    output:
        data="results/laws/delivered.nc",
        table="results/laws/delivered.md",
        png="results/figures/laws_delivered.png",
        pdf="results/figures/laws_delivered.pdf",
    params:
        code_version=LAWS_CODE_VERSION,
    log:
        "logs/laws/delivered.log",
    conda:
        "../envs/contactalpha.yaml"
    script:
        "../scripts/laws_delivered.py"
