"""mkdocs hook (mkdocs.yml names this file under `hooks:`).

The generated pages are plain Markdown that also reads well on a code host; what only the site needs
(the project's own pages, a stylesheet for the wide tables) is added here, at build time, rather
than written into generated/docs.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from regmap.render import templates

if TYPE_CHECKING:
    from mkdocs.config.defaults import MkDocsConfig
    from mkdocs.structure.files import Files as MkDocsFiles
    from mkdocs.structure.pages import Page

SITE_CSS = "css/regmap.css"
ST_README = "README.md"
_ST_LINK = re.compile(r"\]\(\.\./st/([a-z0-9_]+)/README\.md\)")


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
    # The Structured Text READMEs (generated/st/<device>/README.md) join the site as st/<device>.md.
    for readme in sorted((Path(config.docs_dir).parent / "st").glob(f"*/{ST_README}")):
        files.append(File.generated(config, f"st/{readme.parent.name}.md", abs_src_path=str(readme)))
    # By package name, not __name__: mkdocs loads this file by its path, as a module named `hook`.
    css = templates("regmap.backends.markdown").get_template("regmap.css.jinja").render()
    files.append(File.generated(config, SITE_CSS, content=css))
    return files


def on_page_markdown(markdown: str, page: Page, config: MkDocsConfig, files: MkDocsFiles) -> str:
    """mkdocs hook: the index links generated/st/<device>/README.md as a code host shows it; on the
    site that page is st/<device>.md (plain text where the ST tree was not generated)."""

    def link(match: re.Match[str]) -> str:
        return f"](st/{match[1]}.md)" if files.get_file_from_path(f"st/{match[1]}.md") is not None else "]"

    return _ST_LINK.sub(link, markdown)
