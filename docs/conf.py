"""Sphinx configuration of the rollerrig documentation.

Build: ``bash docs/build.sh`` (the executed gallery), or without running the examples
``python -m sphinx -W --keep-going -D plot_gallery=0 docs docs/_build/html``.

The API reference is written at each build from the package itself (:mod:`docs._api`): one
page per public package, one per public module, every name of the module's ``__all__``
documented from its numpydoc docstring.
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

os.environ.setdefault("MPLBACKEND", "Agg")

from _api import write_api_pages  # noqa: E402

import rollerrig  # noqa: E402

project = "rollerrig"
author = "rollerrig developers"
copyright = "rollerrig developers, BSD-3-Clause"
release = rollerrig.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.doctest",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

templates_path = ["_templates"]
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "auto_examples/*.ipynb"]
root_doc = "index"
language = "en"

# API reference: generated from the package's __all__ lists at each build.
write_api_pages(HERE / "api")
autosummary_generate = False  # the module pages document every name themselves
autodoc_default_options = {"members": False}
autodoc_typehints = "none"  # the numpydoc docstrings state types and units
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

# The executed gallery (sphinx-gallery): examples/plot_*.py, run at build time.
sphinx_gallery_conf = {
    "examples_dirs": str(HERE.parent / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": True,
    "remove_config_comments": True,
    "show_memory": False,
    "capture_repr": ("_repr_html_", "__repr__"),
    "matplotlib_animations": False,
    "reference_url": {"rollerrig": None},
    "min_reported_time": 1,
    # a warning an example raises reads "Category: message", without the build machine's path
    "reset_modules": ("matplotlib", "_gallery.plain_warnings"),
    # each figure also at twice the resolution: sharp on a high-density screen and when zoomed
    # into, where the small print of a multi-panel figure scaled to the page's width is read
    "image_srcset": ["2x"],
}

html_theme = "pydata_sphinx_theme"
html_title = f"rollerrig {release}"
html_static_path = ["_static"]
html_css_files = ["rollerrig.css"]
html_favicon = "_static/favicon.svg"  # a browser asks for /favicon.ico otherwise: a 404
_GALLERY_PAGES = [
    "index",
    "sg_execution_times",
    *sorted(p.stem for p in (Path(__file__).parent.parent / "examples").glob("plot_*.py")),
]
html_theme_options = {
    "navigation_with_keys": False,
    # the left sidebar shows the current section only: the theme renders each page's navigation
    # from the whole tree otherwise, which took a fifth of the build with 230 pages
    "collapse_navigation": True,
    "navigation_depth": 2,
    "show_toc_level": 2,
    "navbar_align": "left",
    "header_links_before_dropdown": 6,
    # the gallery's code needs the width; the API and guide pages keep their table of contents
    # (exact page names, not a second wildcard: a page matching two patterns is a warning)
    "secondary_sidebar_items": {
        "**": ["page-toc", "sourcelink"],
        **{f"auto_examples/{page}": [] for page in _GALLERY_PAGES},
    },
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_show_sourcelink = True
# the theme's colour mode on a first visit; without it the theme logs an error to the console
# ("Got invalid theme mode") and falls back to auto
html_context = {"default_mode": "auto"}
html_sidebars = {"index": [], "install": []}

# Doctests of the user guide (python -m sphinx -b doctest docs docs/_build/doctest).
doctest_global_setup = "import numpy as np\nimport rollerrig as rr\n"

# numpydoc renames the citations of a References section; a docstring that cites a reference
# listed elsewhere (its module's docstring) leaves the citation without a target.
suppress_warnings = ["ref.citation"]

_BAR = re.compile(r"(?<!\\)\|")
_CITE = re.compile(r"\[(\d+)\]_")


def _plain_docstring(app, what, name, obj, options, lines):
    """Docstrings are written for ``help()``: ``|w|`` is an absolute value, not a
    substitution; a cited ``[4]_`` listed in another docstring is plain text here; a constant
    without a docstring of its own does not show its type's (``int``, ``ndarray``)."""
    if what in ("data", "attribute") and obj is not None:
        own = [x.strip() for x in (type(obj).__doc__ or "").splitlines() if x.strip()][1:12]
        mine = {x.strip() for x in lines if x.strip()}
        if own and sum(x in mine for x in own) >= min(3, len(own)):
            lines[:] = []
            return
    text = "\n".join(lines)
    defined = set(re.findall(r"^\s*\.\. \[(\d+)\]", text, re.MULTILINE))
    defined |= set(re.findall(r"^\s*\[(\d+)\]\s", text, re.MULTILINE))
    for i, line in enumerate(lines):
        stripped = line.strip()
        if stripped[:1] in "|+" and stripped[-1:] in "|+" and len(stripped) > 1:
            continue  # grid tables
        line = _BAR.sub(r"\|", line)
        lines[i] = _CITE.sub(
            lambda m: m.group(0) if m.group(1) in defined else f"[{m.group(1)}]", line
        )


_CDN_SCRIPTS = re.compile(r"^  \.\. raw:: html\n(?:\n|    .*\n)*", re.MULTILINE)


def _no_cdn_scripts(app, docname, source):
    """sphinx-gallery's computation-times pages load jQuery and DataTables from CDNs to make
    their table sortable: offline (or behind a proxy) that is three failed requests and an
    uncaught ``$ is not defined``, and online a request to third parties from every visit. The
    table is written sorted by time already; it stays, plain."""
    if docname == "sg_execution_times" or docname.endswith("/sg_execution_times"):
        source[0] = _CDN_SCRIPTS.sub("", source[0])


def _compile_numpydoc_template_once() -> None:
    """numpydoc (1.x) compiles its docstring template again for every object it renders:
    ``docscrape_sphinx.get_doc_object`` makes a new jinja environment on each call. That was
    about 3 000 compilations and a quarter of the site's build time. The template depends only
    on the builder, so compile it once per builder and hand it to numpydoc's own renderer."""
    import numpydoc.docscrape_sphinx as scrape
    import numpydoc.numpydoc as mangle

    render = getattr(scrape, "get_doc_object_orig", None)
    if render is None or mangle.get_doc_object is not scrape.get_doc_object:
        return  # another numpydoc: leave it as it is

    # numpydoc's signature hook passes no builder: its template (from the files, not the
    # builder's loader) is compiled once too; it was 1 365 compilations, 12 % of the build
    # (the site without the gallery, one core: 73 -> 64 s).
    without_builder = {}

    def get_doc_object(obj, what=None, doc=None, config=None, builder=None):
        config = {} if config is None else config
        holder = without_builder if builder is None else builder.__dict__
        template = holder.get("_numpydoc_template")
        if template is None:
            scrape.get_doc_object(None, "object", "", config, builder)  # compiles it, once
            template = holder["_numpydoc_template"] = config["template"]
        config["template"] = template
        return render(
            obj,
            what=what,
            doc=doc,
            config=config,
            class_doc=scrape.SphinxClassDoc,
            func_doc=scrape.SphinxFunctionDoc,
            obj_doc=scrape.SphinxObjDoc,
        )

    mangle.get_doc_object = get_doc_object


def setup(app):
    _compile_numpydoc_template_once()
    app.connect("autodoc-process-docstring", _plain_docstring, priority=400)  # before numpydoc
    app.connect("source-read", _no_cdn_scripts)
