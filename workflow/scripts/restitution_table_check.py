"""Check a kinematic exact-alpha table (the shipped one, or one built under results/) against the solver.

Settings (snakemake.params.check): points, seed, max_rel_err (the accuracy the package promises).
snakemake.params.code_version (source hash) only makes an engine edit rerun the check.
Inputs: the table file; a built table is also compared with the shipped copy.
Outputs: the check as markdown; the rule fails if the table misses max_rel_err.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

from pathlib import Path

from contactalpha.engine.table import KINEMATIC_ARRAY_NAMES, KINEMATIC_FILE, read_table_file
from contactalpha.engine.table_build import check_table
from contactalpha.io import json_text, script_logger, write_text_atomic

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("restitution_table_check", sm.log[0])
p = sm.params.check
res = check_table(sm.input[0], n=p["points"], seed=p["seed"], restitution="kinematic")
meta = read_table_file(sm.input[0], KINEMATIC_ARRAY_NAMES)[1]
shipped = Path(sm.input[0]).resolve() == KINEMATIC_FILE.resolve()
what = (
    f"The kinematic table shipped in the package: `{KINEMATIC_FILE.name}`."
    if shipped
    else f"Built table: `{sm.input[0]}`; shipped table: `{KINEMATIC_FILE.name}` in the package."
)
shipped_diff = "— (this is the shipped table)" if shipped else f"{res['max_rel_diff_shipped']:.2e}"
text = f"""# Kinematic exact-alpha table check

{what}

| quantity | value |
|---|---|
| random points off the nodes | {res["n"]} |
| max relative error against `solve_alpha(..., restitution="kinematic")` | {res["max_rel_err"]:.2e} |
| median relative error | {res["median_rel_err"]:.1e} |
| worst point (e_N, ξ) | ({res["worst"][0]:.5g}, {res["worst"][1]:.5g}) |
| promised max relative error | {p["max_rel_err"]:.0e} |
| max relative difference to the shipped table | {shipped_diff} |

Table metadata: `{json_text(meta)}`
"""
write_text_atomic(sm.output[0], text)
log.info(text)
if not res["max_rel_err"] <= p["max_rel_err"]:
    raise SystemExit(
        f"kinematic table {sm.input[0]} misses its accuracy: max rel err {res['max_rel_err']:.2e} > "
        f"{p['max_rel_err']:.0e}; `snakemake -c2 ship_kinematic_table` builds, checks and ships a new one"
    )
