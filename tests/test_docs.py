"""The documentation site builds with warnings as errors (issue 22 point 4).

This test builds it WITHOUT executing the gallery (``-D plot_gallery=0``): the user guide, the
API reference from every public docstring, and the gallery's pages with their code. The full
build, which runs the twelve examples and takes a few minutes, is ``bash docs/build.sh``. The
user guide's ``>>>`` examples run here as doctests (and with Sphinx's ``doctest`` builder in
the script).
"""

import doctest
import importlib.util
import os
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
        "-D",
        "plot_gallery=0",
        "-j",
        "2",
        str(ROOT / "docs"),
        str(out),
    ]
    return subprocess.run(
        command, cwd=ROOT, env=env, capture_output=True, text=True, timeout=600, check=False
    )


@pytest.mark.slow  # about 1-2 min on 2 cores: every public docstring is read
def test_the_site_builds_without_warnings(tmp_path):
    done = _sphinx("html", tmp_path / "html")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-6000:]
    html = tmp_path / "html"
    for page in (
        "index.html",
        "guide/parameter-sets.html",
        "auto_examples/index.html",
        "api/rollerrig.rig.library.html",
        "api/rollerrig.contact.hertz.html",
    ):
        assert (html / page).is_file(), page
    examples = sorted((html / "auto_examples").glob("plot_*.html"))
    assert len(examples) >= 12
    assert "hertz_contact" in (html / "api" / "rollerrig.contact.hertz.html").read_text("utf-8")


@pytest.mark.parametrize("page", sorted((ROOT / "docs" / "guide").glob("*.rst")), ids=str)
def test_the_user_guide_doctests_pass(page):
    failed, _ = doctest.testfile(str(page), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert failed == 0, page.name
