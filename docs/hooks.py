"""MkDocs hooks: show the figures of a workflow run on the site when they exist.

``results/figures/`` is made by ``snakemake -c2`` and is not committed, so a page cannot link
to it directly (``mkdocs build --strict`` would fail on a clean clone).  A page names a figure
with a line ``<!-- figure: NAME | caption -->``; when ``results/figures/NAME.png`` exists the
hook copies it into the site as ``figures/NAME.png`` and puts the image and its caption in place
of the line, otherwise a note saying how to build it.
"""

import re
from pathlib import Path

from mkdocs.structure.files import File

# The run's figures, relative to the project root (the folder holding mkdocs.yml).
FIGURES = Path("results") / "figures"
# Where the figures land in the site.
SITE_FOLDER = "figures"
MARKER = re.compile(r"^<!-- figure: *([\w.\-]+) *\| *(.+?) *-->$", re.MULTILINE)


def _root(config):
    return Path(config["config_file_path"]).parent


def on_files(files, config):
    """Add every PNG of ``results/figures/`` to the site (none on a clean clone)."""
    folder = _root(config) / FIGURES
    for png in sorted(folder.glob("*.png")) if folder.is_dir() else []:
        files.append(File.generated(config, f"{SITE_FOLDER}/{png.name}", abs_src_path=str(png)))
    return files


def figure_markdown(name, caption, available, depth):
    """The Markdown that replaces one figure marker on a page ``depth`` folders below docs/."""
    if available:
        return f"![{caption}]({'../' * depth}{SITE_FOLDER}/{name}.png)\n\n*{caption}*"
    return (
        f'!!! note "Figure not built: {name}"\n'
        f"    {caption}. Run `snakemake -c2`, then `mkdocs build`, to see it here "
        f"(`results/figures/{name}.png`)."
    )


def on_page_markdown(markdown, page, config, files):
    """Replace each figure marker with the figure or a note."""
    folder = _root(config) / FIGURES
    depth = page.file.src_uri.count("/")

    def replace(match):
        name, caption = match.group(1), match.group(2)
        return figure_markdown(name, caption, (folder / f"{name}.png").is_file(), depth)

    return MARKER.sub(replace, markdown)
