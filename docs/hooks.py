"""MkDocs hooks: show the figures and reports of a workflow run on the site when they exist.

``results/`` is made by ``snakemake -c2`` and is not committed, so a page cannot link to it
directly (``mkdocs build --strict`` would fail on a clean clone).  Instead a page names

- a figure with a line ``<!-- figure: NAME | caption -->``: when ``results/figures/NAME.png``
  exists the hook copies it into the site as ``figures/NAME.png`` and puts the image and its
  caption in place of the line;
- a generated report with a line ``<!-- result: PATH | what it is -->`` (PATH under
  ``results/``, a Markdown file): its text goes in place of the line, headings two levels down;

and otherwise the line becomes a note saying how to build the file.

Engine pages: every ``docs/engines/*.md`` that ``mkdocs.yml`` does not list yet is added to the
"Engines" section of the navigation, titled by its first heading, so a new engine's how-to
appears without editing the navigation.
"""

import re
from pathlib import Path

from mkdocs.structure.files import File

# The run's figures, relative to the project root (the folder holding mkdocs.yml).
FIGURES = Path("results") / "figures"
# Where the figures land in the site.
SITE_FOLDER = "figures"
FIGURE = re.compile(r"^<!-- figure: *([\w.\-]+) *\| *(.+?) *-->$", re.MULTILINE)
RESULT = re.compile(r"^<!-- result: *(results/[\w./\-]+\.md) *\| *(.+?) *-->$", re.MULTILINE)
# Levels a report's headings move down, below the page's own section headings.
HEADING_SHIFT = 2


def _root(config):
    return Path(config["config_file_path"]).parent


ENGINES_SECTION = "Engines"
ENGINES_FOLDER = "engines"


def _listed(nav):
    """Every page path named anywhere in a (nested) nav list."""
    for item in nav:
        value = next(iter(item.values())) if isinstance(item, dict) else item
        if isinstance(value, list):
            yield from _listed(value)
        else:
            yield value


def _title(page):
    heading = re.search(r"^# +(.+?) *$", page.read_text(encoding="utf-8"), re.MULTILINE)
    return heading.group(1) if heading else page.stem


def on_config(config):
    """Add engine how-to pages missing from the navigation to its "Engines" section."""
    nav = config["nav"] or []
    section = next(
        (item[ENGINES_SECTION] for item in nav if isinstance(item, dict) and ENGINES_SECTION in item), None
    )
    if section is None:
        return config
    listed = set(_listed(nav))
    for page in sorted((Path(config["docs_dir"]) / ENGINES_FOLDER).glob("*.md")):
        path = f"{ENGINES_FOLDER}/{page.name}"
        if path not in listed:
            section.append({_title(page): path})
    return config


def on_files(files, config):
    """Add every PNG of ``results/figures/`` to the site (none on a clean clone)."""
    folder = _root(config) / FIGURES
    for png in sorted(folder.glob("*.png")) if folder.is_dir() else []:
        files.append(File.generated(config, f"{SITE_FOLDER}/{png.name}", abs_src_path=str(png)))
    return files


def _missing(what, path):
    return (
        f'!!! note "Not built yet: {path}"\n'
        f"    {what}. Run `snakemake -c2`, then `mkdocs build`, to see it here."
    )


def figure_markdown(name, caption, available, depth):
    """The Markdown that replaces one figure marker on a page ``depth`` folders below docs/."""
    if available:
        return f"![{caption}]({'../' * depth}{SITE_FOLDER}/{name}.png)\n\n*{caption}*"
    return _missing(caption, f"results/figures/{name}.png")


def result_markdown(text):
    """A report's Markdown with its headings moved ``HEADING_SHIFT`` levels down."""
    return re.sub(
        r"^(#{1,6}) ", lambda m: "#" * min(6, len(m.group(1)) + HEADING_SHIFT) + " ", text, flags=re.M
    )


def on_page_markdown(markdown, page, config, files):
    """Replace each figure and result marker with the file's content or a note."""
    root = _root(config)
    depth = page.file.src_uri.count("/")

    def figure(match):
        name, caption = match.group(1), match.group(2)
        return figure_markdown(name, caption, (root / FIGURES / f"{name}.png").is_file(), depth)

    def result(match):
        path, what = match.group(1), match.group(2)
        file = root / path
        return result_markdown(file.read_text(encoding="utf-8")) if file.is_file() else _missing(what, path)

    return RESULT.sub(result, FIGURE.sub(figure, markdown))
