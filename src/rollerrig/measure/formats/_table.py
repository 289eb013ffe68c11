"""A file as a table of named columns: what every format reader returns."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rollerrig.measure.channels import split_unit_header

META_KEY = "rollerrig_metadata"
"""Key under which rollerrig's writers store provenance in a file."""
UNITS_KEY = "rollerrig_units"
"""Key under which rollerrig's writers store channel units (MAT files)."""


def require_module(module: str, what: str):
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(
            f"reading {what} needs the optional package {module!r}: install rollerrig[io] "
            "(pip install 'rollerrig[io]')"
        ) from exc


@dataclass
class Column:
    values: np.ndarray
    unit: str | None = None
    time: np.ndarray | None = None  # the column's own time base [s] (TDMS waveform, MDF master)


@dataclass
class Table:
    names: list[str]
    load: Callable[[str], Column]
    base: dict[str, str] = field(default_factory=dict)  # name -> short name (no group / unit)
    aliases: dict[str, list[str]] = field(default_factory=dict)  # other spelling -> names
    notes: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    stored_metadata: Any = None
    own_time_exact: bool = False  # own time bases beat index alignment (MDF masters)
    # group label -> names in that group (TDMS group, MDF data-group index / acquisition name /
    # comment / source), for ``[file] group`` (:func:`apply_default_group`)
    groups: dict[str, list[str]] = field(default_factory=dict)
    slicer: Slicer | None = None  # reads parts of columns (chunked reading); None: load whole


@dataclass
class Slicer:
    """Parts of a file's columns without loading them whole (chunked reading).

    ``length(name)`` is the number of samples of a column, ``read(name, start, stop)`` the
    column's samples ``start:stop`` as a :class:`Column` (with the same part of its own time
    base when it has one [s], on the same clock as :attr:`Table.load` gives).
    """

    length: Callable[[str], int]
    read: Callable[[str, int, int], Column]


def add_alias(table: Table, alias: str, name: str) -> None:
    if alias != name:
        table.aliases.setdefault(alias, []).append(name)


def add_to_group(table: Table, label: Any, name: str) -> None:
    """Record that ``name`` belongs to the group called ``label`` (``[file] group``)."""
    key = str(label).strip()
    if key:
        names = table.groups.setdefault(key, [])
        if name not in names:
            names.append(name)


def apply_default_group(table: Table, group: Any, where: str) -> None:
    """Make unqualified column names resolve inside ``group`` (the map's ``[file] group``).

    A plain channel name that occurs in ``group`` then means the channel of that group, even
    when other groups have a channel of the same name; names that ``group`` lacks resolve as
    before (unique in the file, or an "ambiguous" error listing the candidates).

    Raises
    ------
    RecordingError
        When the file has no group of that name (the message lists the groups).
    """
    from rollerrig.measure.recording import RecordingError

    key = str(group).strip()
    if not table.groups:
        table.notes.append(f"[file] group = {group!r} ignored: this file has no groups")
        return
    if key not in table.groups:
        shown = list(table.groups)[:60]
        raise RecordingError(
            f"{where} [file] group = {group!r} is not a group of the file; groups: {shown}"
        )
    for name in table.groups[key]:
        table.aliases[table.base.get(name, name)] = [name]
    note = f"unqualified column names resolve in group {key!r} ([file] group)"
    if note not in table.notes:
        table.notes.append(note)


def header_table(frame, *, units: Mapping[str, str] | None = None) -> Table:
    """Table over a pandas DataFrame whose headers may carry ``[unit]``."""
    names = [str(c) for c in frame.columns]
    header_units: dict[str, str | None] = {}
    table = Table(names=names, load=lambda n: None)  # type: ignore[arg-type,return-value]
    for name in names:
        base, unit = split_unit_header(name)
        header_units[name] = unit
        table.base[name] = base
        add_alias(table, base, name)
    stored = dict(units or {})

    def load(name: str) -> Column:
        base = table.base[name]
        unit = header_units[name] or stored.get(name) or stored.get(base)
        return Column(frame[name].to_numpy(), unit)

    table.load = load
    return table
