"""Build the kinematic exact-alpha table (contactalpha.engine.table_build.build_kinematic_table).

Settings (snakemake.params.table): n_eta, n_q, tol, rtol, atol.  snakemake.params.code_version
(source hash) only makes an engine edit rebuild the table.
Inputs: none (the table is computed from the impact engine).
Outputs: results/models/alpha_table_kinematic.npz, written atomically, with its grid, tolerances,
package version, git commit and build time in its metadata.
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import time

from contactalpha.engine.table_build import (
    KinematicTableSettings,
    build_kinematic_table,
    save_kinematic_table,
)
from contactalpha.io import script_logger
from contactalpha.provenance import git_commit
from contactalpha.version import __version__

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("restitution_table", sm.log[0])
s = KinematicTableSettings(**sm.params.table)
start = time.perf_counter()
table = build_kinematic_table(s.n_eta, s.n_q, tol=s.tol, rtol=s.rtol, atol=s.atol, progress=log.info)
wall = time.perf_counter() - start
save_kinematic_table(
    table, sm.output[0], wall_time_s=wall, contactalpha_version=__version__, git_commit=git_commit()
)
log.info(f"kinematic table built in {wall:.1f} s: {sm.output[0]}")
