"""Rig parameter sets by name: the bundled sets and those installed packages ship.

A *rig set* is a rig file (:mod:`rollerrig.rig.rigfile`: every value with its unit and its
source or stated assumption) registered under a short name, so that ``load_rig("vt-fra")`` in
Python and ``--rig vt-fra`` on every command load it without a path. Two places register sets:

- the bundled sets, the TOML files of ``rollerrig/rig/data/`` (the Pardubice rig under the
  names ``pardubice`` and ``default``; the others under their file's stem);
- installed packages, through the entry-point group ``rollerrig.rigs`` (:data:`ENTRY_POINT_GROUP`).
  Each entry point is named by the set's name and points at a rig file, or at a function that
  returns one: a :class:`pathlib.Path`, a string path, or a :mod:`importlib.resources`
  traversable. A lab ships its rig as a small package whose ``pyproject.toml`` says::

      [project.entry-points."rollerrig.rigs"]
      ourlab-roller-rig = "ourlab_rigs:RIG_FILE"

  with ``ourlab_rigs/__init__.py`` holding
  ``RIG_FILE = importlib.resources.files(__name__) / "ourlab-roller-rig.toml"`` (and the TOML
  file listed as package data). After ``pip install``, ``rollerrig rig list`` shows it.

A bundled name cannot be taken by a package: the package's set is listed as shadowed. An entry
point that fails to load is listed with its error, never fatal to the others.

Examples
--------
>>> sets = rig_sets()
>>> "pardubice" in sets and "vt-fra-quarter-scale" in sets
True
>>> rig_set("pardubice").path.name
'default_rig.toml'
>>> rig_set("pardubise")
Traceback (most recent call last):
...
rollerrig._validation.ParameterError: no rig set named 'pardubise' (did you mean 'pardubice'?); \
the sets: ...
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from importlib import metadata, resources
from pathlib import Path

from rollerrig._toml import read_toml
from rollerrig._validation import ParameterError, did_you_mean, folder_not_file

__all__ = [
    "BUNDLED_ALIASES",
    "ENTRY_POINT_GROUP",
    "RigSet",
    "resolve_rig",
    "rig_set",
    "rig_sets",
]

ENTRY_POINT_GROUP = "rollerrig.rigs"
"""The entry-point group through which installed packages register rig sets."""

BUNDLED_ALIASES: dict[str, str] = {"pardubice": "default_rig.toml", "default": "default_rig.toml"}
"""Names of bundled sets whose file is not named after them (the default rig's file)."""

_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]*$")


@dataclass(frozen=True)
class RigSet:
    """A registered rig parameter set.

    Attributes
    ----------
    name : str
        The name ``--rig`` and :func:`rollerrig.rig.parameters.load_rig_set` take.
    path : pathlib.Path or None
        The rig file; None where the entry point could not be loaded.
    title : str
        The file's ``[meta] name``.
    description : str
        The file's ``[meta] description``.
    origin : str
        ``"bundled"`` or the distribution that registered it (``"ourlab-rigs 1.0"``).
    problem : str
        Why the set cannot be loaded (an entry point that fails, a shadowed name); empty when
        it can.
    """

    name: str
    path: Path | None
    title: str = ""
    description: str = ""
    origin: str = "bundled"
    problem: str = ""


def _meta(path: Path) -> tuple[str, str]:
    try:
        meta = read_toml(path).get("meta", {})
    except Exception as exc:  # a broken file is listed with its problem, not fatal
        return "", f"(unreadable: {exc})"
    return str(meta.get("name", "")), str(meta.get("description", ""))


def _bundled() -> dict[str, RigSet]:
    folder = resources.files("rollerrig.rig").joinpath("data")
    files = {Path(str(f)).name: Path(str(f)) for f in folder.iterdir() if f.name.endswith(".toml")}
    aliased = set(BUNDLED_ALIASES.values())
    names = dict(BUNDLED_ALIASES)
    names.update({Path(n).stem: n for n in files if n not in aliased})
    sets = {}
    for name, file in sorted(names.items()):
        path = files[file]
        title, description = _meta(path)
        sets[name] = RigSet(name, path, title, description, "bundled")
    return sets


def _entry_point_path(value) -> Path:
    if callable(value) and not isinstance(value, os.PathLike):
        value = value()
    if isinstance(value, str | os.PathLike):
        path = Path(value)
    elif hasattr(value, "is_file") and hasattr(value, "name"):  # importlib.resources traversable
        path = Path(str(value))
    else:
        raise TypeError(f"gives {type(value).__name__}, not a rig file's path")
    if not path.is_file():
        raise FileNotFoundError(f"its rig file {path} does not exist")
    return path


def _installed(taken: set[str]) -> dict[str, RigSet]:
    sets = {}
    for ep in metadata.entry_points(group=ENTRY_POINT_GROUP):
        dist = getattr(ep, "dist", None)
        origin = f"{dist.name} {dist.version}" if dist is not None else ep.value
        if not _NAME.match(ep.name):
            sets[ep.name] = RigSet(ep.name, None, origin=origin, problem="not a valid set name")
            continue
        if ep.name in taken:
            problem = f"shadowed by the bundled set {ep.name!r}"
            sets[f"{ep.name} ({origin})"] = RigSet(ep.name, None, origin=origin, problem=problem)
            continue
        try:
            path = _entry_point_path(ep.load())
        except Exception as exc:  # one broken package does not hide the other sets
            problem = f"entry point {ep.value!r} failed: {exc}"
            sets[ep.name] = RigSet(ep.name, None, origin=origin, problem=problem)
            continue
        title, description = _meta(path)
        sets[ep.name] = RigSet(ep.name, path, title, description, origin)
    return sets


def rig_sets() -> dict[str, RigSet]:
    """Every registered rig set, bundled first, by name.

    Returns
    -------
    dict of str to RigSet
        Name -> set; sets that cannot be loaded carry their ``problem``.
    """
    sets = _bundled()
    sets.update(_installed(set(sets)))
    return sets


def rig_set(name: str) -> RigSet:
    """The registered rig set ``name``.

    Raises
    ------
    ParameterError
        No set of that name (with the nearest name and the list), or the set cannot be loaded.
    """
    sets = rig_sets()
    found = sets.get(name)
    if found is None:
        usable = [n for n, s in sets.items() if not s.problem]
        raise ParameterError(
            f"no rig set named {name!r}{did_you_mean(name, usable)}; the sets: "
            + ", ".join(usable)
            + " (rollerrig rig list)"
        )
    if found.problem:
        raise ParameterError(f"rig set {name!r} ({found.origin}) cannot be loaded: {found.problem}")
    return found


def resolve_rig(value: str | os.PathLike) -> Path:
    """The rig file a ``--rig`` value names: an existing file, else a registered set's file.

    Parameters
    ----------
    value : str or path-like
        A path to a rig file, or the name of a registered set.

    Raises
    ------
    ParameterError
        Neither an existing file nor a set's name; the message offers the nearest set name.
    """
    path = Path(value)
    if path.is_file():
        return path
    name = str(value)
    folder = folder_not_file(  # it was reported as "no rig set named ..."
        path, "a rig file", "a rig TOML file or the name of a rig set (rollerrig rig list)"
    )
    if folder is not None:
        raise ParameterError(f"rig {folder}")
    looks_like_path = os.sep in name or "/" in name or name.endswith(".toml")
    if looks_like_path:
        sets = [n for n, s in rig_sets().items() if not s.problem]
        raise ParameterError(
            f"rig file {name} not found{did_you_mean(path.stem, sets, style=';')}"
            " (a rig set is named without a suffix: rollerrig rig list)"
        )
    return rig_set(name).path
