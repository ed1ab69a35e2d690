"""No figure carries its own "Fig. N" title: captions number figures, not the images."""

import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "contactalpha"
FIGURE_MODULES = sorted([*PACKAGE.glob("paper/*/figures.py"), *PACKAGE.glob("studies/*/figures.py")])
# Calls that put text into a figure.
TEXT_CALLS = {"set_title", "suptitle", "set", "text", "annotate", "set_xlabel", "set_ylabel", "legend"}
NUMBERED = re.compile(r"\bFig(ure)?\.? ?\d")


def _strings(node):
    return [n.value for n in ast.walk(node) if isinstance(n, ast.Constant) and isinstance(n.value, str)]


def numbered_titles(source):
    """Strings naming a figure number that are passed to a text-drawing call in ``source``."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr in TEXT_CALLS
        ):
            args = [*node.args, *(k.value for k in node.keywords)]
            found += [s for a in args for s in _strings(a) if NUMBERED.search(s)]
    return found


def test_the_check_finds_a_numbered_title():
    assert numbered_titles('ax.set(title="Fig. 6: s1")\nfig.suptitle(f"Fig. {n}: x")') == ["Fig. 6: s1"]
    assert numbered_titles('"""Fig. 9: a docstring."""\nax.set_title("(a) ξ = 0")') == []


@pytest.mark.parametrize("path", FIGURE_MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_figures_have_no_numbered_titles(path):
    assert numbered_titles(path.read_text(encoding="utf-8")) == []
