"""Ship a result with the package: copy it over the package's file (a maintainer's step).

Only `snakemake -c2 ship` (and its parts ship_fit, ship_table) runs this; the default run
never writes the package (issue 15, item 6).
Settings (snakemake.params): destination (the package file; config fit.package_coefficients
or models.package_table).
Inputs: source (the result to ship); any others (a passed check) only have to exist.
Outputs: a JSON record of what was copied where (sha256 of both, commit, time); the package
file itself is written atomically and is not a Snakemake output (Snakemake would delete a
tracked file before the job).
"""

from prefork import delegate

delegate()  # in the run's pre-imported process, if there is one (workflow/scripts/prefork.py)

import hashlib
from datetime import UTC, datetime
from pathlib import Path

from contactalpha.io import script_logger, write_atomic, write_json_atomic
from contactalpha.provenance import git_commit
from contactalpha.version import __version__

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("ship", sm.log[0])
source, destination = Path(sm.input.source), Path(sm.params.destination)
data = source.read_bytes()
before = hashlib.sha256(destination.read_bytes()).hexdigest() if destination.is_file() else None
write_atomic(destination, lambda tmp: Path(tmp).write_bytes(data))
record = {
    "source": str(source),
    "destination": str(destination),
    "sha256": hashlib.sha256(destination.read_bytes()).hexdigest(),
    "sha256_before": before,
    "git_commit": git_commit(),
    "contactalpha_version": __version__,
    "shipped": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
}
write_json_atomic(sm.output[0], record)
log.info(f"shipped {source} to {destination} ({'unchanged' if before == record['sha256'] else 'changed'})")
