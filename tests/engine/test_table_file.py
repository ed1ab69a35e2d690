import os
import stat

import numpy as np

from contactalpha.engine.table import ARRAY_NAMES, load_table
from contactalpha.engine.table_build import save_table


def test_saved_table_is_readable_by_everyone_and_round_trips(tmp_path):
    shipped = load_table()
    path = save_table(shipped, tmp_path / "t.npz", note="copy")
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~mask  # not mkstemp's 0600
    assert [p.name for p in tmp_path.iterdir()] == ["t.npz"]
    again = load_table(path)
    assert again.meta == {**shipped.meta, "note": "copy"}
    for name in ARRAY_NAMES:
        assert np.array_equal(getattr(again, name), getattr(shipped, name))
