"""mkdocs hook (mkdocs.yml names this file under `hooks:`).

The generated pages are plain Markdown that also reads well on a code host; what only the site needs
(the project's own pages, a stylesheet for the wide tables) is added here, at build time, rather
than written into generated/docs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from regmap.render import environment

if TYPE_CHECKING:
    from mkdocs.config.defaults import MkDocsConfig
    from mkdocs.structure.files import Files as MkDocsFiles

SITE_CSS = "css/regmap.css"


def on_config(config: MkDocsConfig) -> MkDocsConfig:
    """mkdocs hook: load the stylesheet `on_files` adds."""
    if SITE_CSS not in config.extra_css:
        config.extra_css.append(SITE_CSS)
    return config


def on_files(files: MkDocsFiles, config: MkDocsConfig) -> MkDocsFiles:
    """mkdocs hook: add the project's own pages (docs/*.md beside mkdocs.yml, the map format) and
    the stylesheet to the site whose pages `regmap generate` wrote."""
    from pathlib import Path

    from mkdocs.exceptions import PluginError
    from mkdocs.structure.files import File

    project_docs = Path(config.config_file_path).parent / "docs"
    for path in sorted(project_docs.glob("*.md")):
        if files.get_file_from_path(path.name) is not None:
            raise PluginError(f"docs/{path.name} and a generated page have the same name")
        files.append(File.generated(config, path.name, abs_src_path=str(path)))
    files.append(File.generated(config, SITE_CSS, content=environment().get_template("docs/regmap.css.jinja").render()))
    return files
