"""Header and units rows of text files: where they are, the column names and units in them.

PicoScope, catman, DIAdem and CANape write a row of units (``(ms)``, ``[V]``, ``N·m``,
``1/min``) under the header; :func:`unitlike_row` tells such a row from a row of names, and
:func:`unit_cell` takes the unit out of its cell (a cell that spells a date format such as
``dd.mm.yyyy hh:mm:ss`` holds no unit). :func:`header_rows` finds the two rows above the
numbers (the channel map's ``[file] header_row`` / ``units_row`` win), :func:`column_names`
and :func:`column_units` read them.
"""

from __future__ import annotations

import re
from pathlib import Path

from rollerrig.recordings.channels import TIME_UNITS, UNIT_FACTORS, FileSpec, normalize_unit
from rollerrig.recordings.formats._text import datalike, split_cells, unique_names
from rollerrig.recordings.recording import RecordingError

__all__ = ["column_names", "column_units", "header_rows", "unit_cell", "unitlike_row"]

_HEADER_WORDS = frozenset(
    {"time", "zeit", "t", "x_value", "timestamp", "timestamps", "date", "datum", "index"}
    | {"sample", "samples", "nr", "no", "name", "channel", "kanal"}
)
_KNOWN_UNITS = frozenset(
    {u for table in UNIT_FACTORS.values() for u in table}
    | set(TIME_UNITS)
    | {"V", "mV", "A", "mA", "W", "kW", "Hz", "kHz", "%", "°C", "degC", "K", "g", "m/s^2"}
    | {"m/s²", "km/h", "m/s", "deg", "°", "rad", "kg", "Ohm", "Ω", "um/m", "µm/m", "mV/V"}
    | {"1/s", "Nm", "N·m", "1/min", "U/min", "min-1", "bar", "sec", "µs", "-", "ms"}
)
# "N m", "bar(g)"; an inch's or an arc second's mark (in", ″, ') is a unit's character too
_UNIT_TOKEN = re.compile(r"[A-Za-zµμΩ°%/·*^.\-²³0-9() \"'″′]{1,14}")

_DATE_FORMAT_UNIT = re.compile(r"(?i)[dmyhs]{1,4}(?:[./: T-]+[dmyhs]{1,4})+(?:[.,]s+|[.,]f+)?")
"""A units-row cell that spells a date/time format (``dd.mm.yyyy hh:mm:ss``): no unit."""


def unit_cell(cell: str) -> str | None:
    """The unit in a units-row cell (``(ms)`` -> ``ms``); None when empty or a date format."""
    c = cell.strip()
    if len(c) >= 2 and c[0] + c[-1] in ("()", "[]", "<>", "{}"):
        c = c[1:-1].strip()
    if _DATE_FORMAT_UNIT.fullmatch(c):
        return None
    return c or None


def unitlike_row(fields: list[str]) -> bool:
    """Whether a row looks like units (``s;N·m;1/min``, ``(ms),(V),(V)``), not like names."""
    cells = [f.strip() for f in fields if f.strip()]
    if not cells or datalike(fields):
        return False
    known = 0
    for c in cells:
        bracketed = len(c) >= 2 and c[0] + c[-1] in ("()", "[]")
        if _DATE_FORMAT_UNIT.fullmatch(c.strip("()[] ")):
            continue  # the time column's format, e.g. "dd.mm.yyyy hh:mm:ss"
        u = unit_cell(c) or ""
        if u.lower() in _HEADER_WORDS or not _UNIT_TOKEN.fullmatch(u):
            return False
        if bracketed or u in _KNOWN_UNITS or normalize_unit(u) in _KNOWN_UNITS:
            known += 1
    return known >= max(1, (len(cells) + 1) // 2)


def header_rows(
    above: list[tuple[int, str]], sep: str, spec: FileSpec
) -> tuple[int | None, int | None]:
    """0-based file lines of the header and of the units row (None: none).

    ``above``: the non-blank lines above the numbers, (line, text). ``[file] header_row`` and
    ``units_row`` win (``units_row = false``: no units row); otherwise the line right above
    the numbers is the header, or the units row under the header when it looks like units.
    """
    header_line: int | None = spec.header_row
    units_line: int | None = spec.units_row if spec.units_row is not False else None
    if header_line is None:
        if spec.units_row is not None and spec.units_row is not False:
            cand = [(i, t) for i, t in above if i < spec.units_row]
            header_line = cand[-1][0] if cand else None
        elif spec.units_row is None and len(above) >= 2:
            up, low = above[-2], above[-1]
            uf, lf = split_cells(up[1], sep), split_cells(low[1], sep)
            names3 = split_cells(above[-3][1], sep) if len(above) >= 3 else []
            if unitlike_row(lf) and not unitlike_row(uf) and abs(len(uf) - len(lf)) <= 1:
                header_line, units_line = up[0], low[0]
            elif ends_with_scope_extras(uf):  # Rigol: X,CH1,..,Start,Increment / Sequence,Volt,..
                header_line, units_line = up[0], low[0]
            elif (
                names3
                and unitlike_row(uf)
                and not unitlike_row(names3)
                and not unitlike_row(lf)
                and not datalike(lf)
                and len(names3) == len(uf) == len(lf)
                # the names hold a time column's name, the descriptions none: a key-value
                # preamble ("Device,DL850" / "Range,V" / "Time,Torque") is no such header
                and any(c.strip().strip('"').lower() in _HEADER_WORDS for c in names3)
                and not any(c.strip().strip('"').lower() in _HEADER_WORDS for c in lf)
            ):
                # DIAdem's export: names, units, then a row of descriptions above the numbers
                header_line, units_line = above[-3][0], up[0]
            else:
                header_line = low[0]
        elif above:
            header_line = above[-1][0]
    elif spec.units_row is None:
        between = [(i, t) for i, t in above if i > header_line]
        if len(between) == 1 and unitlike_row(split_cells(between[0][1], sep)):
            units_line = between[0][0]
    return header_line, units_line


SCOPE_EXTRAS = ("start", "increment")
"""Header cells of a Rigol (and Agilent/Keysight InfiniiVision) oscilloscope's CSV beyond its
data columns: ``X,CH1,CH2,Start,Increment,`` over ``Sequence,Volt,Volt,-1e-3,1e-3``, the
time of sample X being Start + X Increment."""


def _scope_start(cells: list[str]) -> int | None:
    """Where an oscilloscope's ``Start, Increment`` (:data:`SCOPE_EXTRAS`) begin among a row's
    cells, they being its last (past empty ones) after at least one name; None otherwise."""
    names = [c.strip().strip('"').lower() for c in cells]
    while names and names[-1] == "":
        names.pop()
    first = len(names) - len(SCOPE_EXTRAS)
    return first if first >= 1 and tuple(names[first:]) == SCOPE_EXTRAS else None


def ends_with_scope_extras(cells: list[str]) -> bool:
    """Whether a row's last cells (past empty ones) are an oscilloscope's ``Start,
    Increment`` (:data:`SCOPE_EXTRAS`) after at least one name."""
    return _scope_start(cells) is not None


def _scope_header(
    names: list[str], n_names: int, below: str, sep: str, notes: list, stated: dict
) -> list:
    """The header's first ``n_names`` cells where the cells beyond the data's columns are an
    oscilloscope's Start and Increment (:data:`SCOPE_EXTRAS`), noted, with the rate they give
    in ``stated["rate_Hz"]``; ``names`` unchanged otherwise (the count check then names the
    mismatch)."""
    first = _scope_start(names)  # where Start stands
    if first is None or first > n_names:
        return names
    values = split_cells(below, sep)[first : first + 2]
    try:
        start, increment = (float(v) for v in values)
    except ValueError:
        start = increment = float("nan")
    if 0.0 < increment < float("inf"):
        stated["rate_Hz"] = 1.0 / increment
        how = (
            f"Start {start:g} s, Increment {increment:g} s on the line below: the samples are "
            f"{1.0 / increment:g} Hz apart (the time of sample X is Start + X Increment), the "
            "time base where the map gives none"
        )
    else:
        how = "the time of sample X is Start + X Increment ([time] sample_rate_Hz = 1/Increment)"
    notes.append(f"an oscilloscope's CSV (Rigol, Keysight): header cells Start, Increment; {how}")
    return names[:first] + [""] * (n_names - first)  # a trailing separator's empty column


def column_names(
    path: Path,
    text_of: dict[int, str],
    header_line: int | None,
    sep: str,
    n: int,
    trailing: bool,
    *,
    data_line: int,
    separator_given: bool,
    notes: list[str],
    repeated: dict | None = None,
    stated: dict | None = None,
) -> list[str]:
    """Unique names of the ``n`` cells of a data row (``trailing``: the last is empty).

    From the header line (``text_of``: line -> text); unnamed columns are ``column 1``,
    ``column 2``, ...; repeated names are renamed ``name.1``, ... (noted; ``repeated`` gets
    them, see :func:`~rollerrig.recordings.formats._text.unique_names`).

    Raises
    ------
    RecordingError
        A header whose cell count differs from the data rows'.
    """
    if header_line is not None:
        names = split_cells(text_of.get(header_line, ""), sep)
        if names and names[-1] == "" and len(names) in (n, n + 1) and trailing:
            names = names[:-1]
        elif names and names[-1] == "" and len(names) == n + 1:
            names = names[:-1]
    else:
        names = []
        notes.append("no header row; columns named 'column 1', 'column 2', ...")
    n_names = n - 1 if trailing else n
    if header_line is not None and len(names) > n_names:
        names = _scope_header(
            names,
            n_names,
            text_of.get(header_line + 1, ""),
            sep,
            notes,
            {} if stated is None else stated,
        )
    if header_line is not None and len(names) != n_names:
        if n == 1 and not separator_given:
            pass  # one column: the separator is unknown and irrelevant
        else:
            raise RecordingError(
                f"{path}: the header (line {header_line + 1}) has {len(names)} cells but the data "
                f"rows (from line {data_line + 1}) have {n_names}; check the separator "
                f"({sep!r}) or give [file] header_row / separator in the channel map"
            )
    if n == 1:
        names = [text_of.get(header_line, "").strip().strip('"')] if header_line is not None else []
    names = [nm.strip().strip('"') or f"column {k + 1}" for k, nm in enumerate(names)]
    names += [f"column {k + 1}" for k in range(len(names), n_names)]
    unique = unique_names(names, repeated)
    if unique != names:
        dup = sorted({nm for nm in names if names.count(nm) > 1})
        notes.append(f"duplicate column names {dup} renamed name.1, name.2, ...")
    return unique


def column_units(
    text_of: dict[int, str], units_line: int | None, sep: str, n: int, n_names: int
) -> list[str | None]:
    """The unit of each of the ``n_names`` columns from the units row (None: no unit)."""
    if units_line is None:
        return [None] * n_names
    cells = split_cells(text_of.get(units_line, ""), sep) if n > 1 else [text_of[units_line]]
    return [unit_cell(c) for c in cells[:n_names]] + [None] * (n_names - len(cells))
