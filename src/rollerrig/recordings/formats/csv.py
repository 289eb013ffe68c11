"""Delimited text files (CSV, TSV, ASCII exports) as acquisition software writes them.

:func:`read_csv` reads the numbers where :func:`rollerrig.recordings.formats.sniff.sniff_layout`
found them (separator, decimal mark, encoding, header and units rows: see there; every key of
the channel map's ``[file]`` section beats the sniffer) with :func:`pandas.read_csv`.

Malformed files give one :class:`~rollerrig.recordings.recording.RecordingError` naming the file and
the line: empty file, header without rows, binary content (NUL bytes), rows with more or fewer
cells than the header. Blank lines inside the numbers are skipped (noted); a last line without a
line end (a file copied while written, a writer interrupted) is dropped (noted, with the rows
kept), whether it is short of cells or may end inside a number (``...,859`` for ``85912.3``),
unless it visibly ends complete (a closing quote, a trailing separator, a last cell as long as
the line before's). Cells are converted later,
in :mod:`rollerrig.recordings.translate` (numbers, and timestamps with one format per column:
:mod:`rollerrig.recordings.formats.timestamps`). A ``<stem>.metadata.json`` sidecar beside the file
(written by rollerrig) is read as the file's provenance.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from rollerrig.recordings.channels import FileSpec
from rollerrig.recordings.formats._table import Table, header_table, require_module
from rollerrig.recordings.formats._text import (
    NAN_WORDS,
    footer_rows,
    sample_in_footer,
    split_cells,
)
from rollerrig.recordings.formats._text import (
    code_unit as _code_unit,
)
from rollerrig.recordings.formats.sniff import HEAD_BYTES, TextLayout, sniff_layout, where_named
from rollerrig.recordings.formats.timestamps import looks_like_timestamp, parse_timestamps
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "NAN_WORDS",
    "TextLayout",
    "TextTable",
    "looks_like_timestamp",
    "parse_timestamps",
    "read_csv",
    "sniff_layout",
    "unreadable",
]


@dataclass
class TextTable(Table):
    """A :class:`Table` of a text file; row ``k`` of every column is file line ``line_of(k)``."""

    rows_lines: list[int] = field(default_factory=list)  # 1-based file line of each row

    def line_of(self, row: int) -> int | None:
        """1-based file line of data row ``row`` (None when unknown)."""
        return self.rows_lines[row] if 0 <= row < len(self.rows_lines) else None


def _lines(path: Path, encoding: str, wanted: set[int]) -> dict[int, str]:
    """Text of the 0-based file lines ``wanted`` (one pass, stops after the last)."""
    out: dict[int, str] = {}
    if not wanted:
        return out
    last = max(wanted)
    with path.open("r", encoding=encoding, errors="replace", newline="") as fh:
        for i, line in enumerate(fh):
            if i in wanted:
                out[i] = line
            if i >= last:
                break
    return out


def _read_frame(layout: TextLayout, notes: list[str], nrows: int | None = None):
    pd = require_module("pandas", "CSV files")

    kwargs = layout.pandas_kwargs()
    if nrows is not None:
        kwargs["nrows"] = nrows  # the lines above a footer
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            with layout.readable(kwargs["encoding"], skip_lines=True) as source:
                frame = pd.read_csv(source, **kwargs)
    except RecordingError:  # a cell a converter refused (thousands marks): names the cell
        raise
    except UnicodeDecodeError:
        if layout.encoding != "utf-8-sig":
            raise RecordingError(
                f"{layout.path}: not valid {layout.encoding!r} text after the first "
                f"{HEAD_BYTES} bytes; fix [file] encoding in the channel map"
            ) from None
        notes.append("the file is not UTF-8 (beyond its first lines); read as Latin-1")
        kwargs["encoding"] = "latin-1"
        return _read_frame_with(layout, kwargs)
    except pd.errors.ParserWarning as exc:
        raise RecordingError(
            f"{layout.path}: rows with more cells than the header: {exc}"
        ) from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as exc:
        raise unreadable(layout, exc) from None
    return frame, kwargs["encoding"]


def unreadable(layout: TextLayout, exc: Exception) -> RecordingError:
    """The error of a CSV file pandas could not read (``exc``): a row with more cells than
    the rows before it named by its line in the file, else pandas' own words."""
    m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(exc))
    if m:
        # pandas counts lines from where it starts reading: past the lines above the numbers
        # where they were skipped line by line (TextLayout.open_quote_above)
        line = int(m.group(2)) + (layout.data_line if layout.open_quote_above else 0)
        return RecordingError(
            f"{layout.path}: line {line} has {m.group(3)} cells, the rows before it "
            f"{m.group(1)}; fix or remove that line"
        )
    return RecordingError(f"{layout.path}: not a readable CSV file: {exc}")


def _read_frame_with(layout: TextLayout, kwargs: dict):
    pd = require_module("pandas", "CSV files")

    try:
        with layout.readable(kwargs["encoding"], skip_lines=True) as source:
            return pd.read_csv(source, **kwargs), kwargs["encoding"]
    except RecordingError:
        raise
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as exc:
        raise RecordingError(f"{layout.path}: not a readable CSV file: {exc}") from None


def read_csv(path: Path, spec: FileSpec | None = None) -> TextTable:
    """Read a delimited text file into a :class:`TextTable` (see the module docstring).

    Parameters
    ----------
    path : path-like
        The file (read-only).
    spec : FileSpec, optional
        Explicit layout from the channel map's ``[file]`` section.
    """
    path = Path(path)
    layout = sniff_layout(path, spec)
    notes = list(layout.notes)
    footer, footer_note = footer_of(layout)
    if footer_note:
        notes.append(footer_note)
    frame, encoding = _read_frame(layout, notes, footer)
    if layout.trailing:
        frame = frame.drop(columns="__trailing__")
    n = len(frame)
    first = layout.data_line  # 0-based file line of frame row 0
    # rows with a missing cell: blank lines, short rows, a cut last line, or a real empty cell
    missing = frame.isna().to_numpy()
    gappy = missing.any(axis=1).nonzero()[0]
    drop: list[int] = []
    # a footer's last line is no sample that a writer may have cut
    ends_with_newline = footer is not None or _ends_with_newline(path, encoding, layout.end)
    if gappy.size or (n and not ends_with_newline):
        check = set(gappy[:200].tolist()) | ({n - 1} if n else set())
        check |= {n - 2} if n >= 2 and not ends_with_newline else set()
        raw = _lines(path, encoding, {first + k for k in check})
        for k in sorted(check):
            line = raw.get(first + k)
            if line is None:
                continue
            body = line.rstrip("\r\n")
            if not body.strip() or (layout.separator != " " and not body.strip(layout.separator)):
                drop.append(k)
                continue
            cells = len(split_cells(body, layout.separator))
            if cells < layout.n_fields:
                if k == n - 1 and not ends_with_newline:
                    drop.append(k)
                    notes.append(
                        f"last line {first + k + 1} is cut short ({cells} of {layout.n_fields} "
                        "cells, no line end): dropped"
                    )
                    continue
                raise RecordingError(
                    f"{path}: line {first + k + 1} has {cells} cells, the header "
                    f"{layout.n_fields}; fix or remove that line"
                )
    if n and not ends_with_newline and n - 1 not in drop:
        last = raw.get(first + n - 1, "").rstrip("\r\n")
        previous = raw.get(first + n - 2, "").rstrip("\r\n") if n >= 2 else ""
        if not _visibly_complete(last, layout, previous):
            drop.append(n - 1)
            notes.append(
                f"last line {first + n} has no line end: the writer may have been interrupted "
                f"inside its last number ({last[-40:]!r}), so it was dropped; {n - 1} data "
                "row(s) kept (end the file with a line break to keep that row)"
            )
    blank = [k for k in drop if k < n - 1 and not _is_trailing_blank(drop, k, n)]
    if blank:
        notes.append(
            f"{len(blank)} blank line(s) inside the data skipped "
            f"(first: line {first + blank[0] + 1})"
        )
    keep_lines = [first + k + 1 for k in range(n)]
    if drop:
        frame = frame.drop(index=drop).reset_index(drop=True)
        dropped = set(drop)
        keep_lines = [ln for k, ln in enumerate(keep_lines) if k not in dropped]
    if len(frame) == 0:
        cut = " (its only row had no line end and was dropped as possibly cut)" if n else ""
        raise RecordingError(f"{path}: has a header but no data rows{cut}; the recording is empty")
    base = layout_table(frame, layout)
    table = TextTable(**{f: getattr(base, f) for f in Table.__dataclass_fields__})
    table.rows_lines = keep_lines
    table.notes += notes
    sidecar = path.with_suffix(".metadata.json")
    if sidecar.is_file():
        try:
            table.stored_metadata = json.loads(sidecar.read_text(encoding="utf-8"))
            table.notes.append(f"provenance read from {sidecar.name}")
        except (json.JSONDecodeError, UnicodeDecodeError):
            table.notes.append(f"sidecar {sidecar.name} is not valid JSON; ignored")
    return table


def layout_table(frame, layout: TextLayout) -> Table:
    """The :class:`Table` over ``frame`` (columns named as ``layout``'s) with what the layout
    knows: the units of its units row, its decimal mark where decided, its repeated names and
    where a name the map gives stands (one place for :func:`read_csv` and the chunked
    reader's table, :func:`rollerrig.recordings.source.open_recording`)."""
    units = {nm: u for nm, u in zip(layout.names, layout.units, strict=True) if u}
    table = header_table(frame, units=units)
    table.decimal = layout.decimal if layout.decimal_decided else None
    table.repeated = {name: list(columns) for name, columns in layout.repeated}
    table.locate = functools.partial(where_named, layout)
    table.stated_rate = layout.rate_Hz
    return table


def _is_trailing_blank(drop: list[int], k: int, n: int) -> bool:
    """Whether row ``k`` belongs to the run of dropped rows that ends the file."""
    tail = set(drop)
    return all(j in tail for j in range(k, n))


def _visibly_complete(line: str, layout: TextLayout, previous: str = "") -> bool:
    """Whether a last line without a line end visibly ends where its writer meant it to: at a
    trailing separator (a layout with one), at the closing quote of a quoted last cell, or
    with a last cell at least as long as the line before's (a writer of fixed decimals, as most
    DAQ software: ``85912.300`` after ``85911.700``). A line ending in a bare number shorter
    than that may have been cut inside it (``...,859`` for ``85912.3``)."""
    body = line.rstrip()
    if layout.trailing and layout.separator != " ":
        return body.endswith(layout.separator)
    cells = split_cells(body, layout.separator)
    if body.endswith('"'):
        return len(cells) == layout.n_fields and body.count('"') % 2 == 0
    before = split_cells(previous.rstrip(), layout.separator) if previous else []
    return (
        len(cells) == layout.n_fields == len(before)
        and len(cells[-1].strip()) >= len(before[-1].strip()) > 0
    )


_TAIL_BYTES = 1 << 20  # the end of a file read to find its last two lines


def _tail(layout: TextLayout, count: int) -> list[tuple[int | None, str]]:
    """The file's last ``count`` lines (with their line ends) and their 0-based line numbers,
    None where the end of a large file was read alone; reading only its end (an
    ASCII-compatible encoding) or, for UTF-16, the whole file line by line."""
    path = layout.path
    if _code_unit(layout.encoding) > 1:
        from collections import deque

        # the text's bytes only: a NUL-padded tail (layout.end) is no line of the file
        with layout.readable() as source, contextlib.ExitStack() as stack:
            if isinstance(source, Path):
                source = stack.enter_context(source.open("rb"))
            fh = (
                source  # lines ending in a lone CR: a text handle already
                if isinstance(source, io.TextIOBase)
                else io.TextIOWrapper(
                    source, encoding=layout.encoding, errors="replace", newline=""
                )
            )
            return list(deque(enumerate(fh), maxlen=count))
    size = path.stat().st_size if layout.end is None else layout.end
    with path.open("rb") as fh:
        fh.seek(max(0, size - _TAIL_BYTES))
        tail = fh.read(size - max(0, size - _TAIL_BYTES)).decode(layout.encoding, errors="replace")
    # Lines as the file reader splits them (\n, \r, \r\n only; str.splitlines would also
    # split at form feeds and U+0085, shifting the count).
    parts = list(io.StringIO(tail, newline=""))
    if size > _TAIL_BYTES:  # the window starts inside a line: not a whole line
        return [(None, p) for p in parts[1:][-count:]]
    return list(enumerate(parts))[-count:]


def _last_two_lines(layout: TextLayout) -> tuple[str, str]:
    """The file's last line and the data line before it ("" where there is none)."""
    numbered = _tail(layout, 2)
    if not numbered:
        return "", ""
    last = numbered[-1][1]
    first = numbered[0][0]
    data = first is None or first >= layout.data_line
    previous = numbered[0][1] if len(numbered) == 2 and data else ""
    return last, previous


def footer_of(layout: TextLayout) -> tuple[int | None, str | None]:
    """``(rows, note)``: the number of lines from the first data line to a footer below the
    numbers (:func:`~rollerrig.recordings.formats._text.footer_rows`), the rows
    :func:`pandas.read_csv` reads (``nrows``), and the note that says the footer was left out;
    ``(None, None)`` where there is none. pandas never sees the footer's lines: a footer line
    of more cells than the header, or text in a column of numbers, changes nothing."""
    lines = [(i, t.rstrip("\r\n")) for i, t in _tail(layout, 200)]
    lines = [(i, t) for i, t in lines if i is None or i >= layout.data_line]
    rows = [split_cells(t, layout.separator) for _, t in lines]
    count = footer_rows(rows)
    if not count:
        return None, None
    first_line, first_text = lines[-count]
    if first_line is None:  # the end of a large file, read alone
        first_line = _count_lines(layout) - count
    sample = sample_in_footer(rows)
    if sample is not None:
        line = first_line + sample - (len(lines) - count)
        raise RecordingError(
            f"{layout.path}: line {line + 1} ({lines[sample][1].strip()[:60]!r}) below the "
            f"samples is laid out as one, but its first column is no number or time this "
            f"reader knows, so it and the {len(lines) - sample - 1} line(s) after it would be "
            "dropped as a footer; correct that line, or cut the file above it"
        )
    return first_line - layout.data_line, (
        f"footer below the numbers left out: line {first_line + 1} to the end "
        f"({first_text.strip()[:60]!r})"
    )


def _count_lines(layout: TextLayout, block: int = 1 << 20) -> int:
    """Lines of the file as :func:`_tail` splits them (``\\n``, ``\\r\\n`` or ``\\r`` ends one),
    counted in blocks of bytes (an ASCII-compatible encoding)."""
    ends = 0
    last = b""
    left = layout.end
    with layout.path.open("rb") as fh:
        while chunk := fh.read(block if left is None else min(block, left)):
            if left is not None:
                left -= len(chunk)
            ends += chunk.count(b"\n") + chunk.count(b"\r") - (last + chunk).count(b"\r\n")
            last = chunk[-1:]
    return ends + (1 if last and last not in (b"\n", b"\r") else 0)


def cut_last_line(layout: TextLayout) -> str | None:
    """Why the streamed reader drops the file's last line, or None to keep it.

    The rule of :func:`read_csv_table`: a last line without a line end is dropped when it has
    fewer cells than the header, or may have been cut inside its last number
    (:func:`_visibly_complete`); a blank one is skipped as blank lines are.
    """
    if _ends_with_newline(layout.path, layout.encoding, layout.end):
        return None
    last, previous = _last_two_lines(layout)
    body = last.rstrip("\r\n")
    if not body.strip() or (layout.separator != " " and not body.strip(layout.separator)):
        return None
    cells = len(split_cells(body, layout.separator))
    if cells < layout.n_fields:
        return (
            f"the last line is cut short ({cells} of {layout.n_fields} cells, no line end): dropped"
        )
    if _visibly_complete(body, layout, previous.rstrip("\r\n")):
        return None
    return (
        "the last line has no line end: the writer may have been interrupted inside its last "
        f"number ({body[-40:]!r}), so it was dropped (end the file with a line break to keep "
        "that row)"
    )


def _ends_with_newline(path: Path, encoding: str = "utf-8", end: int | None = None) -> bool:
    """Whether the file's last character (of its first ``end`` bytes: TextLayout.end) is a
    line end (UTF-16 and UTF-32: its last code unit, either byte order)."""
    unit = _code_unit(encoding)
    with path.open("rb") as fh:
        size = fh.seek(0, 2) if end is None else end
        if size < unit:
            return False
        fh.seek(size - unit)
        tail = fh.read(unit)
    pad = b"\x00" * (unit - 1)
    return any(tail in (c + pad, pad + c) for c in (b"\n", b"\r"))
