"""The site as a reader sees it: built, then opened in headless Chromium at 1,280 px.

The home page and every engine page are opened in a real browser (Debian's ``chromium``; CI
installs it, see .ci/run).  A script injected into a copy of each page (tests/docs_browser_check.js)
reports, after the page and its math have rendered:

- a formula left as raw TeX (TeX in the text, or an ``arithmatex`` element with no KaTeX in it);
- a code block whose content is wider than its box;
- an image that did not load, and every internal link (checked here: the file and its anchor);
- on an engine page, whether it shows a figure of the workflow (``figures/...png``).

Screenshots of the pages go to ``results/docs-browser/`` (not committed; CI keeps them).  The
engine pages' figures come from the workflow (``snakemake -c2 docs_figures``, run here when one
is missing), as on a site built after a run.
"""

import base64
import html as html_lib
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest

ROOT = Path(__file__).resolve().parents[1]
CHECK_JS = Path(__file__).with_name("docs_browser_check.js")
SHOTS = ROOT / "results" / "docs-browser"
WIDTH = 1280
# Pages opened: the home page and every engine page (source path -> needs a workflow figure).
# Engine pages still without a figure of their own, with the reason (each is open work, not a pass).
NO_FIGURE_YET: dict[str, str] = {}
PAGES = {"index.md": False} | {
    f"engines/{p.name}": f"engines/{p.name}" not in NO_FIGURE_YET
    for p in sorted((ROOT / "docs" / "engines").glob("*.md"))
}
# A 1 x 1 PNG.
PIXEL = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg=="
MARK = re.compile(r'<pre id="ca-browser-check">(.*?)</pre>', re.S)


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    reason = "no Chromium (apt-get install -y chromium)"
    if os.environ.get("CI") == "true":
        pytest.fail(f"CI=true: {reason}")
    pytest.skip(reason)


def _browser(chromium, *args):
    base = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--no-first-run", "--allow-file-access-from-files"]  # fmt: skip
    return subprocess.run([*base, *args], capture_output=True, text=True, timeout=120)


def html_of(site, source):
    """The built HTML file of a page's Markdown source (directory URLs)."""
    stem = source[: -len(".md")]
    return site / "index.html" if stem == "index" else site / stem.removesuffix("/index") / "index.html"


def inspect(chromium, html):
    """Open a copy of ``html`` with the check script in Chromium; the script's report (a dict)."""
    probe = html.with_name("_probe.html")
    script = f"<script>{CHECK_JS.read_text(encoding='utf-8')}</script>"
    probe.write_text(
        html.read_text(encoding="utf-8").replace("</body>", script + "</body>"), encoding="utf-8"
    )
    try:
        run = _browser(chromium, f"--window-size={WIDTH},1000", "--virtual-time-budget=8000", "--dump-dom",
                       probe.as_uri())  # fmt: skip
    finally:
        probe.unlink()
    found = MARK.search(run.stdout)
    assert found, f"no report from Chromium for {html}: {run.stderr[-1500:]}"
    return json.loads(html_lib.unescape(found.group(1)))


def _link_problem(site, href, html):
    url = urlparse(href)
    target = Path(unquote(url.path))
    if target == html.with_name("_probe.html"):
        target = html
    if target.is_dir():
        target = target / "index.html"
    if not target.is_file():
        return f"broken link {href}"
    if url.fragment and target.suffix == ".html":
        ids = re.findall(r"\bid=[\"']([^\"']+)[\"']", target.read_text(encoding="utf-8"))
        if unquote(url.fragment) not in ids:
            return f"broken anchor {href}"
    return None


def problems(site, html, report, needs_figure):
    """What the reader would see wrong on one page, as sentences (empty: the page is fine)."""
    out = []
    math = report["math"]
    out += [f"raw TeX: {text!r}" for text in math["raw_tex"]]
    out += [f"unrendered formula: {text!r}" for text in math["unrendered"]]
    out += [
        f"code wider than its box ({w['content']} > {w['box']} px): {w['line']!r}"
        for w in report["wide_code"]
    ]
    out += [f"broken image {src}" for src in report["broken_images"]]
    out += filter(None, (_link_problem(site, href, html) for href in sorted(set(report["links"]))))
    # a workflow run's figure (figures/), or one a benchmark script draws and the docs ship (assets/)
    if needs_figure and not any("/figures/" in src or "/assets/" in src for src in report["images"]):
        out.append("no figure of the workflow on this engine page")
    return out


def screenshot(chromium, html, name):
    """A 1,280-px-wide screenshot of the page under results/docs-browser/."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    path = SHOTS / f"{name.replace('/', '_').removesuffix('.md')}.png"
    _browser(chromium, f"--window-size={WIDTH},2400", "--virtual-time-budget=8000", f"--screenshot={path}",
             html.as_uri())  # fmt: skip
    return path


def test_the_checks_catch_raw_tex_wide_code_and_broken_links(tmp_path):
    """On a hand-made page every check fires; on its fixed version none does."""
    chromium = _chromium()
    (tmp_path / "ok.png").write_bytes(base64.b64decode(PIXEL))
    bad = tmp_path / "bad.html"
    bad.write_text(
        "<html><head><style>pre { width: 600px } pre > code { display: block; overflow: auto }</style></head>"
        "<body><article><p><code>F = k δ^{3/2}</code></p>"
        f"<pre><code>{'x' * 400}</code></pre><img src='missing.png'>"
        "<a href='nowhere.html'>x</a><a href='bad.html#nope'>y</a></article></body></html>",
        encoding="utf-8",
    )
    found = problems(tmp_path, bad, inspect(chromium, bad), True)
    assert [p.split(" ")[0] for p in found] == ["raw", "code", "broken", "broken", "broken", "no"]
    good = tmp_path / "good.html"
    good.write_text(
        "<html><body><article><p id='here'>F = k δ</p><pre><code>short</code></pre>"
        "<img src='figures/../ok.png'><a href='good.html#here'>x</a></article></body></html>",
        encoding="utf-8",
    )
    (tmp_path / "figures").mkdir()
    assert problems(tmp_path, good, inspect(chromium, good), False) == []


def _figures():
    """Make the engine pages' figures with the workflow when one is missing (this checkout's results/)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run(
        [sys.executable, "-m", "snakemake", "-c2", "docs_figures"], cwd=ROOT, env=env, capture_output=True,
        text=True,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]


@pytest.mark.integration
def test_home_and_engine_pages_render_in_chromium(tmp_path):
    """Math typeset, no code cut off, links and images whole, a figure on every engine page."""
    chromium = _chromium()
    pytest.importorskip("mkdocs")
    _figures()
    site = tmp_path / "site"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    build = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(site)], cwd=ROOT,
                           env=env, capture_output=True, text=True)  # fmt: skip
    assert build.returncode == 0, build.stderr[-3000:]
    found = {}
    for source, needs_figure in PAGES.items():
        html = html_of(site, source)
        report = inspect(chromium, html)
        assert report["width"] == WIDTH
        screenshot(chromium, html, source)
        found[source] = problems(site, html, report, needs_figure)
    assert {page: p for page, p in found.items() if p} == {}
