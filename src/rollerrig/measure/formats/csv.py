"""Delimited text files (CSV, TSV, ASCII exports) as acquisition software writes them.

The layout is sniffed from the first lines of the file; every key of the channel map's
``[file]`` section (:class:`rollerrig.measure.channels.FileSpec`) beats the sniffer:

- **preamble**: lines before the header (catman, DIAdem, PicoScope, CANape ASCII exports write
  the file name, date, comments there) are skipped. The numbers are the trailing block of lines
  whose every cell is a number, a timestamp, empty or a NaN/inf word; the header is the nearest
  non-blank line above it.
- **units row**: a non-numeric row between the header and the numbers whose cells look like
  units (``(ms)``, ``[V]``, ``N·m``, ``1/min``; PicoScope, catman, DIAdem, CANape) gives the
  columns' units. It is never used to sniff the decimal mark.
- **separator**: ``,`` ``;`` tab ``|`` or whitespace, the one under which the trailing block of
  numbers is longest and consistent with the header (ties: that order).
- **decimal mark**: ``,`` when the number cells of the data rows (never the header or units row)
  use it; a file mixing both marks is an error asking for ``[file] decimal``.
- **encoding**: UTF-8 (with or without BOM), UTF-16 with BOM, else Latin-1 (noted).

Malformed files give one :class:`~rollerrig.measure.recording.RecordingError` naming the file and
the line: empty file, header without rows, binary content (NUL bytes), rows with more or fewer
cells than the header. Blank lines inside the numbers are skipped (noted); a last line cut short
without a line end (a file copied while written) is dropped (noted). Cells are converted later,
in :mod:`rollerrig.measure.readers` (numbers, timestamps with one format per column).
"""

from __future__ import annotations

import codecs
import csv
import json
import re
import warnings
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rollerrig.measure.channels import (
    TIME_UNITS,
    UNIT_FACTORS,
    FileSpec,
    normalize_unit,
)
from rollerrig.measure.formats._table import Table, header_table
from rollerrig.measure.recording import RecordingError

__all__ = [
    "NAN_WORDS",
    "TextLayout",
    "TextTable",
    "looks_like_timestamp",
    "parse_timestamps",
    "read_csv",
    "sniff_layout",
]

HEAD_BYTES = 1 << 18
"""Bytes read to sniff the layout (256 KiB; the whole file when smaller)."""

_SNIFF_SEPARATORS = ("\t", ";", ",", "|", " ")
_NUMBER = re.compile(r"[+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d+)?")
_COMMA_NUMBER = re.compile(r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?")
_DOT_NUMBER = re.compile(r"[+-]?\d*\.\d+(?:[eE][+-]?\d+)?")
_TIMESTAMP = re.compile(
    r"(?:\d{1,4}[./-]\d{1,2}[./-]\d{1,4}(?:[ T]+\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d+)?)?)?"
    r"|\d{1,2}:\d{2}:\d{2}(?:[.,]\d+)?)"
    r"(?:\s*(?:Z|[+-]\d{2}:?\d{2}))?"
)
NAN_WORDS = frozenset(
    {"nan", "-nan", "+nan", "inf", "+inf", "-inf", "infinity", "-infinity", "+infinity"}
    | {"∞", "+∞", "-∞", "na", "n/a", "#n/a", "null", "none"}
)
"""Cells that stand for a missing or infinite sample (case-insensitive)."""
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
_UNIT_TOKEN = re.compile(r"[A-Za-zµμΩ°%/·*^.\-²³0-9]{1,14}")


def _kind(cell: str) -> str:
    """Classify one cell: "empty", "num", "time", "nan" or "text"."""
    c = cell.strip()
    if not c:
        return "empty"
    if _NUMBER.fullmatch(c):
        return "num"
    if c.lower() in NAN_WORDS:
        return "nan"
    if _TIMESTAMP.fullmatch(c):
        return "time"
    return "text"


def _datalike(fields: list[str]) -> bool:
    kinds = [_kind(f) for f in fields]
    return all(k != "text" for k in kinds) and any(k in ("num", "time") for k in kinds)


def _split(line: str, sep: str) -> list[str]:
    if sep == " ":
        return line.split()
    return [f.strip() for f in next(csv.reader([line], delimiter=sep, quotechar='"'), [""])]


_DATE_FORMAT_UNIT = re.compile(r"(?i)[dmyhs]{1,4}(?:[./: T-]+[dmyhs]{1,4})+(?:[.,]s+|[.,]f+)?")
"""A units-row cell that spells a date/time format (``dd.mm.yyyy hh:mm:ss``): no unit."""


def _unit_cell(cell: str) -> str | None:
    """The unit in a units-row cell (``(ms)`` -> ``ms``); None when empty or a date format."""
    c = cell.strip()
    if len(c) >= 2 and c[0] + c[-1] in ("()", "[]", "<>", "{}"):
        c = c[1:-1].strip()
    if _DATE_FORMAT_UNIT.fullmatch(c):
        return None
    return c or None


def _unitlike_row(fields: list[str]) -> bool:
    """Whether a row looks like units (``s;N·m;1/min``, ``(ms),(V),(V)``), not like names."""
    cells = [f.strip() for f in fields if f.strip()]
    if not cells or _datalike(fields):
        return False
    known = 0
    for c in cells:
        bracketed = len(c) >= 2 and c[0] + c[-1] in ("()", "[]")
        if _DATE_FORMAT_UNIT.fullmatch(c.strip("()[] ")):
            continue  # the time column's format, e.g. "dd.mm.yyyy hh:mm:ss"
        u = _unit_cell(c) or ""
        if u.lower() in _HEADER_WORDS or not _UNIT_TOKEN.fullmatch(u):
            return False
        if bracketed or u in _KNOWN_UNITS or normalize_unit(u) in _KNOWN_UNITS:
            known += 1
    return known >= max(1, (len(cells) + 1) // 2)


@dataclass(frozen=True)
class TextLayout:
    """Where a text file's names, units and numbers are, and how its cells are written.

    Line indices are 0-based and count every line of the file (blank lines included).
    :meth:`pandas_kwargs` reads the numbers with :func:`pandas.read_csv` (also in chunks).
    """

    path: Path
    encoding: str
    separator: str
    decimal: str
    header_line: int | None
    units_line: int | None
    data_line: int
    names: tuple[str, ...]
    units: tuple[str | None, ...]
    trailing: bool = False
    notes: tuple[str, ...] = ()

    @property
    def n_fields(self) -> int:
        """Cells per data row (a trailing separator adds one empty cell)."""
        return len(self.names) + (1 if self.trailing else 0)

    def pandas_kwargs(self) -> dict:
        """Keyword arguments of :func:`pandas.read_csv` for the rows of numbers."""
        names = list(self.names) + (["__trailing__"] if self.trailing else [])
        return {
            "sep": r"\s+" if self.separator == " " else self.separator,
            "decimal": self.decimal,
            "encoding": self.encoding,
            "header": None,
            "names": names,
            "skiprows": self.data_line,
            "skip_blank_lines": False,
            "index_col": False,
            "quotechar": '"',
            "engine": "c",
        }


@dataclass
class TextTable(Table):
    """A :class:`Table` of a text file; row ``k`` of every column is file line ``line_of(k)``."""

    rows_lines: list[int] = field(default_factory=list)  # 1-based file line of each row

    def line_of(self, row: int) -> int | None:
        """1-based file line of data row ``row`` (None when unknown)."""
        return self.rows_lines[row] if 0 <= row < len(self.rows_lines) else None


def _decode_head(path: Path, raw: bytes, spec: FileSpec, notes: list[str]) -> tuple[str, str]:
    """(encoding, text) of the head of the file."""
    if spec.encoding is not None:
        try:
            return spec.encoding, raw.decode(spec.encoding)
        except UnicodeDecodeError as exc:
            if exc.start < len(raw) - 4:  # not just a character cut at the end of the head
                line = raw[: exc.start].count(b"\n") + 1
                raise RecordingError(
                    f"{path}: line {line} is not valid {spec.encoding!r} text ({exc.reason}); "
                    "fix [file] encoding in the channel map"
                ) from None
            return spec.encoding, raw[: exc.start].decode(spec.encoding)
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return "utf-16", raw.decode("utf-16", errors="ignore")
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise RecordingError(
            f"{path}: not a text file (a NUL byte at byte {nul}); is it a binary file with a "
            "text suffix? Export the recording as CSV/ASCII, or read it with its own format "
            "(format='tdms', 'mf4', 'mat', ...)"
        )
    try:
        return "utf-8-sig", raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if exc.start >= len(raw) - 4 and len(raw) >= HEAD_BYTES:
            return "utf-8-sig", raw[: exc.start].decode("utf-8-sig")
    notes.append("the file is not UTF-8; read as Latin-1")
    return "latin-1", raw.decode("latin-1")


def _data_block(
    rows: list[tuple[int, list[str]]], partial_last: bool
) -> tuple[list[tuple[int, list[str]]], int]:
    """(trailing block of data rows, cells per row).

    Walking up from the last row, a row belongs to the data when it has a number or timestamp
    and at most half of the numeric columns (columns that are numbers in >= 80 % of the last
    rows) hold text in it: a stray ``ERR`` cell stays in the data (reported later with its line),
    a header or units row, text in every numeric column, ends the block.
    """
    kinds = [(i, f, [_kind(c) for c in f]) for i, f in rows]
    tail = [x for x in kinds[-50:] if any(k in ("num", "time") for k in x[2])]
    if not tail:
        return [], 0
    sample = tail[:-1] if partial_last and len(tail) > 1 else tail
    n = Counter(len(f) for _, f, _ in sample).most_common(1)[0][0]
    ref = [x for x in sample if len(x[1]) == n]
    numeric = [j for j in range(n) if sum(x[2][j] != "text" for x in ref) >= 0.8 * len(ref)]
    allowed = len(numeric) // 2
    block: list[tuple[int, list[str]]] = []
    for i, f, k in reversed(kinds):
        if not any(x in ("num", "time") for x in k):
            break
        if sum(1 for j in numeric if j < len(k) and k[j] == "text") > allowed:
            break
        block.append((i, f))
    return block[::-1], n


def _score(
    lines: list[tuple[int, str]], sep: str, partial_last: bool
) -> tuple[int, int, list[tuple[int, list[str]]]]:
    """(rows with the usual cell count, cells per row, block) of ``sep``; score 0 when the
    header above the block does not fit the rows. Ties go to the earlier separator of
    :data:`_SNIFF_SEPARATORS` (whitespace last)."""
    rows = [(i, _split(t, sep)) for i, t in lines]
    block, n = _data_block(rows, partial_last)
    if not block:
        return 0, 0, block
    above = [f for i, f in rows if i < block[0][0]]
    if above:
        h = len(above[-1])
        trailing = all(f[-1] == "" for _, f in block if len(f) == n)
        header_ok = (
            h == n or (h == n - 1 and trailing) or (h == n + 1 and above[-1][-1].strip() == "")
        )
        if not header_ok:
            return 0, n, block
    return sum(1 for _, f in block if len(f) == n), n, block


def sniff_layout(path: str | Path, spec: FileSpec | None = None) -> TextLayout:
    """Sniff where the names, units and numbers of a text file are (``[file]`` keys win).

    Parameters
    ----------
    path : path-like
        The text file (read-only).
    spec : FileSpec, optional
        Explicit layout keys from the channel map's ``[file]`` section.

    Raises
    ------
    RecordingError
        Empty file, binary content, no rows of numbers, a header whose cell count does not match
        the data rows, mixed decimal marks.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "pico.csv"
    >>> _ = f.write_text("Time,Channel A\\n(ms),(V)\\n\\n0.0,0.5\\n0.1,0.6\\n")
    >>> lay = sniff_layout(f)
    >>> lay.separator, lay.names, lay.units, lay.data_line
    (',', ('Time', 'Channel A'), ('ms', 'V'), 3)
    """
    p = Path(path)
    spec = spec or FileSpec()
    notes: list[str] = []
    size = p.stat().st_size
    with p.open("rb") as fh:
        raw = fh.read(HEAD_BYTES)
    if not raw.strip():
        raise RecordingError(f"{p}: the file is empty")
    encoding, text = _decode_head(p, raw, spec, notes)
    all_lines = re.split(r"\r\n|\r|\n", text)
    truncated_head = size > len(raw)
    if truncated_head and len(all_lines) > 1:
        all_lines = all_lines[:-1]  # the head ends inside a line
    elif all_lines and all_lines[-1] == "":
        all_lines = all_lines[:-1]
    partial_last = not truncated_head and not text.endswith(("\n", "\r"))
    lines = [(i, t) for i, t in enumerate(all_lines) if t.strip()]
    if not lines:
        raise RecordingError(f"{p}: the file is empty (only blank lines)")
    where = "channel map [file]"

    # --- separator and the rows of numbers
    first_data = spec.data_row
    if first_data is not None:
        if first_data >= len(all_lines) and not truncated_head:
            raise RecordingError(
                f"{p}: {where} data_row = {first_data} but the file has {len(all_lines)} lines"
            )
        lines_for_sniff = [(i, t) for i, t in lines if i >= first_data]
    else:
        # the numbers start after the header / units rows the map names
        given = [r for r in (spec.header_row, spec.units_row) if r is not None and r is not False]
        after = max(given, default=-1)
        lines_for_sniff = [(i, t) for i, t in lines if i > after]
    candidates = (spec.separator,) if spec.separator is not None else _SNIFF_SEPARATORS
    best = None
    for sep in candidates:
        if sep == "," and spec.decimal == ",":
            continue
        score, n, block = _score(lines_for_sniff, sep, partial_last)
        if first_data is not None:
            block = [(i, _split(t, sep)) for i, t in lines_for_sniff]
            n = Counter(len(f) for _, f in block).most_common(1)[0][0] if block else 0
            score = len(block)
        if spec.separator is not None or (n >= 2 and score > 0):
            if best is None or score > best[0]:
                best = (score, n, block, sep)
    if best is None or not best[2]:
        # one column (the separator is one that does not occur) or no numbers at all
        sep = spec.separator or next(
            (c for c in ("\t", ";", "|", ",") if not any(c in t for _, t in lines_for_sniff)),
            "\t",
        )
        score, n, block = _score(lines_for_sniff, sep, partial_last)
        if first_data is not None:
            block = [(i, _split(t, sep)) for i, t in lines_for_sniff]
        if not block:
            shown = [t[:80] for _, t in lines[:5]]
            if len(lines) <= 3:
                raise RecordingError(
                    f"{p}: has a header but no data rows (lines: {shown}); the recording is empty"
                )
            raise RecordingError(
                f"{p}: no rows of numbers found (first lines: {shown}); give the layout in the "
                "channel map's [file] section (separator, decimal, header_row, data_row)"
            )
        best = (score, 1, block, sep)
    _, n, block, sep = best
    data_line = block[0][0] if first_data is None else first_data
    if spec.separator is None and sep != ",":
        notes.append(f"separator {sep!r} sniffed")

    if first_data is None and n >= 2:
        # rows of numbers above the header: two recordings appended, a repeated header
        earlier = [
            i
            for i, t in lines_for_sniff
            if i < data_line and len(f := _split(t, sep)) == n and _datalike(f)
        ]
        if len(earlier) >= 2:
            header_at = max(i for i, _ in lines if i < data_line)
            raise RecordingError(
                f"{p}: rows of numbers (lines {earlier[0] + 1}..{earlier[-1] + 1}) above the "
                f"header at line {header_at + 1}: a header repeated inside the data (recordings "
                "appended to one file?); split the file, or give [file] header_row and data_row "
                "in the channel map"
            )

    # --- decimal mark, from the number cells of the data rows only
    decimal = spec.decimal
    if decimal is None:
        cells = [c.strip() for _, f in block[:2000] for c in f]
        comma = next((c for c in cells if _COMMA_NUMBER.fullmatch(c)), None)
        dot = next((c for c in cells if _DOT_NUMBER.fullmatch(c)), None)
        if comma is not None and sep != ",":
            if dot is not None:
                raise RecordingError(
                    f"{p}: the data rows mix decimal marks ({comma!r} and {dot!r}); give "
                    '[file] decimal = "." or "," in the channel map'
                )
            decimal = ","
            notes.append("CSV uses decimal commas (sniffed from the data rows)")
        else:
            decimal = "."

    # --- header and units rows
    above = [(i, t) for i, t in lines if i < data_line]
    header_line: int | None = spec.header_row
    units_line: int | None = spec.units_row if spec.units_row is not False else None
    if header_line is None:
        if spec.units_row is not None and spec.units_row is not False:
            cand = [(i, t) for i, t in above if i < spec.units_row]
            header_line = cand[-1][0] if cand else None
        elif spec.units_row is None and len(above) >= 2:
            up, low = above[-2], above[-1]
            uf, lf = _split(up[1], sep), _split(low[1], sep)
            if _unitlike_row(lf) and not _unitlike_row(uf) and abs(len(uf) - len(lf)) <= 1:
                header_line, units_line = up[0], low[0]
            else:
                header_line = low[0]
        elif above:
            header_line = above[-1][0]
    elif spec.units_row is None:
        between = [(i, t) for i, t in above if i > header_line]
        if len(between) == 1 and _unitlike_row(_split(between[0][1], sep)):
            units_line = between[0][0]
    text_of = dict(lines)
    if header_line is not None and header_line >= len(all_lines):
        raise RecordingError(
            f"{p}: {where} header_row = {header_line} but the file has {len(all_lines)} lines"
        )
    trailing = n >= 2 and all(len(f) == n and f[-1] == "" for _, f in block[:200])
    if header_line is not None:
        names = _split(text_of.get(header_line, ""), sep)
        if names and names[-1] == "" and len(names) in (n, n + 1) and trailing:
            names = names[:-1]
        elif names and names[-1] == "" and len(names) == n + 1:
            names = names[:-1]
    else:
        names = []
        notes.append("no header row; columns named 'column 1', 'column 2', ...")
    n_names = n - 1 if trailing else n
    if header_line is not None and len(names) != n_names:
        if n == 1 and spec.separator is None:
            pass  # one column: the separator is unknown and irrelevant
        else:
            raise RecordingError(
                f"{p}: the header (line {header_line + 1}) has {len(names)} cells but the data "
                f"rows (from line {data_line + 1}) have {n_names}; check the separator "
                f"({sep!r}) or give [file] header_row / separator in the channel map"
            )
    if n == 1:
        names = [text_of.get(header_line, "").strip().strip('"')] if header_line is not None else []
    names = [nm.strip().strip('"') or f"column {k + 1}" for k, nm in enumerate(names)]
    names += [f"column {k + 1}" for k in range(len(names), n_names)]
    seen: Counter = Counter()
    unique = []
    for nm in names:
        seen[nm] += 1
        unique.append(nm if seen[nm] == 1 else f"{nm}.{seen[nm] - 1}")
    if unique != names:
        dup = sorted(k for k, v in seen.items() if v > 1)
        notes.append(f"duplicate column names {dup} renamed name.1, name.2, ...")
    units: list[str | None] = [None] * n_names
    if units_line is not None:
        if units_line >= len(all_lines):
            raise RecordingError(
                f"{p}: {where} units_row = {units_line} but the file has {len(all_lines)} lines"
            )
        cells = _split(text_of.get(units_line, ""), sep) if n > 1 else [text_of[units_line]]
        units = [_unit_cell(c) for c in cells[:n_names]] + [None] * (n_names - len(cells))
        if spec.units_row is None:
            notes.append(f"units row (line {units_line + 1}) used for the columns' units")
    return TextLayout(
        path=p,
        encoding=encoding,
        separator=sep,
        decimal=decimal,
        header_line=header_line,
        units_line=units_line,
        data_line=data_line,
        names=tuple(unique),
        units=tuple(units),
        trailing=trailing,
        notes=tuple(notes),
    )


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


def _read_frame(layout: TextLayout, notes: list[str]):
    import pandas as pd

    kwargs = layout.pandas_kwargs()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            frame = pd.read_csv(layout.path, **kwargs)
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
        m = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(exc))
        if m:
            raise RecordingError(
                f"{layout.path}: line {m.group(2)} has {m.group(3)} cells, the rows before it "
                f"{m.group(1)}; fix or remove that line"
            ) from None
        raise RecordingError(f"{layout.path}: not a readable CSV file: {exc}") from None
    return frame, kwargs["encoding"]


def _read_frame_with(layout: TextLayout, kwargs: dict):
    import pandas as pd

    try:
        return pd.read_csv(layout.path, **kwargs), kwargs["encoding"]
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
    frame, encoding = _read_frame(layout, notes)
    if layout.trailing:
        frame = frame.drop(columns="__trailing__")
    n = len(frame)
    first = layout.data_line  # 0-based file line of frame row 0
    # rows with a missing cell: blank lines, short rows, a cut last line, or a real empty cell
    missing = frame.isna().to_numpy()
    gappy = missing.any(axis=1).nonzero()[0]
    drop: list[int] = []
    if gappy.size:
        check = set(gappy[:200].tolist()) | ({n - 1} if n else set())
        raw = _lines(path, encoding, {first + k for k in check})
        ends_with_newline = _ends_with_newline(path)
        for k in sorted(check):
            line = raw.get(first + k)
            if line is None:
                continue
            body = line.rstrip("\r\n")
            if not body.strip() or (layout.separator != " " and not body.strip(layout.separator)):
                drop.append(k)
                continue
            cells = len(_split(body, layout.separator))
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
        raise RecordingError(f"{path}: has a header but no data rows; the recording is empty")
    units = {nm: u for nm, u in zip(layout.names, layout.units, strict=True) if u}
    base = header_table(frame, units=units)
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


def _is_trailing_blank(drop: list[int], k: int, n: int) -> bool:
    """Whether row ``k`` belongs to the run of dropped rows that ends the file."""
    tail = set(drop)
    return all(j in tail for j in range(k, n))


def _ends_with_newline(path: Path) -> bool:
    with path.open("rb") as fh:
        fh.seek(0, 2)
        if fh.tell() == 0:
            return False
        fh.seek(-1, 2)
        return fh.read(1) in (b"\n", b"\r")


# ---------------------------------------------------------------------------------------------
# Timestamps: one format per column

_TIME_OF_DAY = r"(?P<H>\d{1,2}):(?P<M>\d{2})(?::(?P<S>\d{2})(?:[.,](?P<f>\d+))?)?"
_TZ = r"(?:\s*(?P<tz>Z|[+-]\d{2}:?\d{2}))?"
_DATE_PATTERNS = {
    # day or month first: 05.08.24 13:46:13, 05/08/2024 13:46:13.250
    "dmy": re.compile(
        r"^(?P<a>\d{1,2})(?P<sep>[./-])(?P<b>\d{1,2})(?P=sep)(?P<y>\d{4}|\d{2})"
        rf"(?:[ T]+{_TIME_OF_DAY})?{_TZ}$"
    ),
    # year first: 2024-08-05T13:46:13.250Z, 2024/08/05 13:46:13
    "ymd": re.compile(
        r"^(?P<y>\d{4})(?P<sep>[./-])(?P<b>\d{1,2})(?P=sep)(?P<a>\d{1,2})"
        rf"(?:[ T]+{_TIME_OF_DAY})?{_TZ}$"
    ),
    # time of day only: 13:46:13,250
    "tod": re.compile(rf"^{_TIME_OF_DAY}$"),
}


def looks_like_timestamp(cell: str) -> bool:
    """Whether a cell is a date/time such as ``05.08.24 13:46:13`` (not a plain number)."""
    c = str(cell).strip()
    return any(p.match(c) for p in _DATE_PATTERNS.values())


def _row_name(k: int, line_of: Callable[[int], int | None] | None) -> str:
    line = line_of(k) if line_of is not None else None
    return f"row {k}" + (f" (file line {line})" if line is not None else "")


def parse_timestamps(
    values,
    *,
    what: str,
    dayfirst: bool | None = None,
    date_format: str | None = None,
    line_of: Callable[[int], int | None] | None = None,
    decided: dict | None = None,
) -> tuple[np.ndarray, str]:
    """Seconds since the first sample of a column of date/time strings, and a note.

    One format is decided for the whole column and applied to every row (never a per-row guess,
    so a file crossing midnight or a day boundary cannot switch between day-first and
    month-first): ``date_format`` when given (:func:`time.strptime` codes); else dotted dates
    (``05.08.24 13:46:13,250``) are day-first (unless ``dayfirst`` is False), slash or dash dates
    are day-first when ``dayfirst`` is True or any first field of the column exceeds 12,
    month-first when any second field does (both: an error), month-first otherwise (noted as
    ambiguous); year-first dates (ISO 8601) are year-month-day, with ``Z``/``+hh:mm`` offsets
    applied. Times of day without a date are unwrapped at midnight (noted). Two-digit years are
    19xx from 69, else 20xx (as ``%y``).

    Parameters
    ----------
    values : array_like of str
        The column.
    what : str
        The column, for error messages (file and column name).
    dayfirst : bool, optional
        ``[file] dayfirst`` of the channel map.
    date_format : str, optional
        ``[file] date_format`` of the channel map (beats ``dayfirst``).
    line_of : callable, optional
        Row index -> 1-based file line, for error messages.
    decided : dict, optional
        For a column read in chunks: pass the same dict for every chunk. The first call stores
        the format it decided (pattern and day/month order) there, later calls apply it instead
        of deciding again, so every chunk is read the same way (a later chunk that does not fit
        is an error naming its row).

    Returns
    -------
    seconds : ndarray
        Time since the first row [s].
    note : str
        The format used and the first timestamp.

    Raises
    ------
    RecordingError
        An empty cell, a row that does not match the column's format (named with its line), an
        impossible date under the chosen order, slash dates that are day-first in some rows and
        month-first in others.

    Examples
    --------
    >>> t, note = parse_timestamps(["31.12.24 23:59:59", "01.01.25 00:00:01"], what="Zeit")
    >>> t.tolist()
    [0.0, 2.0]
    """
    import pandas as pd

    s = pd.Series(np.asarray(values, dtype=object)).map(
        lambda v: "" if v is None or (isinstance(v, float) and v != v) else str(v).strip()
    )
    if s.empty:
        raise RecordingError(f"{what}: no timestamps")
    empty = (s == "").to_numpy()
    if empty.any():
        k = int(np.flatnonzero(empty)[0])
        raise RecordingError(f"{what}: empty timestamp at {_row_name(k, line_of)}")
    if date_format is not None:
        stamps = pd.to_datetime(s, format=date_format, errors="coerce")
        bad = stamps.isna().to_numpy()
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise RecordingError(
                f"{what}: {_row_name(k, line_of)} {s.iloc[k]!r} does not match [file] "
                f"date_format {date_format!r} ({int(bad.sum())} row(s) in total)"
            )
        ns = stamps.to_numpy().astype("datetime64[ns]").astype(np.int64)
        secs = (ns - ns[0]) / 1e9
        return secs, (
            f"absolute timestamps parsed with [file] date_format {date_format!r}, converted to "
            f"seconds since the first sample ({stamps.iloc[0]})"
        )
    first = s.iloc[0]
    kind = next((k for k, p in _DATE_PATTERNS.items() if p.match(first)), None)
    if decided and kind is not None and decided.get("kind", kind) != kind:
        kind = decided["kind"]  # rows of another format are named below
    if kind is None:
        raise RecordingError(
            f"{what}: {_row_name(0, line_of)} {first!r} is neither a number nor a date/time this "
            "reader knows; give [file] date_format (e.g. '%d.%m.%Y %H:%M:%S') in the channel map"
        )
    if decided is not None:
        decided.setdefault("kind", kind)
    parts = s.str.extract(_DATE_PATTERNS[kind].pattern)
    nomatch = parts["H" if kind == "tod" else "a"].isna().to_numpy().copy()
    if kind != "tod":
        sep0 = parts["sep"].iloc[0]
        nomatch |= (parts["sep"] != sep0).to_numpy()
    if nomatch.any():
        k = int(np.flatnonzero(nomatch)[0])
        raise RecordingError(
            f"{what}: {_row_name(k, line_of)} {s.iloc[k]!r} does not have the format of the "
            f"first row {first!r}; give [file] date_format in the channel map"
        )
    tod = np.zeros(len(s))
    if "H" in parts and parts["H"].notna().any():
        has_time = parts["H"].notna().to_numpy()
        if not has_time.all():
            k = int(np.flatnonzero(~has_time)[0])
            raise RecordingError(
                f"{what}: {_row_name(k, line_of)} {s.iloc[k]!r} has no time of day, the first "
                f"row {first!r} has"
            )
        frac = parts["f"].fillna("0")
        tod = (
            parts["H"].astype(int).to_numpy() * 3600.0
            + parts["M"].astype(int).to_numpy() * 60.0
            + parts["S"].fillna("0").astype(int).to_numpy()
            + pd.to_numeric("0." + frac).to_numpy()
        )
    if kind == "tod":
        steps = np.diff(tod)
        wraps = np.concatenate(([0.0], np.cumsum(np.where(steps < -43200.0, 86400.0, 0.0))))
        note = f"times of day (first {first!r}) converted to seconds since the first sample"
        if wraps[-1]:
            note += f"; {int(wraps[-1] // 86400)} midnight crossing(s) unwrapped"
        t = tod + wraps
        return t - t[0], note
    a = parts["a"].astype(int).to_numpy()
    b = parts["b"].astype(int).to_numpy()
    y = parts["y"].astype(int).to_numpy()
    y = np.where(y < 100, np.where(y < 69, 2000 + y, 1900 + y), y)
    sep = parts["sep"].iloc[0]
    if kind == "ymd":
        day, month, order = a, b, "year-month-day"
    else:
        if decided and "first_is_day" in decided:
            first_is_day, order = decided["first_is_day"], decided["order"]
        elif sep == "." and dayfirst is not False:
            first_is_day, order = True, "day-first (dotted date)"
        elif dayfirst is not None:
            first_is_day = dayfirst
            order = f"{'day' if dayfirst else 'month'}-first ([file] dayfirst = {dayfirst})"
        else:
            day_a, day_b = a > 12, b > 12
            if day_a.any() and day_b.any():
                ka, kb = int(np.flatnonzero(day_a)[0]), int(np.flatnonzero(day_b)[0])
                raise RecordingError(
                    f"{what}: dates are day-first at {_row_name(ka, line_of)} "
                    f"({s.iloc[ka]!r}) but month-first at {_row_name(kb, line_of)} "
                    f"({s.iloc[kb]!r}); give [file] date_format in the channel map"
                )
            if day_a.any():
                first_is_day, order = True, "day-first (a first field > 12)"
            elif day_b.any():
                first_is_day, order = False, "month-first (a second field > 12)"
            else:
                first_is_day = False
                order = (
                    "month-first: AMBIGUOUS (every day and month field <= 12); set [file] "
                    "dayfirst = true in the channel map if the dates are day-first"
                )
        day, month = (a, b) if first_is_day else (b, a)
        if decided is not None:
            decided.setdefault("first_is_day", first_is_day)
            decided.setdefault("order", order)
    dates = pd.to_datetime(
        pd.DataFrame({"year": y, "month": month, "day": day}), errors="coerce"
    ).to_numpy()
    bad = np.isnat(dates)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise RecordingError(
            f"{what}: {_row_name(k, line_of)} {s.iloc[k]!r} is not a valid date read {order}; "
            "give [file] dayfirst or date_format in the channel map"
        )
    days = dates.astype("datetime64[D]").astype(np.int64)
    offset = np.zeros(len(s))
    if "tz" in parts and parts["tz"].notna().any():
        tz = parts["tz"].fillna("Z")
        sign = np.where(tz.str[0] == "-", -1.0, 1.0)
        digits = tz.str.replace(":", "", regex=False).str[1:]
        hh = pd.to_numeric(digits.str[:2], errors="coerce").fillna(0).to_numpy()
        mm = pd.to_numeric(digits.str[2:4], errors="coerce").fillna(0).to_numpy()
        offset = np.where(tz == "Z", 0.0, sign * (hh * 3600.0 + mm * 60.0))
    t = (days - days[0]) * 86400.0 + (tod - tod[0]) - (offset - offset[0])
    start = pd.Timestamp(dates[0]) + pd.Timedelta(seconds=float(tod[0]))
    return t, (
        f"absolute timestamps read {order} (first {first!r} = {start}), converted to seconds "
        "since the "
        "first sample"
    )
