"""The bench's thread scaling says how many cores its 2-thread run had (issue 29, also).

It reported "0.64 s on 1 thread and 0.64 s on 2 (speed-up 1.00)" where the library scales
(20,000 solves: 3.45 s -> 1.88 s called directly): its 2-thread run had one core.  Each timing now
carries its CPU time, so the cores it kept busy are measured, and the report says when the
speed-up is the machine's rather than the library's.
"""

import pytest

from contactalpha.paper.bench.report import thread_cores_note
from contactalpha.paper.bench.workprecision import CORES_FREE_MIN, thread_timing


def test_thread_timing_measures_the_cores_each_run_kept_busy():
    rows = thread_timing(400, repeats=1)
    assert [r["threads"] for r in rows] == [1, 2] == [r["numba_threads"] for r in rows]
    for r in rows:
        assert r["seconds"] > 0 and r["cpu_seconds"] > 0
        assert r["cores_busy"] == pytest.approx(r["cpu_seconds"] / r["seconds"], rel=1e-12)
        assert r["cores_free"] == (r["cores_busy"] >= CORES_FREE_MIN * r["threads"])
        assert len(r["load_average"]) == 3 and r["affinity"] >= 1


@pytest.mark.parametrize("busy, free", [(1.02, False), (1.93, True)])
def test_the_report_says_when_the_second_core_was_not_free(busy, free):
    row = {"threads": 2, "cores_busy": busy, "cores_free": free, "load_average": [3.5, 3.0, 2.0]}
    note = thread_cores_note(row)
    assert f"kept {busy:.2f} cores busy, load average 3.5, 3.0, 2.0" in note
    assert ("did not get its second core" in note) == (not free)
