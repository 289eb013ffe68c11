"""The README's contract: its two commands near the top, and links that lead somewhere.

The README is the two commands and a pointer (issue 22); what it pointed to before (the tour,
the notebook block, the nomenclature) is in the user guide, ``docs/guide/``, whose notebook
block runs in ``tests/test_docs.py``.
"""

from __future__ import annotations

import re
from pathlib import Path
from urllib.parse import unquote, urlsplit

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
COMMANDS = [
    'python -m pip install ".[all]" && rollerrig demo --out rollerrig-output',
    'python -m pip install ".[test]" && python -m pytest',
]


def _fences(text: str) -> list[tuple[str, str, int]]:
    """``(language, body, line)`` of every fenced block of a Markdown text."""
    return [
        (m.group(1), m.group(2).strip(), text.count("\n", 0, m.start()) + 1)
        for m in re.finditer(r"^```(\w*)\n(.*?)^```", text, flags=re.S | re.M)
    ]


def test_the_readme_holds_exactly_the_two_commands_near_the_top():
    text = README.read_text(encoding="utf-8")
    fences = _fences(text)
    assert [lang for lang, _, _ in fences] == ["bash", "bash"], fences
    assert [body for _, body, _ in fences] == COMMANDS
    first_heading = text.index("\n## ") if "\n## " in text else len(text)
    for _, _, line in fences:
        assert line < 20, f"a command block starts at line {line}: near the top, please"
    assert text.index("```bash") < first_heading


def test_every_relative_link_of_the_readme_leads_to_a_file():
    text = README.read_text(encoding="utf-8")
    links = re.findall(r"\]\(([^)\s]+)\)", text) + re.findall(r'(?:src|href)="([^"]+)"', text)
    assert links, "the README points to the user guide's pages"
    broken = []
    for link in links:
        parts = urlsplit(link)
        if parts.scheme or parts.netloc or not parts.path:
            continue
        if not (ROOT / unquote(parts.path)).exists():
            broken.append(link)
    assert not broken


def test_the_readme_points_to_the_guide_pages_that_hold_what_it_held():
    text = README.read_text(encoding="utf-8")
    for page in ("tour", "notebook", "nomenclature", "seed-corrections", "recordings"):
        assert f"(docs/guide/{page}.rst)" in text, page
    assert "bash docs/build.sh" in text
    assert 'python -m pip install ".[docs]"' in text


def test_top_level_names_resolve():
    import rollerrig

    missing = [name for name in rollerrig.__all__ if not hasattr(rollerrig, name)]
    assert not missing
