"""The package's layout as contracts (ARCHITECTURE.md): packages import only downwards (the
import-linter contract in pyproject.toml), and no package takes another package's private
names or modules."""

from __future__ import annotations

import ast
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


def _imports_from(path: Path):
    """(line, module, names) of every ``from rollerrig... import ...`` in the file, at any depth
    (inside functions too) and over as many lines as the statement takes."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] == "rollerrig":
                yield node.lineno, node.module, [alias.name for alias in node.names]
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "rollerrig":
                    yield node.lineno, alias.name, []


def test_no_package_imports_another_packages_private_names():
    """``from rollerrig.a.b import _x`` or an import of ``rollerrig.a._b`` from package c is
    refused (an ``as _alias`` of a public name is fine): what another package needs is public.
    Read from the syntax tree, so that an import over several lines or inside a function counts
    as much as one on one line."""
    src = ROOT / "src" / "rollerrig"
    found = []
    for path in sorted(src.rglob("*.py")):
        parts = path.relative_to(src).with_suffix("").parts
        if len(parts) < 2:  # a top-level module (rollerrig/_validation.py, ...): no package
            continue
        package = parts[0]
        for line, module, names in _imports_from(path):
            segments = module.split(".")
            if len(segments) < 2 or segments[1] == package:
                continue
            if any(_private(seg) for seg in segments[2:]) or any(_private(n) for n in names):
                found.append(f"{path.relative_to(ROOT)}:{line}: from {module} import {names}")
    assert found == []


def test_the_private_name_check_reads_whole_statements(tmp_path):
    """The check must see a private name on the second line of a parenthesised import, and one
    imported inside a function (the first line alone missed them)."""
    module = tmp_path / "m.py"
    module.write_text(
        "from rollerrig.studies.summary import (\n    design,\n    _text,\n)\n"
        "def f():\n    from rollerrig.fit.polach import _cost\n"
    )
    seen = [(m, n) for _, m, names in _imports_from(module) for n in names if _private(n)]
    assert seen == [("rollerrig.studies.summary", "_text"), ("rollerrig.fit.polach", "_cost")]


def test_no_module_imports_itself_through_others():
    """No import circles between modules (issue 21), counting imports inside functions and
    under TYPE_CHECKING (grimp sees them all): the strongly connected parts of the import
    graph are single modules."""
    graph = grimp.build_graph("rollerrig", include_external_packages=False, cache_dir=None)
    edges = {m: set(graph.find_modules_directly_imported_by(m)) - {m} for m in graph.modules}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(start: str) -> None:  # Tarjan's algorithm, iterative (the graph is deep)
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges[child]))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
                if low[node] == index[node]:
                    part = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        part.append(member)
                        if member == node:
                            break
                    if len(part) > 1:
                        circles.append(sorted(part))

    for module in sorted(edges):
        if module not in index:
            visit(module)
    assert circles == []
