"""Check a freshly built exact-alpha table against the solver and against the shipped copy.

Settings (snakemake.params.check): points, seed, max_rel_err (the accuracy the package promises).
Inputs: results/models/alpha_table.npz.
Outputs: results/models/table_check.md; the rule fails if the table misses max_rel_err.
"""

from contactalpha.engine.table import DEFAULT_FILE, load_table
from contactalpha.engine.table_build import check_table
from contactalpha.io import json_text, script_logger, write_text_atomic

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("models_table_check", sm.log[0])
p = sm.params.check
res = check_table(sm.input[0], n=p["points"], seed=p["seed"])
meta = load_table(sm.input[0]).meta
text = f"""# Exact-alpha table check

Built table: `{sm.input[0]}`; shipped table: `{DEFAULT_FILE.name}` in the package.

| quantity | value |
|---|---|
| random points off the nodes | {res["n"]} |
| max relative error against `solve_alpha` | {res["max_rel_err"]:.2e} |
| median relative error | {res["median_rel_err"]:.1e} |
| worst point (ε, ξ) | ({res["worst"][0]:.5g}, {res["worst"][1]:.5g}) |
| promised max relative error | {p["max_rel_err"]:.0e} |
| max relative difference to the shipped table | {res["max_rel_diff_shipped"]:.2e} |

Table metadata: `{json_text(meta)}`
"""
write_text_atomic(sm.output[0], text)
log.info(text)
if not res["max_rel_err"] <= p["max_rel_err"]:
    raise SystemExit(
        f"table misses its accuracy: max rel err {res['max_rel_err']:.2e} > {p['max_rel_err']:.0e}"
    )
