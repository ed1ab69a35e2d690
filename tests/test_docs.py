"""The README and the docs pages: every example runs, and the site builds strictly.

Every ```python block of README.md and docs/**/*.md runs, in order, in one namespace per page.
Every `contactalpha ...` command line of a ```console or ```bash block runs through the CLI's
``main(argv)`` and must exit 0; in a console block, the lines that follow a `$ contactalpha`
command (up to the next `$` line) are its output, and must be what the command prints.
A command may go on over several lines, each but the last ending in `\\`.
A block directly below a line `<!-- no-run: reason -->` is left out; one below
`<!-- requires: module -->` runs only where that module imports (under CI=true a missing
module fails, as for the engines' tests).  A block in an engine's own format (MJCF, SDF, URDF,
.osim XML) below a line `<!-- file: NAME -->` is written to NAME in the page's working folder,
where the page's later Python blocks load it into the engine and check what it delivers.
"""

import contextlib
import importlib
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from contactalpha.cli import main

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
FENCE = re.compile(r"^( *)```(\w*)\s*$")  # indented: a block inside a list item
NO_RUN = re.compile(r"^<!-- no-run: .+ -->$")
REQUIRES = re.compile(r"^<!-- requires: ([\w.]+) -->$")
FILE = re.compile(r"^<!-- file: ([\w.\-]+) -->$")
SHELL_LANGS = ("console", "bash", "sh", "shell")
PROMPT = "$ "


@dataclass(frozen=True)
class Block:
    """One fenced code block of a page."""

    lang: str
    text: str
    line: int  # 1-based line of the opening fence
    skip: bool  # below a no-run marker
    requires: str | None  # below a requires marker
    file: str | None = None  # below a file marker: written to this name, not run


def code_blocks(markdown):
    """The fenced blocks of ``markdown``, with the marker on the line directly above each."""
    lines = markdown.splitlines()
    blocks, i = [], 0
    while i < len(lines):
        match = FENCE.match(lines[i])
        if not match:
            i += 1
            continue
        start, above = i, lines[i - 1].strip() if i else ""
        i += 1
        indent = len(match.group(1))
        while i < len(lines) and lines[i].strip() != "```":
            i += 1
        if i == len(lines):
            raise ValueError(f"code block opened on line {start + 1} is never closed")
        requires, file = REQUIRES.match(above), FILE.match(above)
        blocks.append(
            Block(
                match.group(2),
                "\n".join(line[indent:] for line in lines[start + 1 : i]) + "\n",
                start + 1,
                bool(NO_RUN.match(above)),
                requires.group(1) if requires else None,
                file.group(1) if file else None,
            )
        )
        i += 1
    return blocks


def _joined(text):
    """The lines of a shell block with each `\\` continuation joined to the line it ends."""
    lines = []
    for line in text.splitlines():
        if lines and lines[-1].endswith("\\"):
            lines[-1] = lines[-1][:-1].rstrip() + " " + line.strip()
        else:
            lines.append(line)
    return lines


def cli_commands(block):
    """``(argv, expected output or None)`` of each `contactalpha` command line of a shell block."""
    commands, lines = [], _joined(block.text)
    prompted = block.lang == "console"
    for k, line in enumerate(lines):
        text = line[len(PROMPT) :] if prompted and line.startswith(PROMPT) else line
        if prompted and not line.startswith(PROMPT):
            continue  # output of the command above
        argv = shlex.split(text, comments=True)
        if not argv or argv[0] != "contactalpha":
            continue
        expected = None
        if prompted:
            out = []
            for follow in lines[k + 1 :]:
                if follow.startswith(PROMPT):
                    break
                out.append(follow)
            expected = "\n".join(out).strip("\n") or None
        commands.append((argv[1:], expected))
    return commands


def _run_cli(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as stop:
            status = stop.code
    sys.stderr.write(err.getvalue())
    return status, out.getvalue(), err.getvalue()


def _engine_modules():
    """Top-level modules of the registered engines (optional: ``pip install -e ".[engines]"``)."""
    from contactalpha.adapters.registry import ADAPTERS

    return {a.module.split(".")[0] for a in ADAPTERS}


def _missing_engine(err):
    """The optional engine whose absence raised ``err`` (an ImportError or its cause), else None."""
    while err is not None:
        name = (getattr(err, "name", None) or "").split(".")[0]
        if isinstance(err, ImportError) and name in _engine_modules():
            return name
        err = err.__cause__
    return None


def _skip_without_engine(name, where):
    """A page's example needs an engine that is not installed: skip, except under CI=true."""
    reason = f"{where} needs the optional engine {name!r}, which is not installed"
    if os.environ.get("CI") == "true":
        pytest.fail(f"CI=true: {reason}")
    pytest.skip(reason)


def _module_available(name):
    try:
        importlib.import_module(name)
    except ImportError as err:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true: a docs block requires {name!r}, which does not import ({err})")
        return False
    return True


def run_page(path, workdir):
    """Run the examples of one page; returns the number of blocks and command lines run."""
    namespace, ran = {"__name__": "__docs__"}, 0
    for block in code_blocks(Path(path).read_text(encoding="utf-8")):
        if block.skip or (block.requires and not _module_available(block.requires)):
            continue
        where = f"{path}:{block.line}"
        if block.file:
            (Path(workdir) / block.file).write_text(block.text, encoding="utf-8")
        elif block.lang == "python":
            with contextlib.chdir(workdir):
                try:
                    exec(compile(block.text, where, "exec"), namespace)  # noqa: S102
                except ImportError as err:
                    if _missing_engine(err) is None:
                        raise
                    _skip_without_engine(_missing_engine(err), where)
            ran += 1
        elif block.lang in SHELL_LANGS:
            for argv, expected in cli_commands(block):
                with contextlib.chdir(workdir):
                    status, out, err = _run_cli(argv)
                engine = next((m for m in _engine_modules() if f"No module named {m!r}" in err), None)
                if status != 0 and (engine or "is an optional engine" in err):
                    _skip_without_engine(engine or err.strip(), where)
                assert status == 0, f"{where}: `contactalpha {shlex.join(argv)}` exited {status}"
                if expected is not None:
                    assert out.strip("\n") == expected, f"{where}: the page shows another output"
                ran += 1
    return ran


# Modules whose blocks compile (JAX's XLA): a page with one runs with the integration tests.
COMPILING = ("jax",)


def _page_param(page):
    compiles = any(b.requires in COMPILING for b in code_blocks(page.read_text(encoding="utf-8")))
    return pytest.param(page, marks=pytest.mark.integration) if compiles else page


PAGE_PARAMS = [_page_param(p) for p in PAGES]


@pytest.mark.parametrize("page", PAGE_PARAMS, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_page_examples_run(page, tmp_path):
    run_page(page, tmp_path)


def test_readme_leads_with_the_one_call():
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 250
    first_screen = "\n".join(lines[:40])
    assert "ca.contact_parameters(" in first_screen
    assert "$ contactalpha params " in first_screen
    assert "pip install" in first_screen


def test_markers_skip_blocks_and_a_failing_example_fails(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- no-run: a demo -->\n```python\nraise RuntimeError\n```\n\n"
        "```python\nx = 2\n```\n\n```python\nassert x == 2\n```\n\n"
        "<!-- requires: no_such_module_anywhere -->\n```python\nraise RuntimeError\n```\n",
        encoding="utf-8",
    )
    if os.environ.get("CI") != "true":
        assert run_page(page, tmp_path) == 2
    page.write_text("```python\nassert 1 == 2\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError):
        run_page(page, tmp_path)


def test_command_lines_must_exit_0_and_print_what_the_page_shows(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("```console\n$ contactalpha alpha 2 0.1\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError, match="exited 2"):
        run_page(page, tmp_path)
    page.write_text("```console\n$ contactalpha impact 0 0\nnot this\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError, match="another output"):
        run_page(page, tmp_path)
    page.write_text("```bash\ncontactalpha export-c out   # a comment\n```\n", encoding="utf-8")
    assert run_page(page, tmp_path) == 1
    assert (tmp_path / "out" / "contactalpha.h").is_file()
    page.write_text("```console\n$ contactalpha alpha \\\n    0.5 0.1\nnot this\n```\n", encoding="utf-8")
    with pytest.raises(AssertionError, match="another output"):
        run_page(page, tmp_path)


def test_file_blocks_are_written_for_the_python_blocks_below(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- file: scene.xml -->\n```xml\n<mujoco/>\n```\n\n"
        "```python\nassert open('scene.xml').read() == '<mujoco/>\\n'\n```\n",
        encoding="utf-8",
    )
    assert run_page(page, tmp_path) == 1


def _mkdocs_or_skip():
    if importlib.util.find_spec("mkdocs") is None or shutil.which("mkdocs") is None:
        if os.environ.get("CI") == "true":
            pytest.fail('CI=true: mkdocs is not installed (pip install -e ".[docs]")')
        pytest.skip('mkdocs is not installed (pip install -e ".[docs]")')


def _build(root, site):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(site)],
        cwd=root,
        env=env,
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr[-3000:]


@pytest.mark.integration
def test_site_builds_strictly_on_a_clean_clone(tmp_path):
    """Only tracked files (no results/): every figure and report becomes a note, no warning."""
    _mkdocs_or_skip()
    tracked = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=ROOT,
        capture_output=True,
        check=True,
    ).stdout.split(b"\0")
    clone = tmp_path / "clone"
    for name in filter(None, tracked):
        src = ROOT / name.decode()
        if src.is_file():
            (clone / name.decode()).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, clone / name.decode())
    assert not (clone / "results" / "figures").exists()
    _build(clone, tmp_path / "site")
    page = (tmp_path / "site" / "reproduction" / "index.html").read_text(encoding="utf-8")
    assert "Not built yet: results/figures/fig4_alpha_surface.png" in page
    assert (tmp_path / "site" / "api" / "index.html").read_text(encoding="utf-8").count(
        "contact_parameters"
    ) > 1


@pytest.mark.integration
def test_site_builds_strictly_with_this_checkout_results(tmp_path):
    """With a run's results/ (if any), its figures are copied into the site and shown."""
    _mkdocs_or_skip()
    _build(ROOT, tmp_path / "site")
    figures = sorted((ROOT / "results" / "figures").glob("*.png"))
    for png in figures:
        assert (tmp_path / "site" / "figures" / png.name).read_bytes() == png.read_bytes()


def _hooks():
    _mkdocs_or_skip()
    spec = importlib.util.spec_from_file_location("docs_hooks", ROOT / "docs" / "hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_hooks_add_new_engine_pages_to_the_nav_and_show_figures_or_a_note(tmp_path):
    hooks = _hooks()
    (tmp_path / "engines").mkdir()
    for name, heading in (("opensim.md", "# OpenSim"), ("newton.md", "# Newton engine")):
        (tmp_path / "engines" / name).write_text(f"{heading}\n\ntext\n", encoding="utf-8")
    nav = [{"Home": "index.md"}, {"Engines": [{"OpenSim": "engines/opensim.md"}]}]
    hooks.on_config({"nav": nav, "docs_dir": str(tmp_path)})
    assert nav[1]["Engines"] == [{"OpenSim": "engines/opensim.md"}, {"Newton engine": "engines/newton.md"}]
    shown = hooks.figure_markdown("fig4", "the surface", True, 1)
    assert shown.startswith("![the surface](../figures/fig4.png)")
    assert "Not built yet: results/figures/fig4.png" in hooks.figure_markdown("fig4", "the surface", False, 0)
    assert hooks.result_markdown("# Title\n\n## Part\ntext # not a heading\n") == (
        "### Title\n\n#### Part\ntext # not a heading\n"
    )


@pytest.mark.parametrize(
    ("rules", "module"),
    [
        ("bench.smk", "contactalpha.paper.bench.report"),
        ("engines.smk", "contactalpha.studies.engines.report"),
    ],
)
def test_generated_blocks_have_their_markers_on_the_page_their_rule_fills(rules, module):
    text = (ROOT / "workflow" / "rules" / rules).read_text(encoding="utf-8")
    (page,) = re.findall(r'^\s+page="([^"]+)",$', text, re.M)
    report = importlib.import_module(module)
    body = (ROOT / page).read_text(encoding="utf-8")
    assert body.count(report.PAGE_START) == 1 and body.count(report.PAGE_END) == 1
    assert body.index(report.PAGE_START) < body.index(report.PAGE_END)
    assert report.PAGE_START not in (ROOT / "README.md").read_text(encoding="utf-8")


def test_an_example_that_needs_a_missing_engine_skips(tmp_path, monkeypatch):
    """Without an optional engine its examples skip (README's pytest); under CI=true they fail."""
    monkeypatch.setattr(sys.modules[__name__], "_engine_modules", lambda: {"no_such_engine_xyz"})
    page = tmp_path / "page.md"
    page.write_text("```python\nimport no_such_engine_xyz\n```\n", encoding="utf-8")
    monkeypatch.setenv("CI", "false")
    with pytest.raises(pytest.skip.Exception, match="no_such_engine_xyz"):
        run_page(page, tmp_path)
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="CI=true"):
        run_page(page, tmp_path)
    page.write_text("```python\nimport no_such_module_at_all\n```\n", encoding="utf-8")
    with pytest.raises(ImportError):  # any other missing module is a failure
        run_page(page, tmp_path)


def _nav_pages(items):
    """Every page path of a mkdocs ``nav`` (nested sections walked)."""
    for item in items:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        if isinstance(value, list):
            yield from _nav_pages(value)
        elif not str(value).startswith(("http://", "https://")):
            yield str(value)


def _nav():
    import yaml

    return yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))["nav"]


def test_every_docs_page_is_in_the_navigation():
    """A page outside the nav is built but unreachable from the site's menus: each is listed.

    The pages of docs/engines/ count as listed when docs/hooks.py's ``on_config`` adds them.
    """
    nav = list(_nav_pages(_nav()))
    docs = ROOT / "docs"
    missing_files = [page for page in nav if not (docs / page).is_file()]
    assert missing_files == []
    engines_section = [item for item in _nav() if isinstance(item, dict) and "Engines" in item]
    listed = set(nav)
    if engines_section:
        listed |= {f"engines/{p.name}" for p in (docs / "engines").glob("*.md")}  # the hook adds them
    pages = sorted(str(p.relative_to(docs)) for p in [*docs.glob("*.md"), *(docs / "engines").glob("*.md")])
    assert [page for page in pages if page not in listed] == []
