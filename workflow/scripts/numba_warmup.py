"""Compile (cold cache) or load (warm cache) every numba kernel of the workflow, once.

Settings (snakemake.params): code_version (source hash; only makes an engine edit rerun it).
Wildcard: part (a key of contactalpha.warmup.PARTS: which kernel families this job warms).
Inputs: none.
Outputs: JSON with the seconds of each kernel family (contactalpha.warmup.ENTRY_POINTS),
their total, numba's version and cache folder, and the provenance every result carries.
"""

# No prefork.delegate(): the warm-up jobs are the run's first, and in their own
# processes they compile while the job server is still importing, instead of waiting for it.
import time

import numba

from contactalpha.io import script_logger, write_json_atomic
from contactalpha.provenance import result_attrs
from contactalpha.warmup import PARTS, warm_up

sm = snakemake  # noqa: F821  (injected by Snakemake)
log = script_logger("numba_warmup", sm.log[0])
t0 = time.perf_counter()
seconds = warm_up(PARTS[sm.wildcards.part], progress=lambda name, s: log.info(f"{name}: {s:.2f} s"))
total = time.perf_counter() - t0
log.info(f"{sm.wildcards.part} kernels ready in {total:.1f} s")
report = {
    **result_attrs({"code_version": sm.params.code_version, "part": sm.wildcards.part}, "numba_warmup"),
    "seconds": seconds,
    "total_seconds": total,
    "numba_version": numba.__version__,
    "numba_cache_dir": numba.config.CACHE_DIR or "(beside the package sources)",
}
write_json_atomic(sm.output[0], report)
