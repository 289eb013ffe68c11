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


def add_alias(table: Table, alias: str, name: str) -> None:
    if alias != name:
        table.aliases.setdefault(alias, []).append(name)


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
