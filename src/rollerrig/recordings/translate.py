"""A file's columns translated by a channel map into canonical channels in SI units.

:func:`apply_map` takes a format reader's :class:`~rollerrig.recordings.formats.Table` and the
channel map (:mod:`rollerrig.recordings.channels`) and gives the time [s] and the channels in SI
units, on one common time base (:mod:`rollerrig.recordings.timebase`):

- each map entry names a file column (:func:`resolve_column`: a missing or ambiguous column is
  an error with close matches; entries the caller does not need, and ``optional`` ones, are
  noted instead), or, without a map, the file's own names (:func:`auto_entries`);
- cells are numbers (:func:`as_float`: NaN/inf words, the file's decimal and thousands
  marks) converted with the map's unit, scale and offset; the time is a column
  (:func:`time_seconds`: numbers in a time unit, or date/time strings), the map's sample
  rate (checked against the file's own rate), or the channels' own time bases (TDMS
  waveforms, MDF masters, LVM X columns).

Both :func:`rollerrig.recordings.readers.read_recording` and the chunked reader
(:mod:`rollerrig.recordings.source`) resolve the map through this module.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig.output.varnames import ORIGINAL_NAME
from rollerrig.recordings.channels import (
    RATE_TOLERANCE,
    TIME_UNITS,
    ChannelMap,
    ChannelSpec,
    FileSpec,
    normalize_unit,
    time_named,
    time_unit,
)
from rollerrig.recordings.formats import Table
from rollerrig.recordings.formats._table import require_module
from rollerrig.recordings.formats._text import (
    EXACT_ABOVE,
    GROUP_MARKS,
    NAN_WORDS,
    NEGATIVE_INFINITY_WORDS,
    POSITIVE_INFINITY_WORDS,
    decimal_marks,
    exact_offsets,
    parse_number,
    without_group_marks,
)
from rollerrig.recordings.formats.timestamps import looks_like_timestamp, parse_timestamps
from rollerrig.recordings.recording import CANONICAL_CHANNELS, RecordingError
from rollerrig.recordings.timebase import align_channels
from rollerrig.recordings.validate import check_serial_days

__all__ = [
    "apply_map",
    "as_float",
    "auto_entries",
    "resolve_column",
    "text_decimal",
    "time_seconds",
]


def resolve_column(
    table: Table,
    column: str,
    entry: str,
    cmap: ChannelMap,
    path: Path,
    *,
    skip: str | None = None,
) -> str | None:
    """The file column that ``column`` names; missing or ambiguous: an error with close matches.

    A name the file gives to several columns (:attr:`Table.repeated`) is ambiguous alone: its
    columns are ``name.0`` (the first), ``name.1``, ... in the file's order.

    With ``skip`` (why the entry may be absent, e.g. ``"optional"``), a missing or ambiguous
    column is noted in ``table.notes`` instead, and None is returned.
    """
    first_of = column.removesuffix(".0")
    if first_of != column and first_of in table.repeated and column not in table.names:
        return table.repeated[first_of][0]  # "Torque.0": the first of the columns so named
    if column in table.repeated:
        candidates = [f"{column}.0", *table.repeated[column][1:]]
    elif column in table.names:
        return column
    else:
        candidates = table.aliases.get(column, [])
    if len(candidates) == 1:
        return candidates[0]
    pool = table.names + [a for a in table.aliases if a not in table.names]
    close = difflib.get_close_matches(column, pool, n=3, cutoff=0.6)
    if skip is not None:
        problem = f"ambiguous: {candidates}" if candidates else "not in the file"
        table.notes.append(
            f"channel map entry {entry} ({skip}) not read: column {column!r} is {problem}"
            + (f"; close matches: {close}" if close and not candidates else "")
        )
        return None
    if len(candidates) > 1:
        how = (
            f"but the file has {len(candidates)} columns of that name; the reader calls them "
            f"{candidates} in the file's order: name one of those"
            if column in table.repeated
            else f"which is ambiguous in the file: {candidates}; give the full name"
        )
        raise RecordingError(
            f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, " + how
        )
    unreadable = [s for s in table.skipped if s.startswith(f"{column} (")]
    if unreadable:
        raise RecordingError(
            f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, "
            f"which the file holds but cannot be read as numbers: {unreadable[0]}"
        )
    shown = table.names if len(table.names) <= 60 else [*table.names[:60], "..."]
    raise RecordingError(
        f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, "
        f"which is not in the file"
        + (f"; close matches: {close}" if close else "")
        + f"; available columns: {shown}"
        + (f"; not readable: {table.skipped}" if table.skipped else "")
        + (table.locate(column) if table.locate is not None else "")
    )


def as_float(
    values: np.ndarray,
    what: str,
    line_of=None,
    decimal: str | None = None,
    memo: dict | None = None,
    row_offset: int = 0,
) -> np.ndarray:
    """Numbers of a column; NaN/inf words (``NaN``, ``inf``, PicoScope's ``∞``) become NaN/inf.

    ``line_of`` maps a row to its 1-based file line (text files) for the error message.
    ``decimal`` is the decimal mark where it is known (:attr:`Table.decimal`, or the map's
    ``[file] decimal``): a text cell with the other mark is then read as a number only in
    strict groups of three (``1,000`` is 1000 under ``"."``), never as a decimal point
    (``1.5`` under ``","`` is an error). Where it is not known, the column's own cells decide
    it (``0,5`` can only be a decimal comma, ``1,000.5`` only a decimal point; both kinds in one
    column are an error), and a column whose cells all read both ways (``1,000``) is refused,
    naming both readings: read as 1.0, a torque of 1000 N.m written with a thousands comma
    beyond the rows a layout was sniffed from was 1 N.m. ``memo`` (one dict per file, shared
    by its columns and the chunks of a file read in chunks) keeps the mark a column decided
    for the columns and parts after it: one file, one decimal mark. ``row_offset`` is the
    column's first row in the file's samples (a part read in chunks), for the message.
    """
    arr = np.asarray(values)
    if arr.dtype.kind in "biuf":
        return arr.astype(float)
    if arr.dtype.kind in "OUT":
        pd = require_module("pandas", "text columns")
        text, is_str, words, marked = _text_cells(arr, pd)
        infinite = np.isin(words, list(POSITIVE_INFINITY_WORDS))
        neg_inf = np.isin(words, list(NEGATIVE_INFINITY_WORDS))
        memo = memo if memo is not None else {}
        values = np.array(text, dtype=object)  # a copy, any dtype
        if decimal is None and "mark" not in memo:
            found = _column_mark(values[marked])
            if found is not None:
                memo["mark"], memo["cell"] = found
        mark = decimal if decimal is not None else memo.get("mark")
        if marked.any():
            cells = pd.Series(values[marked], dtype=object)
            values[marked] = _marked_values(cells, mark, pd)
        num = pd.to_numeric(pd.Series(values, dtype=object), errors="coerce")
        num = num.to_numpy(dtype=float, copy=True)
        num[infinite] = np.inf
        num[neg_inf] = -np.inf
        known = np.isin(words, list(NAN_WORDS)) | (is_str & (words == ""))
        bad = np.isnan(num) & ~pd.isna(text) & ~known
        if not bad.any():
            return num
        k = int(np.flatnonzero(bad)[0])
        cell = str(arr[k]).strip()
        if decimal is None and mark is not None and decimal_marks(cell) == {_other(mark)}:
            pair = {mark: memo["cell"], _other(mark): cell}
            raise RecordingError(
                f"{what} mixes decimal marks ({pair[',']!r} and {pair['.']!r}); give "
                '[file] decimal = "." or "," in the channel map'
            )
        line = line_of(k) if line_of is not None else None
        raise RecordingError(
            f"{what} has {int(bad.sum())} non-numeric entries, first at row {row_offset + k}: "
            f"{arr[k]!r}"
            + (f" (file line {line})" if line is not None else "")
            + _why_not_a_number(cell, decimal, mark)
        )
    if arr.dtype.kind in "SU" and arr.size:
        shown = [v.decode(errors="replace") if isinstance(v, bytes) else str(v) for v in arr[:3]]
        raise RecordingError(
            f"{what} holds text, not numbers ({shown}, ...): a state or status channel (an MDF "
            "value-to-text conversion, a gear or mode name); map a numeric channel"
        )
    raise RecordingError(f"{what} is not numeric (dtype {arr.dtype})")


def text_decimal(table: Table, cmap: ChannelMap) -> str | None:
    """The decimal mark of a file's text cells where it is known: the text reader's (given or
    sniffed), else the map's ``[file] decimal`` (which the readers of other formats, whose
    text columns are rare, do not see)."""
    return table.decimal if table.decimal is not None else cmap.file.decimal


def _text_cells(arr: np.ndarray, pd) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(cells stripped, is text, lower-case words, has a . or ,)`` of an object column, as
    object, bool, object and bool arrays. A column of text only (and missing cells) is done by
    numpy's string functions at once, any other cell by cell (a cell-by-cell map over a column
    of text made a 500 000-row file read 6 times slower)."""
    obj = np.asarray(arr, dtype=object)
    if pd.api.types.infer_dtype(obj, skipna=True) in ("string", "empty"):
        missing = pd.isna(obj)
        cells = np.char.strip(np.where(missing, "", obj).astype(str))
        grouped = np.zeros(cells.shape, dtype=bool)
        for mark in GROUP_MARKS:
            grouped |= np.char.find(cells, mark) >= 0
        if grouped.any():  # 1 500,00 / 1'800.00: the thousands marks go, in strict groups only
            cells = cells.astype(object)
            cells[grouped] = [without_group_marks(c) for c in cells[grouped]]
            cells = cells.astype(str)
        text = cells.astype(object)
        text[missing] = obj[missing]
        words = np.char.lower(cells).astype(object)
        marked = (np.char.find(cells, ",") >= 0) | (np.char.find(cells, ".") >= 0)
        return text, ~missing, words, marked
    series = pd.Series(obj, dtype=object).map(
        lambda v: without_group_marks(v.strip()) if isinstance(v, str) else v
    )
    is_str = series.map(lambda v: isinstance(v, str)).to_numpy(dtype=bool)
    words = series.map(lambda v: v.lower() if isinstance(v, str) else "").to_numpy(dtype=object)
    marked = series.map(lambda v: isinstance(v, str) and ("," in v or "." in v))
    return series.to_numpy(dtype=object), is_str, words, marked.to_numpy(dtype=bool)


def _other(mark: str) -> str:
    return "," if mark == "." else "."


def _column_mark(cells) -> tuple[str, str] | None:
    """``(mark, cell)``: the decimal mark that the first cell one mark alone makes a number
    decides (``0,5``: a decimal comma), where the file's is unknown; None where every cell reads
    both ways (``1,000``: refused, naming both readings). A later cell only the other mark
    reads is then an error naming both (:func:`as_float`). Plain integers beside ``1,000``
    decide only within the rows the layout is sniffed from, where every column is seen
    (:func:`~rollerrig.recordings.formats._text.thousands_mark_beside_integers`): a column
    alone read them as thousands marks although another column's ``0,5`` beyond those rows
    said decimal commas."""
    for cell in cells:
        marks = decimal_marks(cell)
        if len(marks) == 1:
            return next(iter(marks)), cell
    return None


def _marked_values(cells, mark: str | None, pd):
    """The numbers of text cells with a ``.`` or ``,`` under the decimal mark ``mark`` (NaN
    where a cell is none, and everywhere without a mark): a cell with the mark alone converted
    by pandas at once (the decimal comma made a point first), one with the other mark only as
    strict thousands groups (:func:`~rollerrig.recordings.formats._text.parse_number`), cell
    by cell; pandas never reads the other mark as a decimal point."""
    if mark is None:
        return np.full(len(cells), np.nan)
    other = _other(mark)
    with_other = cells.str.contains(other, regex=False).to_numpy(dtype=bool)
    out = np.full(len(cells), np.nan)
    plain = cells[~with_other]
    if mark == ",":
        plain = plain.str.replace(",", ".", regex=False)
    out[~with_other] = pd.to_numeric(plain, errors="coerce").to_numpy(dtype=float)
    if with_other.any():
        grouped = cells[with_other].map(lambda v: parse_number(v, mark))
        out[with_other] = grouped.map(lambda v: np.nan if v is None else v).to_numpy(dtype=float)
    return out


def _why_not_a_number(cell: str, decimal: str | None, mark: str | None) -> str:
    """Why a cell with a ``.`` or ``,`` is not a number here, and what to do ("" otherwise)."""
    marks = decimal_marks(cell)
    if mark is None and len(marks) == 2:
        return (
            f": {cell!r} is {parse_number(cell, '.'):g} under a decimal point or "
            f"{parse_number(cell, ','):g} under a decimal comma (the other mark a thousands "
            "mark); give [file] decimal in the channel map"
        )
    if mark is not None and marks:
        other = "," if mark == "." else "."
        how = "the file's" if decimal is not None else "the column's"
        return (
            f": {how} decimal mark is {mark!r}, and {other!r} is a thousands mark only in "
            "groups of three digits; fix the cell or give [file] decimal in the channel map"
        )
    return ""


def time_seconds(
    values: np.ndarray,
    unit: str,
    what: str,
    notes: list,
    *,
    file: FileSpec | None = None,
    line_of=None,
    decided: dict | None = None,
    decimal: str | None = None,
    anchors: int = 0,
    first_row: int = 0,
) -> np.ndarray:
    """A time column in seconds: numbers in ``unit``, or date/time strings (one format for the
    whole column, from ``[file] date_format`` / ``dayfirst``; see
    :func:`rollerrig.recordings.formats.timestamps.parse_timestamps`) as seconds since the first
    sample.

    ``decided``: for a column read in chunks, one dict passed with every chunk, so that every
    chunk's timestamps are read in the format decided for the first. ``decimal``: the file's
    decimal mark where known (:func:`as_float`). ``anchors``, ``first_row``: for a part of the
    column read alone, the rows before it that are no neighbours of its own (the file's first
    sample) and where it starts (see
    :func:`~rollerrig.recordings.formats.timestamps.parse_timestamps`)."""
    file = file or FileSpec()
    arr = np.asarray(values)
    if arr.dtype.kind in "OUT":
        first = _first_text(arr)
        if file.date_format is not None or looks_like_timestamp(first):
            secs, note = parse_timestamps(
                arr,
                what=what,
                dayfirst=file.dayfirst,
                date_format=file.date_format,
                line_of=line_of,
                decided=decided,
                anchors=anchors,
                first_row=first_row,
            )
            notes.append(note)
            return secs
        if _DURATION.fullmatch(first):
            return _durations(arr, what, notes, line_of, decimal)
        exact = _exact_time(arr, first, unit, notes, decimal)
        if exact is not None:
            return exact
        raw = as_float(arr, what, line_of, decimal)
        check_serial_days(raw, what)
        return raw * TIME_UNITS[unit]
    if arr.dtype.kind == "m":  # elapsed time (pandas' Timedelta, Parquet's duration)
        return arr / np.timedelta64(1, "s")
    if arr.dtype.kind == "M":
        t0 = arr[0]
        notes.append(f"absolute timestamps converted to seconds since the first sample ({t0})")
        return (arr - t0) / np.timedelta64(1, "s")
    if arr.dtype.kind in "iu" and arr.size and abs(int(arr.flat[0])) >= _EPOCH_COUNT:
        # Epoch counts (time.time_ns() loggers): as floats, 1.7e18 ns is 1.7e9 s to 0.24 µs, a
        # 51.2 kS/s clock read with steps of 19.3-19.8 µs; the integers' difference is exact.
        memo = {} if decided is None else decided  # one origin for every chunk
        if "origin" not in memo:
            memo["origin"] = int(arr.flat[0])
            notes.append(
                f"integer time column made relative to its first value ({memo['origin']} "
                f"{unit}), exactly"
            )
        origin = memo["origin"]
        since = (
            arr.astype(np.int64) - np.int64(origin)
            if arr.dtype.kind == "i"
            else ((arr - np.uint64(origin)).astype(np.int64))
        )
        return since.astype(float) * TIME_UNITS[unit]
    raw = as_float(arr, what, decimal=decimal)
    check_serial_days(raw, what)
    return raw * TIME_UNITS[unit]


def _exact_time(arr, first: str, unit: str, notes: list, decimal: str | None) -> np.ndarray | None:
    """Seconds since the first value of a text column of large numbers (absolute times since
    an epoch, :data:`~rollerrig.recordings.formats._text.EXACT_ABOVE` and more), each
    difference exact (:func:`~rollerrig.recordings.formats._text.exact_offsets`); None for
    other columns, and for cells that are not plain numbers (:func:`as_float` names them).

    Read as floats first, a LabVIEW time of 3.8e9 s keeps its fraction only to 0.48 µs: a
    100 kHz clock read as 99 864 Hz. The text readers keep such columns as text
    (:class:`~rollerrig.recordings.formats.sniff.TextLayout` ``exact``) for this. A chunk of
    a column read in parts comes with the column's first value before it (the chunked
    reader), so every part has the same origin."""
    mark = decimal or "."
    head = parse_number(first, mark)
    if head is None or not abs(head) >= EXACT_ABOVE:
        return None
    found = exact_offsets(np.asarray(arr, dtype=object).ravel(), mark)
    if found is None:
        return None
    since, _ = found
    note = (
        f"time column made relative to its first value ({first} {unit}), read exactly (not "
        "rounded to a float first)"
    )
    if note not in notes:
        notes.append(note)
    start = since[0] if since.size and np.isfinite(since[0]) else 0.0  # below 1: exact enough
    return (since - start) * TIME_UNITS[unit]


_DURATION = re.compile(
    r"(?P<value>[-+]?(?:\d+[.,]?\d*|[.,]\d+)(?:[eE][-+]?\d+)?)\s*"
    r"(?P<unit>secs?|s|ms|msec|mins?|hrs?|h|days?)"
)
"""A duration with its unit in the cell, as MATLAB's ``writetimetable`` writes a timetable's
row times (``0.001 sec``, ``1.5 min``)."""
_DURATION_SECONDS = {
    "sec": 1.0, "secs": 1.0, "s": 1.0, "ms": 1e-3, "msec": 1e-3, "min": 60.0, "mins": 60.0,
    "hr": 3600.0, "hrs": 3600.0, "h": 3600.0, "day": 86400.0, "days": 86400.0,
}  # fmt: skip


def _durations(arr, what: str, notes: list, line_of, decimal: str | None) -> np.ndarray:
    """Seconds of a column of durations with their unit in each cell (:data:`_DURATION`)."""
    cells = [str(v).strip() for v in np.asarray(arr).ravel()]
    out = np.empty(len(cells))
    for k, cell in enumerate(cells):
        m = _DURATION.fullmatch(cell)
        if m is None:
            line = line_of(k) if line_of is not None else None
            raise RecordingError(
                f"{what}: row {k}"
                + (f" (file line {line})" if line is not None else "")
                + f" {cell!r} is not a duration like the column's first ('0.001 sec')"
            )
        value = parse_number(m["value"], decimal or ".")
        if value is None:
            raise RecordingError(
                f"{what}: row {k} {cell!r}: {m['value']!r} is no number under the file's "
                f"decimal mark {decimal or '.'!r}"
            )
        out[k] = value * _DURATION_SECONDS[m["unit"]]
    notes.append(
        "durations with their unit in each cell ('0.001 sec', MATLAB's timetables) read in seconds"
    )
    return out


_EPOCH_SPAN_S = (631_152_000.0, 4_102_444_800.0)
"""Unix times [s] of 1990-01-01 and 2100-01-01 UTC: a time column's first value read in a unit
is a plausible absolute time (an epoch count) between them."""

_EPOCH_UNITS = ("s", "ms", "us", "ns")
"""Units of epoch counts, about 1.7e9, 1.7e12, 1.7e15 and 1.7e18 in 2024 (keys of TIME_UNITS)."""


def _head_numbers(values, decimal: str | None, n: int = 1001) -> tuple[str, np.ndarray] | None:
    """``(first as written, [first, offsets of the first n values from it...])`` of a numeric
    time column, as floats (the offsets of integers exact); None where they are no numbers."""
    arr = np.asarray(values).ravel()[:n]
    if arr.dtype.kind in "iu" and arr.size:
        first = int(arr[0])
        steps = (arr.astype(object) - first).astype(float)  # exact differences, any magnitude
        return str(first), np.concatenate([[float(first)], steps])
    if arr.dtype.kind == "f":
        ok = arr[np.isfinite(arr)]
        return (repr(float(ok[0])), np.concatenate([[ok[0]], ok - ok[0]])) if ok.size else None
    if arr.dtype.kind in "OUS":
        cells = [str(v).strip() for v in arr if str(v).strip()]
        pairs = [(c, parse_number(c, decimal or ".")) for c in cells]
        pairs = [(c, x) for c, x in pairs if x is not None and np.isfinite(x)]
        if not pairs:
            return None
        nums = np.array([x for _, x in pairs])
        return pairs[0][0], np.concatenate([[nums[0]], nums - nums[0]])
    return None


def _epoch_unit(
    values, unit: str, assumed: bool, what: str, notes: list, decimal: str | None
) -> str | None:
    """The unit a numeric time column is read in where its values are an epoch count that only
    another unit makes a plausible date (:data:`_EPOCH_SPAN_S`): microseconds since 1970,
    1.7e15, had been read as seconds with a warning that advised milliseconds, and read so
    gave 1 Hz without a word. None: ``unit`` stands.

    Where the unit was ``assumed`` (none in the file or the map) the column is read in the
    unit that makes it a date, with a note. Where it was stated, a rate that the stated unit
    makes implausible for a rig (below :data:`~rollerrig.recordings.validate
    .MIN_PLAUSIBLE_RATE_HZ` or above :data:`~rollerrig.recordings.validate.MAX_SAMPLE_RATE_HZ`)
    and that the epoch's unit makes plausible is an error naming that unit (a stated unit and a
    plausible rate stand: a monotonic count in ns since boot is no epoch).
    """
    from rollerrig.recordings.validate import MAX_SAMPLE_RATE_HZ, MIN_PLAUSIBLE_RATE_HZ

    found_head = _head_numbers(values, decimal)
    if found_head is None:
        return None
    shown, head = found_head
    if not np.isfinite(head[0]) or abs(head[0]) < _EPOCH_SPAN_S[0]:
        return None  # an elapsed time (small numbers) is no epoch
    first = float(head[0])
    lo, hi = _EPOCH_SPAN_S
    fits = [u for u in _EPOCH_UNITS if lo <= first * TIME_UNITS[u] <= hi]
    if len(fits) != 1 or unit in fits:
        return None
    found = fits[0]
    date = np.datetime64(round(first * TIME_UNITS[found] * 1e3), "ms")
    steps = np.diff(head[1:])
    steps = steps[np.isfinite(steps) & (steps > 0)]
    step = float(np.median(steps)) if steps.size else float("nan")

    def rate(u: str) -> float:
        return 1.0 / (step * TIME_UNITS[u]) if step > 0 else float("nan")

    def plausible(u: str) -> bool:
        return MIN_PLAUSIBLE_RATE_HZ <= rate(u) <= MAX_SAMPLE_RATE_HZ

    if assumed:
        notes.append(
            f"{what.split(': ', 1)[-1]} has no unit; its first value {shown} is a date only "
            f"in {found!r} ({date} UTC since 1970; {rate(found):.6g} Hz), so it was read in "
            f'{found!r}; declare it with unit = "{found}" in the channel map\'s [time] section'
        )
        return found
    if np.isfinite(rate(unit)) and not plausible(unit) and plausible(found):
        raise RecordingError(
            f"{what} read in {unit!r} gives {rate(unit):.4g} Hz, and its first value {shown} "
            f"{unit} is no date; in {found!r} it is {date} UTC (since 1970) at "
            f'{rate(found):.6g} Hz: give unit = "{found}" in the channel map\'s [time] '
            "section (and in the file's header, if it states one)"
        )
    return None


_EPOCH_COUNT = 1 << 32
"""An integer time column from this magnitude on counts from an epoch, not from the start: it
is made relative to its first value before it becomes a float (:func:`time_seconds`)."""


def _first_text(arr: np.ndarray) -> str:
    """The first non-blank cell of a text column (among its first 1000), stripped; "" if none."""
    return next((str(v).strip() for v in arr.ravel()[:1000] if str(v).strip()), "")


def _numeric_time(values, file: FileSpec) -> bool:
    """Whether a time column holds numbers in a unit (not date/time strings or datetimes)."""
    arr = np.asarray(values)
    if arr.dtype.kind in "biuf":
        return True
    if arr.dtype.kind not in "OUS":
        return False
    first = _first_text(arr)
    return file.date_format is None and not looks_like_timestamp(first)


def auto_entries(table: Table, cmap: ChannelMap, path: Path) -> list[ChannelSpec]:
    """The file's own names as channels (no map). In a file rollerrig wrote, a column named in
    its stored ``variables`` keeps that name whole (``[x]`` is not a unit there), and a column
    the writer renamed for the format (``oil_temp_bearing`` in a MAT file) gets its
    ``original_name`` back."""
    specs: list[ChannelSpec] = []
    seen: dict[str, str] = {}
    stored = table.stored_variables if isinstance(table.stored_variables, Mapping) else {}
    for name in table.names:
        base = table.base.get(name, name)
        if name in stored:  # rollerrig wrote this very name (not "name [unit]")
            base = name
        entry = stored.get(base)
        original = entry.get(ORIGINAL_NAME) if isinstance(entry, Mapping) else None
        if isinstance(original, str) and original and original != "time":
            base = original
        if base == "time":
            continue
        canonical = base in CANONICAL_CHANNELS
        if base in seen:
            if canonical:
                raise RecordingError(
                    f"{path}: canonical channel {base!r} occurs twice ({seen[base]!r}, {name!r}); "
                    "give a channel map"
                )
            continue
        seen[base] = name
        specs.append(ChannelSpec(base, name, None, canonical=canonical))
    return specs


def _table_seconds(table: Table, cmap: ChannelMap, values, unit: str, what: str, notes, line_of):
    """:func:`time_seconds` of a column of ``table``, with the map's file layout and the
    table's decimal mark."""
    return time_seconds(
        values, unit, what, notes, file=cmap.file, line_of=line_of,
        decimal=text_decimal(table, cmap),
    )  # fmt: skip


def _check_stated_rate(table: Table, cmap: ChannelMap, loaded: list, info: dict, path, line_of):
    """Raise when the map's ``[time] sample_rate_Hz`` contradicts the file's own rate.

    The file's rate is that of each channel's own time base (TDMS ``wf_increment``, MDF master,
    LVM X column) and of a column named like a time (``Time``, ``Zeit``, ``t``, ``X_Value``,
    ``Zeit  1 - Standardmessrate``: :func:`~rollerrig.recordings.channels.time_named`;
    numbers in its stated unit, else seconds or milliseconds, or timestamps). A difference of
    more than :data:`~rollerrig.recordings.channels.RATE_TOLERANCE` is an error naming both rates.
    """
    stated = cmap.time.sample_rate_Hz

    def off(rate: float) -> bool:
        return not np.isfinite(rate) or abs(rate - stated) > RATE_TOLERANCE * stated

    def fail(rate: float, source: str) -> None:
        raise RecordingError(
            f"{path}: the channel map's [time] sample_rate_Hz = {stated:g} Hz (map "
            f"{cmap.source}) contradicts the file's own rate of {rate:.6g} Hz ({source}); "
            "remove sample_rate_Hz to use the file's time base, or correct it"
        )

    def median_rate(t: np.ndarray) -> float:
        d = np.diff(t)
        d = d[np.isfinite(d)]
        med = float(np.median(d)) if d.size else 0.0
        return 1.0 / med if med > 0 else float("nan")

    if table.stated_rate and off(table.stated_rate):
        fail(table.stated_rate, "stated in its header: an oscilloscope's 1/Increment")
    for spec, _values, _si, own in loaded:
        if own is not None and own.size > 1:
            rate = median_rate(np.asarray(own, dtype=float))
            if off(rate):
                fail(rate, f"time base of column {info['columns'][spec.name]!r}")
    used = set(info["columns"].values())
    for name in table.names:
        base = str(table.base.get(name, name)).strip().lower()
        if name in used or not time_named(base):
            continue
        try:
            col = table.load(name)
            file_unit = time_unit(col.unit) if col.unit else None
            if col.unit and file_unit is None:
                continue  # named so, but in another unit (an MDF angle master): no time
            scratch: list[str] = []
            unit = file_unit or "s"
            secs = _table_seconds(
                table, cmap, col.values, unit, f"{path}: column {name!r}", scratch, line_of
            )
        except RecordingError:
            table.notes.append(
                f"column {name!r} looks like a time column but is not readable; "
                "the stated sample_rate_Hz was not checked against it"
            )
            continue
        if secs.size < 2:
            continue
        if not np.all(np.diff(secs) > 0):
            continue  # not increasing: no time base (a temperature 'T'), nothing to check
        rate = median_rate(secs)
        numeric = np.asarray(col.values).dtype.kind in "biuf"
        if off(rate) and not (numeric and file_unit is None and not off(rate * 1e3)):
            fail(rate, f"column {name!r}" + ("" if file_unit or not numeric else " read in s"))


def _time_column_hint(table: Table) -> str:
    """``; columns that may hold it: [...] ([time] column = "...")``: the file's columns named
    as a time (:func:`~rollerrig.recordings.channels.time_named`), or a pandas index stored in
    Parquet (``__index_level_0__``); "" where none."""
    found = [
        n
        for n in table.names
        if time_named(base := str(table.base.get(n, n)).strip().lower())
        or base == "__index_level_0__"
    ]
    if not found:
        return ""
    return f"; columns that may hold it: {found[:5]} (set [time] column = {str(found[0])!r})"


def foreign_time(table: Table, column: str, time_column: str | None, where: str) -> str | None:
    """The column the file names as ``column``'s own time base where that is not the map's time
    column ``time_column`` nor in its group (:attr:`Table.time_of`: a TDMS group's ``Time``
    channel, DIAdem style; a ControlDesk raster ``X(k)``); None otherwise (the channel is
    sampled with the time column, index by index).

    Raises
    ------
    RecordingError
        The channel's group holds several time channels: which one times it is not known.
    """
    times = table.time_of.get(column, ())
    if time_column is None or not times or time_column in times:
        return None
    if any(column in names and time_column in names for names in table.groups.values()):
        return None  # in the time column's group: sampled with it
    if len(times) > 1:
        raise RecordingError(
            f"{where} column {column!r} is in a group with several time channels {list(times)} "
            f"and not in the group of the [time] column {time_column!r}: which time it was "
            "sampled at is not known; map as [time] column the time channel of its group and "
            "read the other group's channels separately"
        )
    return times[0]


def _own_time(
    table: Table, column: str, time_col: str, values, unit: str, cmap, what: str, notes, line_of,
    read: dict[str, np.ndarray],
) -> np.ndarray:  # fmt: skip
    """Seconds of the time channel ``time_col`` that times ``column`` (:func:`foreign_time`):
    in its own unit where it states a time unit, else in the [time] column's ``unit``; each
    time channel loaded and read once (``read``: time channel -> seconds), whichever of its
    group's channels asks first."""
    secs = read.get(time_col)
    if secs is None:
        col = table.load(time_col)
        own_unit = (time_unit(col.unit) if col.unit else None) or unit
        secs = _table_seconds(
            table, cmap, col.values, own_unit, f"{what}: its time channel {time_col!r}", notes,
            line_of,
        )  # fmt: skip
        read[time_col] = secs
    if secs.size != np.asarray(values).size:
        raise RecordingError(
            f"{what} has {np.asarray(values).size} samples but its group's time channel "
            f"{time_col!r} has {secs.size}; the file is damaged or the channel is timed "
            "otherwise: map it with a [time] column of its own length (read it separately)"
        )
    return np.asarray(secs, dtype=float)


def apply_map(
    table: Table,
    cmap: ChannelMap,
    path: Path,
    needed: Iterable[str] | None = None,
    validate: str = "strict",
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, str], dict[str, Any]]:
    """Time [s] and channels in SI units from a table through the channel map.

    ``needed``: the channels the caller needs; entries not needed, and ``optional`` ones, are
    noted instead of failing when their column is missing (None: every entry is needed).
    ``validate``: as for :func:`~rollerrig.recordings.readers.read_recording`, for the NaN/inf
    samples of channels that are resampled onto the common time base
    (:func:`~rollerrig.recordings.timebase.align_channels`).
    """
    notes = table.notes
    info: dict[str, Any] = {"columns": {}, "source_units": {}}
    where = f"{path}:"
    needed = None if needed is None else set(needed)
    line_of = getattr(table, "line_of", None)  # text files: row -> file line

    # --- time from a column
    time = None
    tspec = cmap.time
    if tspec is not None and tspec.column is not None:
        col_name = None
        if cmap.auto:
            hits = [n for n in table.names if table.base.get(n, n) == tspec.column]
            col_name = hits[0] if hits else None
        else:
            col_name = resolve_column(table, tspec.column, "[time]", cmap, path)
        if col_name is not None:
            col = table.load(col_name)
            unit = tspec.unit
            file_unit = time_unit(col.unit) if col.unit else None
            if col.unit and file_unit is None and _numeric_time(col.values, cmap.file):
                # A unit this reader does not know: read as the map's default (seconds), a
                # time in msec was 1000 times too slow, without a word.
                if cmap.auto or not tspec.unit_stated:
                    raise RecordingError(
                        f"{where} time column {col_name!r} has unit {col.unit!r}, which is not "
                        f"a time unit this reader knows (allowed: {sorted(TIME_UNITS)}); give "
                        "[time] unit in the channel map"
                    )
                notes.append(
                    f"time column {col_name!r}: the file's unit {col.unit!r} is not a time unit "
                    f"this reader knows; the map's {unit!r} used"
                )
            elif cmap.auto and file_unit is not None:
                unit = file_unit
            elif file_unit is not None and file_unit != unit:
                if tspec.unit_stated:
                    raise RecordingError(
                        f"{where} channel map entry [time] (map {cmap.source}) says unit "
                        f"{unit!r} but column {col_name!r} says {col.unit!r}"
                    )
                unit = file_unit
                notes.append(f"time unit {col.unit!r} taken from the file (the map gives none)")
            assumed = file_unit is None and (cmap.auto or not tspec.unit_stated)
            epoch = None
            if _numeric_time(col.values, cmap.file):
                epoch = _epoch_unit(
                    col.values, unit, assumed, f"{where} time column {col_name!r}", notes,
                    text_decimal(table, cmap),
                )  # fmt: skip
            time = _table_seconds(
                table,
                cmap,
                col.values,
                epoch or unit,
                f"{where} time column {col_name!r}",
                notes,
                line_of,
            )
            info["columns"]["time"] = col_name
            info["source_units"]["time"] = epoch or unit
            if assumed and epoch is None:
                if np.asarray(col.values).dtype.kind in "biuf":  # numbers read in seconds
                    info["time_unit_assumed"] = unit  # popped by the readers: check_time_unit

    # --- channels
    specs = auto_entries(table, cmap, path) if cmap.auto else list(cmap.entries)
    loaded: list[tuple[ChannelSpec, np.ndarray, str, np.ndarray | None]] = []
    marks: dict = {}  # the decimal mark one column's cells decided, for the others (as_float)
    exact: set[str] = set()  # channels timed by their group's time channel (foreign_time)
    clocks: dict[str, list[str]] = {}  # that time channel -> those channels
    clock_seconds: dict[str, np.ndarray] = {}  # that time channel -> its seconds, read once
    for spec in specs:
        skip = None
        if cmap.auto:
            name = spec.column
            if needed is not None and spec.name not in needed:
                skip = "not needed here"
        else:
            skip = (
                "optional"
                if spec.optional and (needed is None or spec.name not in needed)
                else "not needed here"
                if needed is not None and spec.name not in needed
                else None
            )
            name = resolve_column(table, spec.column, spec.entry, cmap, path, skip=skip)
            if name is None:
                continue
        if skip is not None:  # present but unreadable (an MDF group, a TDMS channel, without
            try:  # samples): a note, since the caller does not need it
                col = table.load(name)
            except RecordingError as exc:
                entry = f"channel map entry {spec.entry}" if not cmap.auto else f"column {name!r}"
                notes.append(f"{entry} ({skip}) not read: " + str(exc).removeprefix(where).strip())
                continue
        else:
            col = table.load(name)
        what = f"{where} column {name!r} (channel map entry {spec.entry}, map {cmap.source})"
        if cmap.auto and not spec.canonical:
            if col.unit is None or np.asarray(col.values).dtype.kind not in "biuf":
                notes.append(f"column {name!r} not read (no unit or not numeric)")
                continue
        if spec.unit is None and col.unit is None:
            raise RecordingError(
                f"{what}: no unit in the channel map nor in the file; "
                f"give 'unit' (SI unit {CANONICAL_CHANNELS.get(spec.name, ('?',))[0]!r})"
            )
        unit = spec.unit if spec.unit is not None else col.unit
        try:
            si, factor = spec.conversion(unit)
        except RecordingError as exc:
            raise RecordingError(f"{what}: {exc}") from None
        if spec.unit is not None and col.unit is not None:
            if normalize_unit(col.unit) != normalize_unit(spec.unit):
                try:
                    file_si, file_factor = spec.conversion(col.unit)
                except RecordingError:
                    file_si, file_factor = None, None
                if not spec.canonical and file_si != si:
                    file_factor = None  # an extra in a unit of another quantity, or unknown
                if file_factor is not None and np.isclose(file_factor, factor, rtol=1e-12):
                    file_factor = None  # the same unit spelled otherwise (MN/m, kN/mm)
                if file_factor is not None and spec.scale == 1.0 and spec.offset == 0.0:
                    raise RecordingError(
                        f"{what}: the map says unit {spec.unit!r} but the file says "
                        f"{col.unit!r}; fix the map (or give scale/offset)"
                    )
                notes.append(
                    f"{spec.name}: file unit {col.unit!r}, map unit {spec.unit!r} used "
                    f"(scale {spec.scale}, offset {spec.offset})"
                )
        raw = as_float(col.values, what, line_of, text_decimal(table, cmap), marks)
        # A corrupted or absurd raw value may overflow to inf here: validation then names the
        # channel and the samples; numpy's overflow warning would only say "multiply".
        with np.errstate(over="ignore", invalid="ignore"):
            values = (spec.scale * raw + spec.offset) * factor
        own = None if col.time is None else np.asarray(col.time, dtype=float)
        clock = (
            None
            if own is not None or time is None
            else foreign_time(table, name, info["columns"]["time"], where)
        )
        if clock is not None:  # timed by its group's time channel, not the time column
            own = _own_time(
                table,
                name,
                clock,
                values,
                info["source_units"]["time"],
                cmap,
                what,
                notes,
                line_of,
                clock_seconds,
            )
            exact.add(spec.name)
            clocks.setdefault(clock, []).append(spec.name)
        loaded.append((spec, values, si, own))
        info["columns"][spec.name] = name
        info["source_units"][spec.name] = unit

    if not loaded:
        raise RecordingError(
            f"{where} no channels found (map {cmap.source}); file columns: {table.names[:60]}"
        )

    # --- time from the sample rate or from the first channel's own time base
    _, first_values, _, first_own = loaded[0]
    if time is None and tspec is not None and tspec.sample_rate_Hz is not None:
        _check_stated_rate(table, cmap, loaded, info, path, line_of)
        time = np.arange(first_values.size) / tspec.sample_rate_Hz
        info["source_units"]["time"] = f"sample_rate_Hz = {tspec.sample_rate_Hz}"
        own_times: list = [None] * len(loaded)
    elif time is None and first_own is None and table.stated_rate:
        # the file states its rate and no time column (an oscilloscope's 1/Increment)
        time = np.arange(first_values.size) / table.stated_rate
        info["source_units"]["time"] = f"the file's stated rate, {table.stated_rate:g} Hz"
        own_times = [None] * len(loaded)
    elif time is None:
        if first_own is None:
            raise RecordingError(
                f"{where} no time: the channel map (map {cmap.source}) gives no [time] column "
                "nor sample_rate_Hz, and the file's channels carry no time base "
                "(TDMS wf_increment / MDF master)"
                + _time_column_hint(table)
                + "".join(
                    f"; {n}"
                    for n in table.notes
                    if "master that is not time" in n or "oscilloscope's CSV" in n
                )
            )
        # time stays None: align_channels chooses the common base from the own time bases
        own_times = [own for _, _, _, own in loaded]
    else:
        own_times = [own for _, _, _, own in loaded]

    for clock, names in clocks.items():
        notes.append(
            f"channels {names} read on {clock!r}, the time channel of their own group (TDMS) "
            f"or raster (ControlDesk X(k)), not on the [time] column "
            f"{info['columns']['time']!r} of another group"
        )
    groups = {}
    for spec, *_ in loaded:
        labels = [g for g, names in table.groups.items() if info["columns"][spec.name] in names]
        if labels:  # its own group's labels, not those that hold every group (a source name)
            fewest = min(len(table.groups[g]) for g in labels)
            labels = [g for g in labels if len(table.groups[g]) == fewest]
            groups[spec.name] = "group " + " / ".join(repr(g) for g in labels[:3])
    time, channels, units = align_channels(
        time,
        loaded,
        own_times,
        own_time_exact=table.own_time_exact,
        exact_channels=exact,
        info=info,
        notes=notes,
        where=where,
        resample_Hz=getattr(tspec, "resample_Hz", None),
        validate=validate,
        groups=groups,
    )
    return np.asarray(time, dtype=float), channels, units, info
