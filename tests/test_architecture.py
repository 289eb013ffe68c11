"""The package's layout as contracts (ARCHITECTURE.md): packages import only downwards (the
import-linter contract in pyproject.toml), and no package takes another package's private
names or modules."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

grimp = pytest.importorskip("grimp", reason="the test extra installs import-linter")


def test_packages_import_only_downwards(monkeypatch):
    from importlinter.cli import lint_imports

    monkeypatch.chdir(ROOT)
    assert lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True) == 0


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def test_no_package_imports_another_packages_private_names():
    """``from rollerrig.a.b import _x`` or an import of ``rollerrig.a._b`` from package c is
    refused (an ``as _alias`` of a public name is fine): what another package needs is public."""
    graph = grimp.build_graph("rollerrig", include_external_packages=False, cache_dir=None)
    found = []
    for importer in sorted(graph.modules):
        for imported in graph.find_modules_directly_imported_by(importer):
            a, b = importer.split(".")[1:2], imported.split(".")[1:2]
            if not a or not b or a == b:
                continue
            for detail in graph.get_import_details(importer=importer, imported=imported):
                line = detail["line_contents"]
                names = re.sub(r"\bas\s+\w+", "", line.split(" import ", 1)[-1])
                taken = [n for n in re.split(r"[\s,()]+", names) if n]
                if any(_private(seg) for seg in imported.split(".")[2:]) or any(
                    _private(n) for n in taken
                ):
                    found.append(f"{importer}: {line.strip()}")
    allowed: set[str] = set()
    assert sorted(set(found) - allowed) == []
