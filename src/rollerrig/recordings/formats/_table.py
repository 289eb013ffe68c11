"""A file as a table of named columns: what every format reader returns."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rollerrig.output.tables import META_KEY, PROVENANCE_KEY, UNITS_STRUCT, VARIABLES_KEY
from rollerrig.recordings.channels import split_unit_header

UNITS_KEY = "rollerrig_units"
"""MAT variable (JSON text) in which rollerrig's writers before the ``units`` struct
(:data:`~rollerrig.output.tables.UNITS_STRUCT`) stored channel units; still read."""

__all__ = [
    "META_KEY",
    "PROVENANCE_KEY",
    "UNITS_KEY",
    "UNITS_STRUCT",
    "VARIABLES_KEY",
    "Column",
    "Slicer",
    "Table",
    "add_alias",
    "add_to_group",
    "apply_default_group",
    "header_table",
    "require_module",
]


def require_module(module: str, what: str):
    """``module``, or an error naming the ``io`` extra that provides it (reading ``what``)."""
    from rollerrig._optional import require

    return require(module, "io", f"reading {what}")


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
    # before stored_metadata: __init__ must not reset what setting stored_metadata split off
    stored_provenance: Any = None  # the provenance record of a file rollerrig wrote
    stored_variables: Any = None  # {column: {"units", "long_name", "nan_meaning", ...}}
    stored_metadata: Any = None  # the metadata object rollerrig's writer stored (see below)
    own_time_exact: bool = False  # own time bases beat index alignment (MDF masters)
    # group label -> names in that group (TDMS group, MDF data-group index / acquisition name /
    # comment / source), for ``[file] group`` (:func:`apply_default_group`)
    groups: dict[str, list[str]] = field(default_factory=dict)
    slicer: Slicer | None = None  # reads parts of columns (chunked reading); None: load whole
    # the decimal mark of a text file, where given or sniffed (not a default): text cells are
    # then read under it (:func:`rollerrig.recordings.translate.as_float`)
    decimal: str | None = None
    # a name the file gives to more than one column -> the unique names those columns got
    # (``name``, ``name.1``, ...): the name alone is ambiguous (translate.resolve_column)
    repeated: dict[str, list[str]] = field(default_factory=dict)
    # a text file's hint where a name the map gives stands, when it is no column's name
    # (sniff.where_named: another line than the header the reader took)
    locate: Callable[[str], str] | None = None
    # a sample rate the file states without a time column [Hz] (an oscilloscope CSV's
    # 1/Increment): the time base where the map gives none
    stated_rate: float | None = None
    # a column -> the columns the file names as its time base, one where it is known (a TDMS
    # group's time channel, DIAdem style; a ControlDesk signal's raster X(k) by its XIndex),
    # several where the group holds more than one time channel: a mapped channel timed by
    # another than the map's time column is put on its own time (translate.foreign_time)
    time_of: dict[str, tuple[str, ...]] = field(default_factory=dict)

    def __setattr__(self, name: str, value: Any) -> None:
        """Setting ``stored_metadata`` to the object :func:`rollerrig.output.write_table` wrote
        splits it: its ``"provenance"`` and ``"variables"`` entries go to
        :attr:`stored_provenance` and :attr:`stored_variables`, the rest (the recording's own
        metadata) stays in :attr:`stored_metadata`."""
        if name == "stored_metadata" and isinstance(value, Mapping):
            value = dict(value)
            prov = value.pop(PROVENANCE_KEY, None)
            variables = value.pop(VARIABLES_KEY, None)
            if prov is not None:
                object.__setattr__(self, "stored_provenance", prov)
            if variables is not None:
                object.__setattr__(self, "stored_variables", variables)
        object.__setattr__(self, name, value)


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
    from rollerrig.recordings.recording import RecordingError

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
