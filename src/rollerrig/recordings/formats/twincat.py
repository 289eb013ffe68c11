"""TwinCAT 3 Scope View text exports (Beckhoff TwinCAT Scope: the ``.svdx`` exported as CSV).

Layout (as TwinCAT Scope 3.4 writes it; checked on exports of TwinCAT 3.1.4024):

- a file header of key/value rows: ``Name`` (the scope's name), ``File``, ``Starttime of
  export`` and ``Endtime of export`` (each a Windows FILETIME, 100 ns since 1601 UTC, then the
  local date and time as words), and blank lines;
- the channels' header, one row per property: ``Name``, ``SymbolComment``, ``Data-Type``,
  ``SampleTime[ms]``, ``VariableSize``, ..., ``Unit`` (``V (Voltage)``, ``(None)``), ``Unit
  ScaleFactor``, ``Unit Offset``. A cell holding the property's key marks a time column; the
  cells right of it, up to the next key, are the channels sampled at those times (one channel
  per time column by default; with the export's "exclude double timestamps" every channel of
  one sample time shares one time column);
- a blank line, then the samples: the time columns in ms and the channels' values as displayed
  (scale factors and offsets applied), a row per sample of the longest channel. A channel that
  ended (a slower one, or one that started later) leaves its cells blank (a space) or its row
  short; a last line ``EOF`` where the export was asked for one.

The separator is the export's choice (tab by default, ``;`` and ``,`` too); the decimal mark
follows the exporting PC's locale (``0,2`` under a tab or ``;``). A space as the separator is
refused: the property keys (``Unit ScaleFactor``), units (``V (Voltage)``) and names hold
spaces, so its cells cannot be told apart.

Each channel is read with its own time base [s] (:attr:`Column.time`): channels of different
sample times are never aligned by index (a map's ``[time] resample_Hz`` puts them on one). The
channel map needs no ``[time]`` section. ``Unit`` gives the channel's unit (``(None)``: none).

Why a reader of our own: pytcs (PyPI, BSD licence) reads these files well but needs pandas or
polars and returns every channel on its own, with no channel map, units in SI or checks; the
generic text sniffer (:mod:`.sniff`) cannot: the header of names is not the row above the
numbers, the same key names every time column, and the rows are ragged.
"""

from __future__ import annotations

import io
import re
from datetime import UTC, datetime, timedelta
from pathlib import Path

import numpy as np

from rollerrig.recordings.channels import FileSpec
from rollerrig.recordings.formats._table import Column, Table, require_module
from rollerrig.recordings.formats._text import decode_text, unique_names, whole_text
from rollerrig.recordings.formats.sniff import text_end
from rollerrig.recordings.recording import RecordingError

__all__ = ["is_twincat_scope", "read_twincat", "reads_as_twincat"]

SAMPLE_TIME_KEY = "SampleTime[ms]"
"""The property row that marks a TwinCAT Scope export (with ``Name`` as its first cell)."""

_SEPARATORS = ("\t", ";", ",", ":")
_HEAD_BYTES = 1 << 20  # a scope of 1 200 channels has its SampleTime[ms] row at 85 kB
_FILETIME_EPOCH = datetime(1601, 1, 1, tzinfo=UTC)
_UNIT = re.compile(r"^\s*(?P<unit>[^()]*?)\s*(\((?P<what>[^()]*)\))?\s*$")


def _cells(line: str, sep: str) -> list[str]:
    """The cells of a line, quotes around a cell removed (the space-separated export quotes
    cells with spaces; the others do not quote)."""
    return [c.strip().strip('"').strip() for c in line.split(sep)]


def _lines(text: str) -> list[str]:
    """The lines of ``text`` at any line end (``re.split`` took five times as long on a 60 MB
    export)."""
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")


def _head_lines(path: Path) -> list[str]:
    with path.open("rb") as fh:
        raw = fh.read(_HEAD_BYTES)
    if b"\x00" in raw:  # a NUL-padded tail (a logger that lost power) is no part of the text
        end = text_end(path, FileSpec(), [])
        raw = raw if end is None else raw[:end]
    _, text = decode_text(
        path,
        raw,
        None,
        [],
        truncated=len(raw) == _HEAD_BYTES,
        fallback="cp1252",
        fallback_name="Windows-1252",
        binary_hint="not a text file",
    )
    return _lines(text)


def _separator(lines: list[str]) -> str | None:
    """The separator of a TwinCAT Scope export's lines, or None where they are not one: the
    first line names the scope (``Name``), and a ``SampleTime[ms]`` row sits in a block of
    rows (between blank lines) that starts with the channels' ``Name`` row."""
    first = next((t for t in lines if t.strip()), "")
    for at, line in enumerate(lines[:400]):
        stripped = line.lstrip('"')
        if not stripped.startswith(SAMPLE_TIME_KEY):
            continue
        sep = stripped[len(SAMPLE_TIME_KEY) :].lstrip('"')[:1]
        if sep not in (*_SEPARATORS, " "):
            continue
        top = at
        while top > 0 and lines[top - 1].strip():
            top -= 1
        if _cells(first, sep)[0] == "Name" and _cells(lines[top], sep)[0] == "Name":
            return sep
    return None


def is_twincat_scope(path: str | Path) -> bool:
    """True when the text file is a TwinCAT Scope export: its first line is the scope's
    ``Name`` and a ``SampleTime[ms]`` property row follows within its first lines."""
    try:
        return _separator(_head_lines(Path(path))) is not None
    except (OSError, RecordingError):
        return False


def reads_as_twincat(path: str | Path, spec: FileSpec | None = None) -> bool:
    """True when a text file is read by :func:`read_twincat`: a TwinCAT Scope export
    (:func:`is_twincat_scope`) whose channel map does not place the header or the numbers
    (``[file] header_row`` / ``data_row``: such a map reads it as plain CSV, as before this
    reader, e.g. with ``[time] column = "Name.0"``)."""
    if spec is not None and (spec.header_row is not None or spec.data_row is not None):
        return False
    return is_twincat_scope(path)


def _unit(cell: str) -> str | None:
    """``V (Voltage)`` -> ``V``; ``(None)`` or empty -> None."""
    m = _UNIT.match(cell)
    unit = (m.group("unit") if m else cell).strip()
    return unit or None


def _export_start(row: list[str]) -> str | None:
    """The export's start (``Starttime of export`` row) as an ISO UTC time, or None."""
    try:
        start = _FILETIME_EPOCH + timedelta(microseconds=int(row[1]) // 10)
    except (IndexError, ValueError, OverflowError):
        return None  # no FILETIME, or one beyond the dates Python holds: not stated
    return start.isoformat(timespec="milliseconds").replace("+00:00", "Z")


def _decimal(path: Path, sep: str, body: str, given: str | None) -> str:
    """The decimal mark of the samples: given, else ``,`` where a sample cell anywhere in the
    body has one between digits (never under a ``,`` separator: a channel may show whole
    numbers for its first seconds), else ``.``."""
    if given is not None:
        return given
    if sep == ",":
        return "."
    # a mark between two digits: under a tab or ';' separator a ',' there is a decimal comma
    # (TwinCAT writes no thousands marks)
    has_comma = _between_digits(body, ",")
    has_point = _between_digits(body, ".")
    if has_comma and has_point:
        raise RecordingError(
            f"{path}: the samples use both ',' and '.' as decimal marks; give [file] decimal "
            "in the channel map"
        )
    return "," if has_comma else "."


def _between_digits(text: str, mark: str) -> bool:
    """True where ``mark`` stands between two digits somewhere in ``text``: found by
    ``str.find`` from mark to mark (a regular expression took 1.3 s on a 60 MB export
    without the mark; this, 0.02 s)."""
    i = text.find(mark)
    while i != -1:
        if 0 < i < len(text) - 1 and text[i - 1].isdigit() and text[i + 1].isdigit():
            return True
        i = text.find(mark, i + 1)
    return False


def read_twincat(path: Path, spec: FileSpec | None = None) -> Table:
    """Read a TwinCAT Scope text export into a :class:`Table` (see the module docstring).

    Parameters
    ----------
    path : path-like
        The file (read-only).
    spec : FileSpec, optional
        The channel map's ``[file]`` section: ``separator``, ``decimal`` and ``encoding`` beat
        what the file says (with ``header_row`` or ``data_row`` the file is read as plain CSV:
        :func:`reads_as_twincat`).

    Raises
    ------
    RecordingError
        Not such an export, a space as the separator, a channel header without a time
        column, a sample that is not a number (naming its line and channel).
    """
    pd = require_module("pandas", "TwinCAT Scope exports")
    path = Path(path)
    spec = spec or FileSpec()
    notes: list[str] = []
    text = whole_text(
        path,
        spec.encoding,
        notes,
        fallback="cp1252",
        fallback_name="Windows-1252",
        binary_hint="not a TwinCAT Scope export",
        end=text_end(path, spec, notes),
    )
    lines = _lines(text)
    sep = spec.separator or _separator(lines)
    if sep is None:
        raise RecordingError(
            f"{path}: not a TwinCAT Scope export (no '{SAMPLE_TIME_KEY}' row under a first "
            "'Name' row); read it as CSV with format='csv'"
        )
    if sep == " ":
        raise RecordingError(
            f"{path}: a TwinCAT Scope export separated by spaces: its keys, units and channel "
            "names hold spaces too, so its cells cannot be told apart; export it again with a "
            "tab (the default), ';' or ',' as the separator"
        )

    # --- the channels' header: the block of rows holding the SampleTime[ms] row
    at = next((i for i, t in enumerate(lines) if _cells(t, sep)[:1] == [SAMPLE_TIME_KEY]), None)
    if at is None:
        raise RecordingError(
            f"{path}: no '{SAMPLE_TIME_KEY}' row under the separator {sep!r}: is [file] "
            "separator in the channel map the export's?"
        )
    first = at
    while first > 0 and lines[first - 1].strip():
        first -= 1
    last = at
    while last + 1 < len(lines) and lines[last + 1].strip():
        last += 1
    props = {(c := _cells(lines[i], sep))[0]: c for i in range(first, last + 1)}
    names_row = props.get("Name")
    if names_row is None or names_row[:1] != ["Name"]:
        raise RecordingError(
            f"{path}: line {first + 1}: the channels' header does not start with a 'Name' row "
            f"(it starts {lines[first][:60]!r})"
        )
    keys = [j for j, c in enumerate(names_row) if c == "Name"]
    groups: list[tuple[int, list[int]]] = []  # (time column, its channels' columns)
    for g, j in enumerate(keys):
        end = keys[g + 1] if g + 1 < len(keys) else len(names_row)
        cols = [c for c in range(j + 1, end) if names_row[c]]
        if cols:
            groups.append((j, cols))
    if not groups:
        raise RecordingError(f"{path}: line {first + 1}: no channel names in the 'Name' row")

    def property_row(key: str) -> list[str]:
        """The property row ``key``, cell for cell under the names; [] where it has more
        cells than the names (under a ',' separator TwinCAT writes a sample time of 0,2 ms
        unquoted, which splits it and shifts every cell right of it)."""
        row = props.get(key, [])
        if len(row) > len(names_row):
            notes.append(
                f"TwinCAT Scope {key!r} row not read: it has more cells than the 'Name' row "
                f"({len(row)} against {len(names_row)}; a decimal comma under a ',' separator?)"
            )
            return []
        return row

    unit_row = property_row("Unit")
    sample_row = property_row(SAMPLE_TIME_KEY)

    file_header = {c[0]: c for c in (_cells(t, sep) for t in lines[:first] if t.strip()) if c[0]}
    if "Name" in file_header and len(file_header["Name"]) > 1:
        notes.append(f"TwinCAT Scope export of {file_header['Name'][1]!r}")
    start = _export_start(file_header.get("Starttime of export", []))
    if start:
        notes.append(f"TwinCAT Scope export started {start} (Starttime of export, UTC)")

    # --- the samples: from the first non-blank line below the header to the end, less a
    # last "EOF" line (and blank lines)
    data_first = last + 1
    while data_first < len(lines) and not lines[data_first].strip():
        data_first += 1
    data_last = len(lines) - 1
    while data_last >= data_first and not lines[data_last].strip():
        data_last -= 1
    if data_last >= data_first and lines[data_last].strip().strip('"') != "EOF":
        if not text.endswith(("\n", "\r")):  # a copy cut short: its last cell may be cut too
            notes.append(
                f"TwinCAT Scope export: the last line ({data_last + 1}) ends without a line "
                "end (the file cut short?): dropped"
            )
            data_last -= 1
    if data_last >= data_first and lines[data_last].strip().strip('"') == "EOF":
        data_last -= 1
        while data_last >= data_first and not lines[data_last].strip():
            data_last -= 1
    if data_last < data_first:
        raise RecordingError(
            f"{path}: a TwinCAT Scope export without samples (no rows below the channels' "
            f"header, lines {first + 1}-{last + 1}, and a blank line); if the file is no such "
            "export, give [file] header_row and data_row in the channel map to read it as CSV"
        )
    body = lines[data_first : data_last + 1]
    text_body = "\n".join(body)
    decimal = _decimal(path, sep, text_body, spec.decimal)
    if sep == decimal:
        raise RecordingError(f"{path}: separator and decimal mark are both {sep!r}")
    if decimal == ",":
        notes.append("TwinCAT Scope decimal commas (the exporting PC's locale)")
    # every row's cells: a row longer than the names (a stray separator) must not stop the
    # parser midway, which sizes its columns from the names it is given
    width = max(len(names_row), max(line.count(sep) for line in body) + 1)
    frame = pd.read_csv(
        io.StringIO(text_body),
        sep=sep,
        header=None,
        names=list(range(width)),
        decimal=decimal,
        na_values=["", " "],
        keep_default_na=False,
        engine="c",
        low_memory=False,
    )

    def column(j: int, what: str) -> np.ndarray:
        """Column ``j`` as numbers, NaN where blank; a cell that is no number is an error
        naming its line (pandas left the column as text)."""
        col = frame[j]
        if col.dtype.kind in "fiu":
            return col.to_numpy(dtype=float)
        values = np.full(len(col), np.nan)
        for k, cell in enumerate(col.to_numpy()):
            if isinstance(cell, float) and cell != cell:  # blank
                continue
            text = str(cell).strip()
            try:
                values[k] = float(text.replace(",", ".") if decimal == "," else text)
            except ValueError:
                raise RecordingError(
                    f"{path}: line {data_first + k + 1}, {what}: {text!r} is not a number "
                    f"(decimal mark {decimal!r})"
                ) from None
        return values

    repeated: dict[str, list[str]] = {}
    names = unique_names([names_row[c] for _, cols in groups for c in cols], repeated)
    where: dict[str, tuple[int, int]] = {}  # channel -> (its time column, its column)
    order = iter(names)
    for j, cols in groups:
        for c in cols:
            where[next(order)] = (j, c)
    times: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # time column -> (rows, times [s])
    columns: dict[str, Column] = {}

    def load(name: str) -> Column:
        """The channel ``name`` on its own time base, parsed when first asked for: the
        samples of the rows where its time column holds one."""
        if name not in columns:
            j, c = where[name]
            if j not in times:
                t_ms = column(j, f"the time column of {names_row[c]!r}")
                rows = np.flatnonzero(~np.isnan(t_ms))
                times[j] = rows, t_ms[rows] / 1e3
            rows, t_s = times[j]
            unit = _unit(unit_row[c]) if c < len(unit_row) else None
            values = column(c, f"channel {names_row[c]!r}")[rows]
            columns[name] = Column(values, unit, t_s.copy())
        return columns[name]

    empty = [j for j, _ in groups if frame[j].isna().all()] if width else []
    if len(empty) == len(groups):
        raise RecordingError(f"{path}: no time column of the TwinCAT Scope export holds samples")
    for j in empty:
        notes.append(f"TwinCAT Scope time column {j + 1} holds no samples")
    rates = sorted({sample_row[c] for _, cols in groups for c in cols if c < len(sample_row)})
    if len(rates) > 1:
        notes.append(
            "TwinCAT Scope channels of different sample times (SampleTime[ms] "
            + ", ".join(rates)
            + "): each on its own time base"
        )
    notes.append(f"TwinCAT Scope export read with separator {sep!r}")
    return Table(
        names=list(names),
        load=load,
        base={n: n for n in names},
        notes=notes,
        own_time_exact=True,
        repeated=repeated,
    )
