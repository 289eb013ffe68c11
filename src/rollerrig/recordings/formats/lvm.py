"""LabVIEW Measurement files (``.lvm``, written by LabVIEW's Write To Measurement File).

Layout (NI, "Specification for the LabVIEW Measurement File (.lvm)", LVM 2.0, LabVIEW 8.6+):

- a file header from ``LabVIEW Measurement`` to ``***End_of_Header***``: one tag per line
  (``Separator`` ``Tab``/``Comma``, ``Decimal_Separator`` ``.``/``,``, ``X_Columns``
  ``No``/``One``/``Multi``, ``Time_Pref``, ``Date``, ``Time``, ...);
- one or more segments (one per call of the Express VI), each with an optional segment header
  (``Channels``, ``Samples``, ``Date``, ``Time``, ``Y_Unit_Label``, ``X_Dimension``, ``X0``,
  ``Delta_X`` per channel, ended by ``***End_of_Header***``), a row of column names starting with
  ``X_Value`` and ending with ``Comment``, and the rows of numbers;
- X columns: ``One``: the first column is the time of every channel; ``Multi``: an ``X_Value``
  column before each channel; ``No``: the first cell of each row is empty and each channel's
  time is ``X0 + k * Delta_X`` from its segment header.

Each channel is read with its own time base [s] (:attr:`Column.time`), so channels of different
rates or lengths are never index-aligned. Segments are joined in file order; a segment whose time
restarts is shifted by its start ``Date``/``Time`` (noted), or is an error naming it.
``Y_Unit_Label`` is the channel's unit. The separator and decimal mark come from the header; the
channel map's ``[file] separator``/``decimal``/``encoding`` beat it.

Why a reader of our own: ``lvm_read`` 1.26 (PyPI, MIT licence, maintained by J. Slavič's lab,
numpy only) does read the ``Decimal_Separator`` and returns the segments one by one, but it turns
every cell it cannot parse into NaN without a word, pads short rows with NaN, decodes with
``errors='ignore'``, leaves joining segments (and their time bases) to the caller, and by default
writes a ``.pkl`` cache next to the input file and later unpickles whatever file of that name it
finds. Here every unreadable cell is an error naming its line and column, segments are joined on
one clock, and nothing is written.
"""

from __future__ import annotations

import re
from datetime import datetime, timedelta
from decimal import Decimal, InvalidOperation
from pathlib import Path

import numpy as np

from rollerrig.recordings.channels import FileSpec
from rollerrig.recordings.formats._table import Column, Table, add_alias
from rollerrig.recordings.formats._text import (
    EXACT_ABOVE,
    NEGATIVE_INFINITY_WORDS,
    POSITIVE_INFINITY_WORDS,
    exact_offsets,
    unique_names,
    whole_text,
)
from rollerrig.recordings.formats.sniff import text_end
from rollerrig.recordings.recording import RecordingError

__all__ = ["read_lvm"]

_END = "***End_of_Header***"
_SEPARATOR_NAMES = {"tab": "\t", "comma": ",", "semicolon": ";", "space": " "}
_SEGMENT_TAGS = {
    "Channels",
    "Samples",
    "Date",
    "Time",
    "Y_Unit_Label",
    "X_Dimension",
    "X0",
    "Delta_X",
    "Notes",
    "Test_Name",
    "Test_Numbers",
    "Test_Series",
    "UUT_M/N",
    "UUT_Name",
    "UUT_S/N",
}
_EPOCH_1904 = datetime(1904, 1, 1)
_ABSOLUTE_X = EXACT_ABOVE
"""X values above this [s] are LabVIEW absolute times (seconds since 1904-01-01)."""


def _number(cell: str, decimal: str) -> float:
    c = cell.strip()
    if decimal == ",":
        c = c.replace(",", ".")
    low = c.lower()
    if low in ("nan", "+nan", "-nan"):
        return float("nan")
    if low in POSITIVE_INFINITY_WORDS:
        return float("inf")
    if low in NEGATIVE_INFINITY_WORDS:
        return float("-inf")
    return float(c)  # raises ValueError


def _stamp(date: str, time: str) -> datetime | None:
    """LabVIEW's header Date (``2024/08/05``) and Time (``13:46:13,1234``) as a datetime."""
    m = re.fullmatch(r"\s*(\d{4})/(\d{1,2})/(\d{1,2})\s*", date or "")
    t = re.fullmatch(r"\s*(\d{1,2}):(\d{2}):(\d{2})(?:[.,](\d+))?\s*", time or "")
    if not m or not t:
        return None
    frac = float("0." + t.group(4)) if t.group(4) else 0.0
    try:
        base = datetime(int(m.group(1)), int(m.group(2)), int(m.group(3)))
    except ValueError:
        return None
    secs = int(t.group(1)) * 3600 + int(t.group(2)) * 60 + int(t.group(3)) + frac
    return base + timedelta(seconds=secs)


class _Segment:
    def __init__(self, index: int, header: dict[str, list[str]], line: int):
        self.index = index
        self.header = header
        self.line = line  # 1-based line of its column-name row
        self.names: list[str] = []
        self.x_cols: list[int] = []
        self.y_cols: list[int] = []
        self.comment_col: int | None = None
        self.rows: list[tuple[int, list[str]]] = []


def read_lvm(path: Path, spec: FileSpec | None = None) -> Table:
    """Read a LabVIEW ``.lvm`` file into a :class:`Table` (see the module docstring).

    Parameters
    ----------
    path : path-like
        The file (read-only).
    spec : FileSpec, optional
        The channel map's ``[file]`` section (``separator``, ``decimal``, ``encoding``).

    Raises
    ------
    RecordingError
        Not an LVM file, a header without data, a cell that is not a number (line and column
        named), rows with more cells than the column names, segments with different channels,
        a segment whose time goes backwards.
    """
    path = Path(path)
    spec = spec or FileSpec()
    notes: list[str] = []
    text = whole_text(
        path,
        spec.encoding,
        notes,
        fallback="cp1252",
        fallback_name="Windows-1252 (LabVIEW's usual code page)",
        binary_hint="not a LabVIEW .lvm file",
        end=text_end(path, spec, notes),
    )
    lines = re.split(r"\r\n|\r|\n", text)
    ends_with_newline = text.endswith(("\n", "\r"))
    if lines and lines[-1] == "":
        lines.pop()
    if not lines[0].startswith("LabVIEW Measurement"):
        raise RecordingError(
            f"{path}: not a LabVIEW Measurement file (the first line is {lines[0][:60]!r}, "
            "expected 'LabVIEW Measurement'); read it as CSV with format='csv' (or rename it "
            "to .csv)"
        )

    # --- file header
    sep = None
    file_header: dict[str, str] = {}
    k = 1
    while k < len(lines) and not lines[k].startswith(_END):
        line = lines[k]
        if line.startswith("Separator") and len(line) > 9:
            value = line[10:].strip().lower()
            sep = _SEPARATOR_NAMES.get(value, line[9])
        k += 1
    if k >= len(lines):
        raise RecordingError(f"{path}: the LVM file header has no {_END} line; file cut short?")
    sep = spec.separator or sep or "\t"
    for line in lines[1:k]:
        cells = line.split(sep) if sep != " " else line.split()
        if len(cells) >= 2:
            file_header[cells[0].strip()] = cells[1].strip()
    decimal = spec.decimal or file_header.get("Decimal_Separator") or "."
    if decimal not in (".", ","):
        raise RecordingError(
            f"{path}: Decimal_Separator {decimal!r} in the LVM header is not '.' or ','; "
            "give [file] decimal in the channel map"
        )
    if sep == decimal:
        raise RecordingError(f"{path}: separator and decimal mark are both {sep!r}")
    x_columns = file_header.get("X_Columns", "One")
    if x_columns not in ("No", "One", "Multi"):
        raise RecordingError(
            f"{path}: X_Columns {x_columns!r} in the LVM header is not No, One or Multi"
        )
    if decimal == ",":
        notes.append("LVM decimal comma (Decimal_Separator in the header)")

    def split(line: str) -> list[str]:
        return line.split(sep) if sep != " " else line.split()

    # --- segments
    segments: list[_Segment] = []
    header: dict[str, list[str]] = {}
    current: _Segment | None = None
    collecting = False  # inside a segment header
    in_special = False
    k += 1
    while k < len(lines):
        line = lines[k]
        cells = split(line)
        first = cells[0].strip() if cells else ""
        k += 1
        if in_special:
            in_special = first != "***End_Special***"
            continue
        if first == "***Start_Special***":
            in_special = True
            continue
        if not line.strip() or not line.strip(sep).strip():
            current = None  # a blank line ends the rows of a segment
            continue
        if first == _END:
            continue
        if first in _SEGMENT_TAGS:
            if not collecting or first == "Channels":
                header = {}
                collecting = True
            current = None
            header[first] = cells[1:]
            continue
        if first == "X_Value":
            collecting = False
            seg = _Segment(len(segments), header, k)
            seg.names = [c.strip() for c in cells]
            if seg.names and seg.names[-1] == "Comment":
                seg.comment_col = len(seg.names) - 1
            body = range(len(seg.names) if seg.comment_col is None else seg.comment_col)
            for j in body:
                (seg.x_cols if seg.names[j] == "X_Value" else seg.y_cols).append(j)
            y_names = unique_names([seg.names[j] or f"column {j + 1}" for j in seg.y_cols])
            for j, nm in zip(seg.y_cols, y_names, strict=True):
                seg.names[j] = nm
            segments.append(seg)
            current = seg
            continue
        if current is None:
            if segments and first != "" and not _looks_numeric(first, decimal):
                raise RecordingError(f"{path}: line {k}: unexpected {line[:60]!r} in the LVM file")
            if not segments:
                raise RecordingError(
                    f"{path}: line {k}: numbers before any 'X_Value' row of column names"
                )
            # a segment without its own header (Multi_Headings = No): same columns as before
            prev = segments[-1]
            seg = _Segment(len(segments), prev.header, k)
            seg.names, seg.x_cols, seg.y_cols = prev.names, prev.x_cols, prev.y_cols
            seg.comment_col = prev.comment_col
            segments.append(seg)
            current = seg
        current.rows.append((k, cells))
    segments = [s for s in segments if s.rows]
    if not segments:
        raise RecordingError(f"{path}: the LVM file has a header but no data rows")

    # --- channels per segment
    per_channel: dict[str, list[tuple[np.ndarray, np.ndarray | None]]] = {}
    units: dict[str, str | None] = {}
    order: list[str] = []
    comments = 0
    origin: list[int] = []  # whole seconds of LabVIEW absolute times (_x_values), once decided
    for seg in segments:
        n_cols = len(seg.names) if seg.comment_col is None else seg.comment_col
        last_line = seg.rows[-1][0]
        if len(seg.rows[-1][1]) < n_cols and last_line == len(lines) and not ends_with_newline:
            seg.rows.pop()
            notes.append(f"last line {last_line} is cut short (no line end): dropped")
            if not seg.rows:
                continue
        width = max(len(c) for _, c in seg.rows)
        cells = np.full((len(seg.rows), max(width, n_cols)), "", dtype=object)
        for r, (ln, c) in enumerate(seg.rows):
            if len(c) > n_cols + (1 if seg.comment_col is not None else 0):
                raise RecordingError(
                    f"{path}: line {ln} has {len(c)} cells, the column names (line {seg.line}) "
                    f"{len(seg.names)}"
                )
            cells[r, : len(c)] = c
        if seg.comment_col is not None and cells.shape[1] > seg.comment_col:
            comments += int(np.count_nonzero(cells[:, seg.comment_col] != ""))
        y_names = [seg.names[j] for j in seg.y_cols]
        if segments[0] is not seg and y_names != [segments[0].names[j] for j in segments[0].y_cols]:
            raise RecordingError(
                f"{path}: segment {seg.index + 1} (line {seg.line}) has channels {y_names}, "
                f"segment 1 has {[segments[0].names[j] for j in segments[0].y_cols]}; "
                "split the file or export one channel set per file"
            )
        shared_x = None
        if x_columns == "One" and seg.x_cols:
            shared_x = seg.x_cols[0]
        for j in seg.y_cols:
            name = seg.names[j]
            col = cells[:, j]
            filled = col != ""
            n = int(filled.sum())
            if n and not filled[:n].all():
                r = int(np.flatnonzero(~filled[:n])[0])
                raise RecordingError(
                    f"{path}: line {seg.rows[r][0]}: channel {name!r} has an empty cell between "
                    "samples"
                )
            values = _column(path, seg, j, col[:n], decimal)
            if x_columns == "Multi":
                xj = j - 1 if j - 1 in seg.x_cols else None
            else:
                xj = shared_x
            own = None
            if xj is not None and np.count_nonzero(cells[:n, xj] != "") == n:
                own = _x_values(path, seg, xj, cells[:n, xj], decimal, origin)
            else:
                x0 = seg.header.get("X0", [])[j - 1 : j]
                dx = _header_value(seg.header, "Delta_X", j, decimal)
                if dx is not None and dx > 0:
                    start = _x_values(path, seg, j, np.array(x0 or ["0"]), decimal, origin)[0]
                    own = start + np.arange(n) * dx
            per_channel.setdefault(name, []).append((values, own))
            if name not in order:
                order.append(name)
                labels = seg.header.get("Y_Unit_Label", [])
                units[name] = (labels[j - 1].strip() or None) if j - 1 < len(labels) else None
    if comments:
        notes.append(f"{comments} LVM comment cell(s) not read")
    if len(segments) > 1:
        notes.append(f"{len(segments)} LVM segments joined in file order")

    columns: dict[str, Column] = {}
    for name in order:
        parts = per_channel[name]
        values = np.concatenate([v for v, _ in parts])
        if any(t is None for _, t in parts):
            columns[name] = Column(values, units[name], None)
            continue
        times = _join_times(path, name, parts, segments, notes)
        columns[name] = Column(values, units[name], times)
    first_time = next((c.time for c in columns.values() if c.time is not None), None)
    if first_time is not None and first_time.size and origin and origin[0]:
        t0 = float(first_time[0])  # since the whole seconds origin[0]
        notes.append(
            f"LVM absolute times (s since 1904-01-01) made relative to {origin[0] + t0:.6f} s "
            f"({_EPOCH_1904 + timedelta(seconds=origin[0] + t0)})"
        )
        for c in columns.values():
            if c.time is not None:
                c.time = c.time - t0
    table = Table(
        names=list(columns),
        load=lambda n: columns[n],
        base={n: n for n in columns},
        notes=notes,
        own_time_exact=True,
    )
    if x_columns == "One" and segments[0].x_cols and first_time is not None:
        # the shared X column is also addressable, e.g. [time] column = "X_Value"
        x_time = columns[order[0]].time if order else None
        if x_time is not None and all(
            c.time is not None and c.time.size == x_time.size and np.array_equal(c.time, x_time)
            for c in columns.values()
        ):
            columns["X_Value"] = Column(x_time.copy(), "s", None)
            table.names.insert(0, "X_Value")
            table.base["X_Value"] = "time"  # the default map takes it as the time column
            add_alias(table, "time", "X_Value")
    return table


def _looks_numeric(cell: str, decimal: str) -> bool:
    try:
        _number(cell, decimal)
    except ValueError:
        return False
    return True


def _column(path: Path, seg: _Segment, col: int, cells: np.ndarray, decimal: str) -> np.ndarray:
    """Cells of one column as floats; a cell that is not a number is an error naming its line."""
    text = cells.astype(str)
    if decimal == ",":
        text = np.char.replace(text, ",", ".")
    try:
        return text.astype(object).astype(float)
    except ValueError:
        pass
    for row, cell in enumerate(cells):
        try:
            _number(str(cell), decimal)
        except ValueError:
            raise RecordingError(
                f"{path}: line {seg.rows[row][0]}, column {seg.names[col]!r} (column {col + 1}): "
                f"{cell!r} is not a number (decimal mark {decimal!r})"
            ) from None
    raise RecordingError(f"{path}: column {seg.names[col]!r} is not numeric")  # pragma: no cover


def _x_values(
    path: Path, seg: _Segment, col: int, cells: np.ndarray, decimal: str, origin: list[int]
) -> np.ndarray:
    """X values (column ``col``'s cells, or an ``X0``) [s], less ``origin[0]`` whole seconds.

    LabVIEW's absolute times are seconds since 1904 (about 3.8e9), where a float64 steps by
    0.48 µs: summed or parsed at that size, 10 kHz read as 9 986 Hz and every step jittered.
    The first X value decides ``origin`` (its whole seconds where it is absolute, else 0);
    absolute values are then parsed exactly less the origin (:func:`exact_offsets`).
    """

    def plain(cell) -> str:
        text = str(cell).strip()
        return text.replace(",", ".") if decimal == "," else text

    if not origin:
        try:
            first = Decimal(plain(cells[0])) if len(cells) else Decimal(0)
        except InvalidOperation:
            first = Decimal(0)  # not a number: _column names the cell
        origin.append(int(first) if first.is_finite() and first > _ABSOLUTE_X else 0)
    if not origin[0]:  # relative times: the floats are exact enough, read at numpy's speed
        return _column(path, seg, col, cells, decimal)
    found = exact_offsets(cells, decimal, origin[0])
    if found is None:
        return _column(path, seg, col, cells, decimal)  # names the cell that is no number
    return found[0]


def _header_value(header: dict[str, list[str]], tag: str, col: int, decimal: str) -> float | None:
    """The segment-header value of ``tag`` under column ``col`` (the tag is column 0)."""
    values = header.get(tag, [])
    if col - 1 >= len(values) or not values[col - 1].strip():
        return None
    try:
        return _number(values[col - 1], decimal)
    except ValueError:
        return None


def _join_times(path, name, parts, segments, notes) -> np.ndarray:
    times = [t for _, t in parts]
    out = [times[0]]
    start0 = _segment_start(segments[0], name)
    for s, t in enumerate(times[1:], start=1):
        prev_end = out[-1][-1] if out[-1].size else -np.inf
        if t.size and t[0] <= prev_end:
            start = _segment_start(segments[s], name)
            if start is None or start0 is None:
                raise RecordingError(
                    f"{path}: segment {s + 1} (line {segments[s].line}) restarts its time at "
                    f"{t[0]:.6g} s before segment {s} ends ({prev_end:.6g} s) and its header "
                    "gives no Date/Time to place it; split the file into its segments"
                )
            shifted = t - t[0] + times[0][0] + (start - start0).total_seconds()
            if shifted[0] <= prev_end:
                raise RecordingError(
                    f"{path}: segment {s + 1} (line {segments[s].line}) starts at {start} "
                    f"({shifted[0]:.6g} s), before segment {s} ends ({prev_end:.6g} s)"
                )
            msg = (
                f"LVM segment {s + 1} restarts its time; placed by its header Date/Time at "
                f"{shifted[0]:.6g} s"
            )
            if msg not in notes:
                notes.append(msg)
            t = shifted
        out.append(t)
    return np.concatenate(out)


def _segment_start(seg: _Segment, name: str) -> datetime | None:
    col = next(j for j in seg.y_cols if seg.names[j] == name) - 1
    dates, times = seg.header.get("Date", []), seg.header.get("Time", [])
    if col >= len(dates) or col >= len(times):
        return None
    return _stamp(dates[col], times[col])
