"""The documentation site builds with warnings as errors (issue 22 point 4).

This test builds the whole site as ``bash docs/build.sh`` does: the user guide, the API reference
from every public docstring, and the gallery with its examples EXECUTED (sphinx-gallery runs each
``examples/plot_*.py`` and fails the build, under ``-W``, when one raises), about 35 s of it on
2 cores. Then every internal link of the built pages is followed: each relative ``href`` and
``src`` must name a file of the site, and each ``#anchor`` an ``id`` on its page (Sphinx's ``-W``
catches broken cross-references, not links written as raw HTML or by the theme). The user
guide's ``>>>`` examples run here as doctests, and its notebook page's and tour's python blocks
as written. External links are not checked (CI has no network).
"""

import doctest
import html.parser
import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MISSING = [
    m
    for m in ("sphinx", "numpydoc", "sphinx_gallery", "pydata_sphinx_theme")
    if importlib.util.find_spec(m) is None
]

pytestmark = pytest.mark.skipif(
    bool(MISSING) or not (ROOT / "docs" / "conf.py").is_file(),
    reason=f"the docs extra is not installed (missing: {', '.join(MISSING)}): "
    'python -m pip install ".[docs]"',
)


def _fresh_sources(where: Path) -> Path:
    """A copy of ``docs/`` and ``examples/`` as a clean clone has them, under ``where``.

    Nothing a previous build generated is copied (the API pages, the gallery's pages and its
    checksums, the files the examples write): sphinx-gallery skips an example whose checksum is
    unchanged and keeps its old page, so a build in a used checkout could pass without running
    one. The build also leaves the checkout as it was.
    """
    generated = shutil.ignore_patterns("_build", "api", "auto_examples", "sg_execution_times.rst")
    shutil.copytree(ROOT / "docs", where / "docs", ignore=generated)
    (where / "examples").mkdir()
    for name in (
        "README.rst",
        "eurosprinter_engel1998.csv",
        *(p.name for p in (ROOT / "examples").glob("plot_*.py")),
    ):
        shutil.copy2(ROOT / "examples" / name, where / "examples" / name)
    return where / "docs"


def _sphinx(builder: str, out: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "MPLBACKEND": "Agg"}
    command = [
        sys.executable,
        "-m",
        "sphinx",
        "-W",
        "--keep-going",
        "-q",
        "-b",
        builder,
        "-j",
        "2",
        str(_fresh_sources(out.parent / "sources")),
        str(out),
    ]
    return subprocess.run(
        command, cwd=out.parent, env=env, capture_output=True, text=True, timeout=600, check=False
    )


class _Links(html.parser.HTMLParser):
    """The ``id``s of one page and the links it makes (``href`` and ``src``)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("id", "name") and value:
                self.ids.add(value)
            elif name in ("href", "src") and value:
                self.links.append(value)


def broken_internal_links(root: Path) -> list[str]:
    """``page: link`` for every relative link of the site under ``root`` that leads nowhere.

    A link leads nowhere when its file is not in the site, or its ``#fragment`` is no ``id``
    (or ``name``) of the page it names. Links with a scheme (``https:``, ``mailto:``, ``data:``)
    and protocol-relative ones are external and not followed. Files under ``_static/`` are
    the theme's assets (one is a Jinja template named ``.html``), not pages: they are not read.
    """
    from urllib.parse import unquote, urlsplit

    pages = {}
    for page in root.rglob("*.html"):
        if page.relative_to(root).parts[0] == "_static":
            continue
        parser = _Links()
        parser.feed(page.read_text("utf-8", errors="replace"))
        pages[page.resolve()] = parser
    broken = []
    for page, parser in pages.items():
        for link in parser.links:
            parts = urlsplit(link)
            if parts.scheme or parts.netloc or link.startswith("//"):
                continue
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(root.resolve())}: {link}")
            elif parts.fragment and target.suffix == ".html":
                ids = pages[target].ids if target in pages else set()
                if unquote(parts.fragment) not in ids:
                    broken.append(f"{page.relative_to(root.resolve())}: {link}")
    return sorted(set(broken))


def test_the_link_checker_finds_a_missing_page_and_a_missing_anchor(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "index.html").write_text(
        '<a href="sub/a.html#here">ok</a><a href="sub/a.html#gone">x</a>'
        '<a href="missing.html">x</a><img src="img.png"><a href="https://example.org/x">ext</a>'
        '<a href="#top">top</a><p id="top"></p>',
        "utf-8",
    )
    (tmp_path / "sub" / "a.html").write_text(
        '<h1 id="here">a</h1><a href="../index.html">', "utf-8"
    )
    assert broken_internal_links(tmp_path) == [
        "index.html: img.png",
        "index.html: missing.html",
        "index.html: sub/a.html#gone",
    ]


@pytest.mark.slow  # about 2 min on 2 cores: every public docstring is read, the gallery runs
def test_the_site_builds_without_warnings(tmp_path):
    done = _sphinx("html", tmp_path / "html")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-6000:]
    html = tmp_path / "html"
    for page in (
        "index.html",
        "guide/parameter-sets.html",
        "guide/tour.html",
        "guide/notebook.html",
        "guide/nomenclature.html",
        "auto_examples/index.html",
        "api/rollerrig.rig.library.html",
        "api/rollerrig.contact.hertz.html",
    ):
        assert (html / page).is_file(), page
    examples = sorted((html / "auto_examples").glob("plot_*.html"))
    assert len(examples) >= 12
    assert "hertz_contact" in (html / "api" / "rollerrig.contact.hertz.html").read_text("utf-8")
    # The gallery ran: each example's page shows a figure it drew or the output it printed.
    for page in examples:
        text = page.read_text("utf-8")
        drawn = re.search(rf"sphx_glr_{page.stem}_\d+\.png", text)
        assert drawn or "sphx-glr-script-out" in text, f"{page.name}: was the example executed?"
    assert broken_internal_links(html) == []


@pytest.mark.parametrize("page", sorted((ROOT / "docs" / "guide").glob("*.rst")), ids=str)
def test_the_user_guide_doctests_pass(page):
    failed, _ = doctest.testfile(str(page), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert failed == 0, page.name


def python_blocks(page: Path) -> list[str]:
    """The ``.. code-block:: python`` blocks of a reStructuredText page, dedented."""
    import textwrap

    blocks = []
    for m in re.finditer(
        r"^\.\. code-block:: python\n((?:[ \t]+:[^\n]*\n)*)\n((?:(?:[ \t]+[^\n]*)?\n)+)",
        page.read_text("utf-8"),
        flags=re.M,
    ):
        blocks.append(textwrap.dedent(m.group(2)).strip() + "\n")
    return blocks


def test_python_blocks_are_read_whole():
    page = ROOT / "docs" / "guide" / "notebook.rst"
    (block,) = python_blocks(page)
    assert block.startswith("import rollerrig as rr\n")
    assert block.rstrip().endswith('source="two-releases.tdms")')
    compile(block, str(page), "exec")


@pytest.mark.slow
def test_the_notebook_block_runs(tmp_path, monkeypatch, capsys):
    page = ROOT / "docs" / "guide" / "notebook.rst"
    blocks = python_blocks(page)
    assert len(blocks) == 1, "the notebook page holds one python block"
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "notebook"}
    exec(compile(blocks[0], str(page), "exec"), namespace)
    printed = capsys.readouterr().out
    assert "ramp" in printed  # the analysis found the ramps of the simulated protocol
    assert (tmp_path / "two-releases.tdms").is_file()
    written = sorted(p.name for p in (tmp_path / "notebook-output").iterdir())
    assert "two-releases-analysis.json" in written
    assert "two-releases-report.html" in written
    # The block switches to wet friction before its last ramp: the fits keep the dry points
    # only, and say so (issue 23, point 2); the repr stays a few lines (point 8).
    result = namespace["result"]
    assert any("changes friction (dry from 0 s, wet from" in n for n in result.notes)
    assert result.recording.time[result.fit_points].max() < 6.04
    assert "'dry' set" in result.true_parameters_source
    assert len(repr(result).splitlines()) <= 8


def test_the_tours_python_block_runs(capsys):
    page = ROOT / "docs" / "guide" / "tour.rst"
    blocks = python_blocks(page)
    assert len(blocks) == 1, "the tour holds one python block (contact mechanics)"
    namespace = {"__name__": "tour"}
    exec(compile(blocks[0], str(page), "exec"), namespace)
    assert capsys.readouterr().out.count("\n") == 2
    creep, coa = namespace["curve"].peak
    assert 0 < creep < 0.1 and 0 < coa < 0.55
