"""The advisor's cost model is the documented one (issue 34: its constants could change unnoticed)."""

import re
from pathlib import Path

from contactalpha.scene import advisor

DOC = Path(__file__).parents[2] / "docs" / "advisor.md"


def test_the_libm_weight_and_the_tie_factor_are_the_documented_ones():
    text = " ".join(DOC.read_text().split())
    libm = re.search(r"counts as (\d+) operations", text)
    tie = re.search(r"within ([\d.]+)× of its cost", text)
    assert libm and int(libm.group(1)) == advisor.LIBM_OPS == 20
    assert tie and float(tie.group(1)) == advisor.COST_TIE == 1.5


def test_each_models_cost_is_its_counted_operations():
    # (libm calls, arithmetic operations) per evaluation, counted from each model's formula.
    counted = {
        "hunt_crossley": (0, 2),
        "lankarani_nikravesh": (0, 3),
        "flores": (0, 3),
        "hu_guo": (0, 3),
        "gonthier": (0, 3),
        "shen_zero_load": (1, 3),
        "exact_unloaded": (1, 30),
        "exact": (5, 150),
        "shen_published": (9, 30),
        "shen_refit": (9, 30),
        "closed_form": (20, 80),
        "exact_solve": (0, 5 * 80 * 12 * 40),
    }
    assert advisor.COST_MODEL == {name: 20 * libm + ops for name, (libm, ops) in counted.items()}
    # The ranking the advice rests on: formulas, then the table, then the closed form, then a solve.
    cost = advisor.COST_MODEL
    ranked = ("hunt_crossley", "shen_zero_load", "exact", "closed_form", "exact_solve")
    assert [cost[name] for name in ranked] == sorted(cost[name] for name in ranked)
