"""Build the exact-alpha spline table (contactalpha.engine.table_build.build_table).

Settings (snakemake.params.table): n_eta, n_p, refine_n, tol, rtol, atol.  snakemake.params.code_version
(source hash) only makes an engine edit rebuild the table.
Inputs: none (the table is computed from the impact engine).
Outputs: results/models/alpha_table.npz, written atomically, with its grid, tolerances,
package version, git commit and build time in its metadata.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import time

from contactalpha.engine.table_build import TableSettings, build_table, save_table
from contactalpha.io import script_logger
from contactalpha.provenance import git_commit
from contactalpha.version import __version__

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("models_table", sm.log[0])
p = dict(sm.params.table)
start = time.perf_counter()
s = TableSettings(**p)
table = build_table(s.n_eta, s.n_p, s.refine_n, tol=s.tol, rtol=s.rtol, atol=s.atol, progress=log.info)
wall = time.perf_counter() - start
# refine_n is not part of the table's own metadata: recorded so that a run can tell the settings.
save_table(
    table,
    sm.output[0],
    refine_n=s.refine_n,
    wall_time_s=wall,
    contactalpha_version=__version__,
    git_commit=git_commit(),
)
log.info(f"table built in {wall:.1f} s: {sm.output[0]}")
