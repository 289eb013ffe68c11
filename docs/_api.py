"""Write the API reference's pages from the package itself (called by ``conf.py``).

One page per public package (its docstring and a table of its modules) and one per public
module (its docstring, a table of the names of its ``__all__`` and each of them documented from
its numpydoc docstring). A name is documented in the module that defines it; a module that
re-exports it links to it from its table. Nothing here is edited by hand: a new public function
appears in the reference when it enters its module's ``__all__``.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from pathlib import Path

#: The public packages, in the order of the reference (the layers of ARCHITECTURE.md, bottom up).
PACKAGES = (
    "units",
    "output",
    "contact",
    "frame",
    "experiment",
    "drives",
    "rig",
    "solve",
    "fit",
    "recordings",
    "signal",
    "measure",
    "estimation",
    "analysis",
    "calibrate",
    "studies",
    "report",
)


def _title(text: str, char: str = "=") -> str:
    return f"{text}\n{char * len(text)}\n"


def _public_modules(package) -> list[str]:
    if not hasattr(package, "__path__"):
        return []
    names = []
    for info in pkgutil.iter_modules(package.__path__):
        if info.name.startswith("_"):
            continue
        names.append(f"{package.__name__}.{info.name}")
    return sorted(names)


def _defined_here(module, name: str) -> bool:
    obj = getattr(module, name, None)
    if obj is None:
        return False
    if inspect.isclass(obj) or inspect.isfunction(obj) or callable(obj):
        return getattr(obj, "__module__", None) == module.__name__
    try:
        source = inspect.getsource(module)
    except (OSError, TypeError):
        return False
    return re.search(rf"^{re.escape(name)}\s*[:=]", source, re.MULTILINE) is not None


def _directive(module, name: str) -> str:
    obj = getattr(module, name)
    full = f"{module.__name__}.{name}"
    if inspect.isclass(obj):
        if issubclass(obj, BaseException):
            return f".. autoexception:: {full}\n"
        return f".. autoclass:: {full}\n   :members:\n"
    if inspect.isfunction(obj) or inspect.isbuiltin(obj):
        return f".. autofunction:: {full}\n"
    if callable(obj) and hasattr(obj, "__doc__"):
        return f".. autofunction:: {full}\n"
    return f".. autodata:: {full}\n   :annotation:\n"


def _module_page(modname: str) -> str:
    module = importlib.import_module(modname)
    names = list(getattr(module, "__all__", []))
    lines = [_title(f"``{modname}``"), f".. automodule:: {modname}\n   :no-members:\n"]
    here = [n for n in names if _defined_here(module, n)]
    elsewhere = [n for n in names if n not in here and hasattr(module, n)]
    if here:
        lines.append(".. rubric:: Contents\n")
        lines.append(".. autosummary::\n   :nosignatures:\n")
        lines.extend(f"   {n}" for n in here)
        lines.append("")
        lines.extend(_directive(module, n) for n in here)
    if elsewhere:
        lines.append("\nAlso importable from this module:\n")
        for n in elsewhere:
            obj = getattr(module, n)
            home = getattr(obj, "__module__", None)
            if home and (inspect.isclass(obj) or inspect.isfunction(obj)):
                lines.append(f"- :py:obj:`{n} <{home}.{n}>`")
            else:
                lines.append(f"- ``{n}``")
        lines.append("")
    return "\n".join(lines) + "\n"


def _package_page(pkgname: str, modules: list[str]) -> str:
    lines = [_title(f"``{pkgname}``"), f".. automodule:: {pkgname}\n   :no-members:\n"]
    if modules:
        lines.append(".. autosummary::\n   :nosignatures:\n")
        lines.extend(f"   {m.rsplit('.', 1)[1]}" for m in modules)
        lines.append("\n.. toctree::\n   :hidden:\n")
        lines.extend(f"   {m}" for m in modules)
        return "\n".join(lines) + "\n"
    return _module_page(pkgname)  # a module, not a package (rollerrig.units)


def _write(path: Path, text: str) -> None:
    if not path.exists() or path.read_text("utf-8") != text:  # unchanged pages keep their mtime
        path.write_text(text, "utf-8")


def write_api_pages(folder: Path) -> None:
    """Write ``folder/index.rst`` and a page per public package and module."""
    folder.mkdir(parents=True, exist_ok=True)
    index = [
        _title("API reference"),
        "Every public function and class, from its docstring: parameters with their units in "
        "brackets, the equations and the sources. The names a notebook needs are also "
        "importable from ``rollerrig`` itself (:doc:`top-level names <rollerrig>`).\n",
        ".. toctree::\n   :maxdepth: 1\n",
        "   rollerrig",
    ]
    _write(folder / "rollerrig.rst", _top_level_page())
    wanted: set[str] = {"index.rst", "rollerrig.rst"}
    for short in PACKAGES:
        pkgname = f"rollerrig.{short}"
        package = importlib.import_module(pkgname)
        modules = _public_modules(package)
        _write(folder / f"{pkgname}.rst", _package_page(pkgname, modules))
        wanted.add(f"{pkgname}.rst")
        for modname in modules:
            _write(folder / f"{modname}.rst", _module_page(modname))
            wanted.add(f"{modname}.rst")
        index.append(f"   {pkgname}")
    _write(folder / "index.rst", "\n".join(index) + "\n")
    for stale in folder.glob("*.rst"):
        if stale.name not in wanted:
            stale.unlink()


def _top_level_page() -> str:
    import rollerrig

    lines = [
        _title("``rollerrig`` (top level)"),
        ".. automodule:: rollerrig\n   :no-members:\n",
        "The top-level names and where they are documented:\n",
        ".. list-table::\n   :header-rows: 1\n\n   * - name\n     - documented in",
    ]
    for name, modname in rollerrig._EXPORTS.items():
        obj = getattr(importlib.import_module(modname), name)
        home = getattr(obj, "__module__", modname)
        lines.append(f"   * - :py:obj:`{name} <{home}.{name}>`\n     - ``{home}``")
    return "\n".join(lines) + "\n"
