"""Check an exact-alpha table (the shipped one, or one built under results/) against the solver.

Settings (snakemake.params.check): points, seed, max_rel_err (the accuracy the package promises).
snakemake.params.code_version (source hash) and shipped_table (digest of the shipped table, when
it is the one checked) only make an engine edit or a new shipped table rerun the check.
Inputs: table (a built table, also compared with the shipped copy; absent: the shipped table);
warmup (the numba warm-up's records: they order the job after the compile, and are not read).
Outputs: the check as markdown; the rule fails if the table misses max_rel_err.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.engine.table import DEFAULT_FILE, load_table
from contactalpha.engine.table_build import check_table
from contactalpha.io import json_text, script_logger, write_text_atomic

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("models_table_check", sm.log[0])
p = sm.params.check
table = sm.input.get("table", DEFAULT_FILE)
res = check_table(table, n=p["points"], seed=p["seed"])
meta = load_table(table).meta
if Path(table).resolve() == DEFAULT_FILE.resolve():
    what, shipped_diff = (
        f"The table shipped in the package: `{DEFAULT_FILE.name}`.",
        "— (this is the shipped table)",
    )
else:
    what = f"Built table: `{table}`; shipped table: `{DEFAULT_FILE.name}` in the package."
    shipped_diff = f"{res['max_rel_diff_shipped']:.2e}"
text = f"""# Exact-alpha table check

{what}

| quantity | value |
|---|---|
| random points off the nodes | {res["n"]} |
| max relative error against `solve_alpha` | {res["max_rel_err"]:.2e} |
| median relative error | {res["median_rel_err"]:.1e} |
| worst point (ε, ξ) | ({res["worst"][0]:.5g}, {res["worst"][1]:.5g}) |
| promised max relative error | {p["max_rel_err"]:.0e} |
| max relative difference to the shipped table | {shipped_diff} |

Table metadata: `{json_text(meta)}`
"""
write_text_atomic(sm.output[0], text)
log.info(text)
if not res["max_rel_err"] <= p["max_rel_err"]:
    raise SystemExit(
        f"table {table} misses its accuracy: max rel err {res['max_rel_err']:.2e} > "
        f"{p['max_rel_err']:.0e}; `snakemake -c2 ship` builds, checks and ships a new one"
    )
