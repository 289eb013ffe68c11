"""Excel workbooks (.xlsx, .xlsm) as test engineers and acquisition software write them (HBM
catman, Dewesoft, LabVIEW Report Generation, Excel itself).

One sheet is read: the map's ``[file] sheet`` (a name, or a 0-based index in Excel's tab order,
chart sheets counted), else the sheet with the most rows of numbers in its first
:data:`HEAD_ROWS` rows (a note names it and the others). The sheet is
read with openpyxl in read-only mode, values only (a formula gives the value Excel cached with
the file), its rows streamed and each column collected into an array of floats as it goes.

The layout is decided as a text file's is (:func:`~rollerrig.recordings.formats.sniff.
sniff_rows`, the rules of :func:`~rollerrig.recordings.formats.sniff.sniff_layout`): metadata
rows above the names, the names row, a units row or units in brackets in the names, key-value
rows, NaN words (``#N/A``, ``NaN``), blank rows (skipped, noted) and a footer below the numbers
(left out, noted). ``[file] header_row``, ``units_row`` and ``data_row`` count the sheet's rows
from 0 (row 1 of Excel is 0). Cells are mapped by their type, never through text: numbers as
they are stored (float64), date/time cells exactly from their serial day number (to the
microsecond, as far as the stored day number resolves it, about 1 µs; not openpyxl's
millisecond rounding): a date and time an absolute timestamp
(``datetime64``, read as seconds since the first sample), a time of day or a duration
(``[h]:mm:ss``) seconds (times of day unwrapped at midnight). A column of text cells is text,
as in a CSV file (timestamps written as text are parsed as there). Numbers stored as text are
read as numbers (noted), with a decimal comma under ``[file] decimal = ","`` or where all of a
column's text numbers use one; Excel's error cells (``#DIV/0!``...) are missing samples, noted.
Text in a column without a name and without numbers (a signature beside the data) is a footer
or ignored, noted.

Refused with a :class:`~rollerrig.recordings.recording.RecordingError`: an old binary ``.xls``
or an OpenDocument ``.ods`` (save as .xlsx or CSV), a password-protected or corrupt workbook,
merged cells in the names or units row, a sheet without numbers, text in a column of numbers
(naming the cell, ``Sheet1!C17``), formulas without saved values (a workbook a script wrote:
open and save it in Excel), a text file named .xlsx (rename it to .csv), and date/time cells
that cannot time the samples (steps rounded to the millisecond, or finer than the day number
resolves: write the time as a number).
"""

from __future__ import annotations

import codecs
import contextlib
import datetime as _dt
import math
import re
import zipfile
from array import array
from collections import deque
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig.recordings.channels import FileSpec, split_unit_header
from rollerrig.recordings.formats._table import Column, Table, add_alias, require_module
from rollerrig.recordings.formats._text import (
    NAN_WORDS,
    NEGATIVE_INFINITY_WORDS,
    NUMBER,
    POSITIVE_INFINITY_WORDS,
    bom_less_utf16,
    footer_rows,
    sample_in_footer,
)
from rollerrig.recordings.formats.sniff import sniff_rows
from rollerrig.recordings.recording import RecordingError

__all__ = ["read_xlsx"]

HEAD_ROWS = 2000
"""Rows of a sheet the layout is decided from (the whole sheet when shorter)."""
TAIL_ROWS = 200
"""Last rows of a sheet searched for a footer below the numbers."""

_OLE2 = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"  # compound file: .xls, and encrypted OOXML
_US_PER_DAY = 86_400_000_000

_XLS = (
    "an Excel 97-2003 workbook (.xls, binary BIFF) is not read; in Excel use File > Save As > "
    "Excel Workbook (.xlsx), or CSV, and read that file"
)
_ODS = (
    "OpenDocument spreadsheets (.ods) are not read; in LibreOffice Calc use File > Save As > "
    "Excel 2007-365 (.xlsx), or Text CSV, and read that file"
)


def refuse_other_spreadsheet(path: Path, head: bytes) -> None:
    """Raise for a file that is no .xlsx workbook though named or read as one: a compound file
    (an .xls, or an .xlsx encrypted with a password) or an OpenDocument spreadsheet."""
    if head.startswith(_OLE2):
        with path.open("rb") as fh:
            body = fh.read(1 << 20)
        if "EncryptedPackage".encode("utf-16-le") in body:
            raise RecordingError(
                f"{path}: the workbook is password-protected (encrypted); open it in Excel, "
                "remove the password (File > Info > Protect Workbook > Encrypt with Password) "
                "and save it again, or save the sheet as CSV"
            )
        raise RecordingError(f"{path}: {_XLS}")
    if head.startswith(b"PK") and b"mimetypeapplication/vnd.oasis.opendocument" in head[:200]:
        raise RecordingError(f"{path}: {_ODS}")


def _not_a_workbook(path: Path) -> str:
    """The message for a file named .xlsx that is no zip archive: a CSV file renamed (its
    bytes text) is told to be renamed back."""
    with path.open("rb") as fh:
        head = fh.read(4096)
    # text: UTF-16 (with a byte-order mark or by its look), or no control bytes but tab, CR,
    # LF, FF (a zip's "PK\x03\x04" has one) in any 8-bit code page (UTF-8, Windows-1252)
    utf16 = head.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)) or bool(
        bom_less_utf16(head)
    )
    text = utf16 or (bool(head.strip()) and not any(b < 9 or 13 < b < 32 for b in head))
    if text:
        return (
            f"{path}: not an Excel workbook: the file is text (a CSV or text export named "
            f"{path.suffix}); rename it to .csv and read that"
        )
    if head.startswith(b"PK\x03\x04"):  # a zip whose directory at its end is missing
        return (
            f"{path}: not a readable Excel workbook (.xlsx): the file is corrupt, cut short (a zip "
            "archive without its end, as a copy or download that stopped leaves it); use the "
            "complete file, or open it in Excel and save it again"
        )
    return (
        f"{path}: not a readable Excel workbook (.xlsx): the file is corrupt or of another "
        "format (no zip archive); open it in Excel and save it again as .xlsx, or as CSV"
    )


def read_xlsx(path: Path, spec: FileSpec | None = None) -> Table:
    """Read one sheet of an Excel workbook into a :class:`Table` (see the module docstring)."""
    openpyxl = require_module("openpyxl", "Excel workbooks (.xlsx)")
    path = Path(path)
    spec = spec or FileSpec()
    with path.open("rb") as fh:
        refuse_other_spreadsheet(path, fh.read(512))
    with contextlib.ExitStack() as stack:
        fh = stack.enter_context(path.open("rb"))
        try:
            wb = openpyxl.load_workbook(fh, read_only=True, data_only=True)
        except zipfile.BadZipFile:
            raise RecordingError(_not_a_workbook(path)) from None
        except Exception as exc:  # zipfile.BadZipFile, KeyError, lxml/ElementTree errors
            raise RecordingError(
                f"{path}: not a readable Excel workbook (.xlsx): the file is corrupt or of "
                f"another format ({type(exc).__name__}: {exc}); open it in Excel and save it "
                "again as .xlsx, or as CSV"
            ) from None
        stack.callback(wb.close)
        return _read_workbook(path, wb, spec)
    raise AssertionError("unreachable")  # pragma: no cover


def _read_workbook(path: Path, wb, spec: FileSpec) -> Table:
    sheets = list(wb.worksheets)  # chart sheets are not among them
    if not sheets:
        raise RecordingError(f"{path}: the workbook has no worksheets")
    # Date cells raw (their serial day number), converted here to the microsecond: openpyxl
    # rounds them to the millisecond. Where its internals differ, its datetimes are taken.
    dates = durations = None
    if hasattr(wb, "_date_formats") and hasattr(wb, "_timedelta_formats"):
        dates, durations = set(wb._date_formats), set(wb._timedelta_formats)
        wb._date_formats, wb._timedelta_formats = set(), set()
    reader = _Cells(wb, dates, durations)
    notes: list[str] = []
    if spec.sheet is not None:
        ws = _named_sheet(path, wb, sheets, spec.sheet)
        if len(sheets) > 1:
            notes.append(f"sheet {ws.title!r} read (of {[s.title for s in sheets]})")
    else:
        ws = _recording_sheet(path, sheets, reader, notes)
    table = _read_sheet(path, ws, reader, spec, notes)
    if len(sheets) > 1:
        others = [s.title for s in sheets if s is not ws]
        table.locate = lambda column: _where_else(path, ws.title, others, column)
    return table


def _recording_sheet(path: Path, sheets: list, reader: _Cells, notes: list[str]):
    """The sheet that holds the recording, where the map names none: of the sheets with
    numbers, the one with the most rows of numbers in its first :data:`HEAD_ROWS` rows (as
    deep as :func:`_read_sheet` looks for the names: a parameter block of 250 rows above them
    is no sheet without numbers). The first such sheet was a 3-row summary before the data."""
    counts = [reader.number_rows(s) for s in sheets]
    if not any(counts):
        raise RecordingError(
            f"{path}: no sheet holds numbers (sheets: {[s.title for s in sheets]}); "
            "a recording is a column of times and columns of numbers"
        )
    best = counts.index(max(counts))  # the first of equals: tab order
    ws = sheets[best]
    if len(sheets) > 1:
        deep = f" (of the first {HEAD_ROWS})" if counts[best] >= HEAD_ROWS else ""
        others = ", ".join(
            f"{s.title!r} ({c or 'no'} row(s) of numbers)"
            for s, c in zip(sheets, counts, strict=True)
            if s is not ws
        )
        notes.append(
            f"sheet {ws.title!r} read: the most rows of numbers ({counts[best]}{deep}); other "
            f"sheets: {others}; give [file] sheet in the channel map to read another"
        )
    return ws


def _where_else(path: Path, title: str, others: list[str], column: str) -> str:
    """For the error of a mapped column that the sheet read lacks: the sheet read, and the
    other sheets with whether their first rows name that column (the workbook opened again:
    only on that error)."""
    import openpyxl

    found: dict[str, bool] = {}
    with contextlib.suppress(Exception), path.open("rb") as fh:
        wb = openpyxl.load_workbook(fh, read_only=True, data_only=True)
        try:
            for ws in wb.worksheets:
                if ws.title in others:
                    found[ws.title] = _names_column(ws, column)
        finally:
            wb.close()
    told = ", ".join(
        f"{t!r}"
        + ("" if t not in found else f" ({'has a' if found[t] else 'no'} column {column!r})")
        for t in others
    )
    having = [t for t in others if found.get(t)]
    hint = f"[file] sheet = {having[0]!r}" if having else "[file] sheet"
    return (
        f"; sheet {title!r} was read; other sheets: {told}; give {hint} "
        "in the channel map to read another sheet"
    )


def _names_column(ws, column: str) -> bool:
    """Whether a text cell of the first :data:`HEAD_ROWS` rows of ``ws`` names ``column``
    (alone, or with a unit in brackets)."""
    for k, row in enumerate(ws.iter_rows(values_only=True)):
        if k >= HEAD_ROWS:
            break
        for v in row:
            if isinstance(v, str) and column in (v.strip(), split_unit_header(v.strip())[0]):
                return True
    return False


def _named_sheet(path: Path, wb, sheets: list, sheet: str | int):
    """The map's ``[file] sheet``: a name, or a 0-based index in Excel's tab order, chart
    sheets counted (the tab a user counts to); a chart sheet has no cells to read."""
    tabs = list(wb.sheetnames)  # worksheets and chart sheets, in tab order
    titles = [s.title for s in sheets]
    if isinstance(sheet, int):
        if sheet >= len(tabs):
            raise RecordingError(
                f"{path}: channel map [file] sheet = {sheet} but the workbook has "
                f"{len(tabs)} sheet(s): {tabs} (0-based index, in tab order)"
            )
        name = tabs[sheet]
    elif sheet not in tabs:
        raise RecordingError(
            f"{path}: channel map [file] sheet = {sheet!r} is not a sheet of the workbook; "
            f"sheets: {tabs}"
        )
    else:
        name = sheet
    if name not in titles:
        raise RecordingError(
            f"{path}: channel map [file] sheet = {sheet!r} is the chart sheet {name!r}, which "
            f"holds no cells; worksheets: {titles} (an index counts the tabs, chart sheets too)"
        )
    return sheets[titles.index(name)]


def _cell_name(title: str, column: int, row: int) -> str:
    """``Sheet1!C17`` (``'My data'!C17`` for a title Excel would quote); 0-based column."""
    from openpyxl.utils import get_column_letter

    sheet = title if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.]*", title) else f"'{title}'"
    return f"{sheet}!{get_column_letter(column + 1)}{row}"


class _Cells:
    """A sheet's rows as (kinds, values): per cell ``"n"`` number, ``"d"`` date/time serial,
    ``"t"`` time-of-day serial, ``"m"`` duration [days], ``"s"`` text, ``""`` empty."""

    def __init__(self, wb, dates: set | None, durations: set | None):
        self.dates, self.durations = dates, durations
        self.epoch = wb.epoch  # 1899-12-30 (Windows) or 1904-01-01 (Mac)

    def rows(self, ws):
        """Each row of ``ws`` as a list of (kind, value), as streamed (nothing kept)."""
        with contextlib.suppress(AttributeError):
            ws.reset_dimensions()  # a writer's wrong <dimension> would cut rows or columns
        for row in ws.iter_rows(values_only=False):
            yield [self.cell(c) for c in row]

    def cell(self, c) -> tuple[str, Any]:
        v = c.value
        if v is None:
            return "", None
        if isinstance(v, bool):
            return "n", float(v)
        if isinstance(v, int | float):
            style = getattr(c, "_style_id", None)
            if self.durations and style in self.durations:
                return "m", float(v)
            if self.dates and style in self.dates:
                return ("t" if 0 <= v < 1 else "d"), float(v)
            return "n", float(v)
        if isinstance(v, _dt.datetime):
            return "d", self.serial(v)
        if isinstance(v, _dt.time):
            return "t", (v.hour * 3600 + v.minute * 60 + v.second + v.microsecond / 1e6) / 86400
        if isinstance(v, _dt.timedelta):
            return "m", v / _dt.timedelta(days=1)
        if isinstance(v, _dt.date):
            return "d", self.serial(_dt.datetime.combine(v, _dt.time()))
        return "s", str(v)

    def serial(self, value: _dt.datetime) -> float:
        return (value.replace(tzinfo=None) - self.epoch) / _dt.timedelta(days=1)

    def number_rows(self, ws, rows: int = HEAD_ROWS) -> int:
        """How many of the first ``rows`` rows of ``ws`` hold a number, a date/time, or a
        text that is a number (a column of numbers stored as text)."""
        count = 0
        for k, row in enumerate(self.rows(ws)):
            if k >= rows:
                break
            if any(kind in "ndtm" or (kind == "s" and _is_text_number(v)) for kind, v in row):
                count += 1
        return count

    def text(self, kind: str, value: Any) -> str:
        """The cell as the layout rules read text (numbers with a decimal point)."""
        if kind == "":
            return ""
        if kind == "s":
            return value
        if kind == "n":
            return repr(value) if not value.is_integer() else str(int(value))
        us = _serial_us(np.array([value]))[0]
        if kind == "d":
            stamp = np.datetime64(self.epoch, "us") + np.timedelta64(int(us), "us")
            return str(stamp).replace("T", " ")
        s, frac = divmod(int(us), 1_000_000)
        return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}.{frac:06d}"


def _is_text_number(text: str) -> bool:
    """Whether a text cell is a number written as text (either decimal mark)."""
    return NUMBER.fullmatch(text.strip()) is not None


def _serial_us(serials: np.ndarray) -> np.ndarray:
    """Excel day numbers as whole microseconds (int64): the fraction of the day scaled alone,
    so its rounding is that of the serial's last bit (0.6 µs in the 2020s), not the product's."""
    day = np.floor(serials)
    return day.astype(np.int64) * _US_PER_DAY + np.rint((serials - day) * _US_PER_DAY).astype(
        np.int64
    )


_EXCEL_ERRORS = frozenset(
    {"#div/0!", "#value!", "#ref!", "#num!", "#name?", "#null!", "#spill!", "#calc!"}
)
"""Excel's error values (openpyxl gives them as text in data_only mode; #N/A is a NaN word)."""


def _text_number(text: str, mark: str) -> float | None:
    """A text cell that is a number under the decimal mark ``mark`` (Excel's green triangle:
    ``'6.5`` typed as text, or a column pasted from a German export, ``1,5``), else None."""
    t = text.strip()
    if NUMBER.fullmatch(t) is None:
        return None
    if mark == _UNDECIDED:  # integers only: a mark would be a guess
        return None if ("," in t or "." in t) else float(t)
    if ("," if mark == "." else ".") in t:
        return None
    return float(t.replace(",", "."))


_UNDECIDED = "?"
"""The decimal mark of a column whose numbers stored as text all read as thousands too."""
_THOUSANDS = {
    mark: re.compile(rf"[+-]?[1-9]\d{{0,2}}(?:{re.escape(mark)}\d{{3}})+") for mark in ",."
}
"""A text number that a thousands mark could have written (``1.000``, ``12,500``; a leading 0
cannot: ``0,500``)."""


def _text_marks(head: list[list[tuple[str, Any]]], given: str | None) -> dict[int, str]:
    """The decimal mark of each column's numbers stored as text: the map's ``[file] decimal``
    where given; else the one mark the column's text numbers use, where one of them at least
    cannot be a thousands mark (``1,5``, ``0,500``, ``1.25``: as the CSV reader decides a
    mark, never a guess); :data:`_UNDECIDED` where each could be one (``1.000``, ``1.120``: 1
    or 1000; a German column of thousands had read 1000 times too small); ``"."`` without
    marks."""
    width = max((len(r) for r in head), default=0)
    if given is not None:
        return dict.fromkeys(range(width), given)
    count = {",": [0] * width, ".": [0] * width}
    sure = {",": [False] * width, ".": [False] * width}
    for row in head:
        for j, (kind, v) in enumerate(row):
            if kind == "s" and _is_text_number(v):
                t = v.strip()
                for mark in ",.":
                    if mark in t:
                        count[mark][j] += 1
                        sure[mark][j] |= _THOUSANDS[mark].fullmatch(t) is None
    out = {}
    for j in range(width):
        only = [m for m in ",." if count[m][j]]
        if len(only) == 1:
            out[j] = only[0] if sure[only[0]][j] else _UNDECIDED
        else:
            out[j] = "."  # no mark, or both (refused cell by cell: 1.234,5)
    return out


class _Collector:
    """One column's cells as they stream by: floats (numbers, day numbers) in an
    :class:`array.array`, and the few cells that are no value of the column's kind."""

    def __init__(self, mark: str = "."):
        self.values = array("d")
        self.kind = ""  # the first value's kind: "n", "d", "t", "m", or "s" for text
        self.odd: dict[int, str] = {}  # data row -> a cell of another kind (text, a date...)
        self.mark = mark  # the decimal mark of its numbers stored as text
        self.native = 0  # cells stored as numbers or dates
        self.texts: dict[int, str] = {}  # data row -> a number stored as text, as written
        self.errors: dict[int, str] = {}  # data row -> an Excel error value (#DIV/0!)
        self.empty = 0  # empty cells

    def add(self, k: int, kind: str, value: Any) -> None:
        if kind == "":
            self.empty += 1
            self.values.append(math.nan)
            return
        if kind == "s":
            word = value.strip().lower()
            if word in _EXCEL_ERRORS:  # a formula's error: no value, as #N/A
                self.errors[k] = value
                self.values.append(math.nan)
                return
            if word in NAN_WORDS or not word:
                inf = word in POSITIVE_INFINITY_WORDS
                ninf = word in NEGATIVE_INFINITY_WORDS
                self.values.append(math.inf if inf else -math.inf if ninf else math.nan)
                return
            number = _text_number(value, self.mark)
            if number is not None and self.kind in ("", "n"):
                self.kind = "n"
                self.texts[k] = value
                self.values.append(number)
                return
            self.odd[k] = value
            self.values.append(math.nan)
            return
        self.native += 1
        if not self.kind:
            self.kind = kind
        if kind != self.kind and {kind, self.kind} != {"d", "t"}:
            self.odd[k] = f"{_KIND_NAMES[kind]} {value!r}"
        self.values.append(value)


_KIND_NAMES = {"n": "number", "d": "date", "t": "time of day", "m": "duration"}


def _read_sheet(path: Path, ws, reader: _Cells, spec: FileSpec, notes: list[str]) -> Table:
    title = ws.title
    where = f"{path} (sheet {title!r})"
    rows = reader.rows(ws)
    head: list[list[tuple[str, Any]]] = []
    for row in rows:
        head.append(row)
        if len(head) >= HEAD_ROWS:
            break
    complete = len(head) < HEAD_ROWS
    if complete:
        while head and not any(kind for kind, _ in head[-1]):
            head.pop()
    if not any(
        kind in "ndtm" or (kind == "s" and _is_text_number(v)) for row in head for kind, v in row
    ):
        raise RecordingError(
            f"{where}: the sheet holds no numbers or dates"
            + (" in its first rows" if not complete else "")
            + "; a recording is a column of times and columns of numbers"
        )
    width = max(len(r) for r in head)
    marks = _text_marks(head, spec.decimal)

    def text(j: int, kind: str, v: Any) -> str:
        # a number stored as text as the layout rules read numbers (with a decimal point)
        if kind == "s" and (number := _text_number(v, marks.get(j, "."))) is not None:
            return reader.text("n", number)
        return reader.text(kind, v)

    layout = sniff_rows(
        where,
        [
            [text(j, kind, v) for j, (kind, v) in enumerate(r)] + [""] * (width - len(r))
            for r in head
        ],
        spec,
        complete=complete,
    )
    notes.extend(layout.notes)
    names = list(layout.names)
    ncol = len(names)
    _refuse_merged_header(path, ws, title, layout)
    cols = [_Collector(marks.get(j, ".")) for j in range(ncol)]
    sheet_rows = array("l")  # 1-based sheet row of each data row
    tail: deque = deque(maxlen=TAIL_ROWS)  # the cells of the last rows
    blank = array("l")
    number = 0

    # cells right of the named columns: a signature or a comment beside the data is no
    # reason to refuse the sheet, a column of numbers without a name is (decided once the
    # footer is known): column -> [(row, value) of its first number, rows of text, first text]
    stray: dict[int, list] = {}

    def take(i: int, row: list[tuple[str, Any]]) -> None:
        for j in range(ncol, len(row)):
            kind, value = row[j]
            if kind:
                seen = stray.setdefault(j, [None, array("l"), None])
                if kind in "ndtm" or _is_text_number(value):
                    seen[0] = seen[0] or (i + 1, value)
                else:
                    seen[1].append(i + 1)
                    seen[2] = value if seen[2] is None else seen[2]
        if not any(kind for kind, _ in row[:ncol]):
            blank.append(i + 1)
            return
        k = len(sheet_rows)
        for j in range(ncol):
            kind, value = row[j] if j < len(row) else ("", None)
            cols[j].add(k, kind, value)
        sheet_rows.append(i + 1)
        tail.append(row[:ncol])  # as text only once the last rows are known

    for i, row in enumerate(head):
        if i >= layout.data_line:
            take(i, row)
        number = i + 1
    for row in rows:
        take(number, row)
        number += 1
    n = len(sheet_rows)
    last = [[text(j, kind, v) for j, (kind, v) in enumerate(cells)] for cells in tail]
    footer = footer_rows(last)
    if footer:
        sample = sample_in_footer(last)
        if sample is not None:
            at = sheet_rows[n - len(last) + sample]
            raise RecordingError(
                f"{path}: row {at} of sheet {title!r} below the samples is laid out as one, but "
                "its first column is no number or time this reader knows, so it and the rows "
                "after it would be dropped as a footer; correct that row"
            )
        first = sheet_rows[n - footer]
        notes.append(f"footer below the numbers left out: row {first} to the end")
        n -= footer
    cut = sheet_rows[n] if n < len(sheet_rows) else math.inf  # the footer's first row
    for j, (number, texts, first_text) in sorted(stray.items()):
        if number is not None and number[0] < cut:
            raise RecordingError(
                f"{path}: {_cell_name(title, j, number[0])} holds {number[1]!r} but its column "
                f"has no name ({ncol} named columns); name the column or clear it"
            )
        kept = [r for r in texts if r < cut]  # those in the footer went with it
        if kept:
            notes.append(
                f"{len(kept)} text cell(s) in a column without a name and without numbers "
                f"ignored (first: {_cell_name(title, j, kept[0])} {first_text!r})"
            )
    if n == 0:
        raise RecordingError(f"{where}: has a header but no data rows; the recording is empty")
    last = sheet_rows[n - 1]
    inside = [r for r in blank if r < last]
    if inside:
        notes.append(f"{len(inside)} blank row(s) inside the data skipped (first: row {inside[0]})")
    table = Table(names=names, load=lambda name: None)  # type: ignore[arg-type,return-value]
    for name in names:
        base, _ = split_unit_header(name)
        table.base[name] = base
        add_alias(table, base, name)
    table.repeated = {name: list(columns) for name, columns in layout.repeated}
    table.stated_rate = layout.rate_Hz
    table.notes += notes
    units = dict(zip(names, layout.units, strict=True))
    index = {name: j for j, name in enumerate(names)}
    rows_of = np.frombuffer(sheet_rows, dtype=sheet_rows.typecode)[:n].copy()

    def load(name: str) -> Column:
        j = index[name]
        col = cols[j]
        values = np.frombuffer(col.values, dtype=np.float64)[:n].copy()
        odd = {k: v for k, v in col.odd.items() if k < n}
        texts = {k: v for k, v in col.texts.items() if k < n}
        if n and 2 * col.empty >= n:  # mostly empty: formulas a script wrote, never computed?
            _refuse_formulas_without_values(path, title, j, name, rows_of, values)
        unit = split_unit_header(name)[1] or units[name]
        if odd and not col.native and len(texts) <= len(odd):  # mostly words: a text column
            return Column(_text_column(values, {**texts, **odd}, n), unit)
        marked = [k for k in sorted(odd) if _is_text_number(odd[k])]
        if col.mark == _UNDECIDED and marked:
            k = marked[0]
            raise RecordingError(
                f"{path}: column {name!r} holds numbers stored as text such as "
                f"{odd[k]!r} ({_cell_name(title, j, int(rows_of[k]))}) that read as decimals or "
                "with a thousands mark alike (1.000: 1 or 1000): give [file] decimal in the "
                "channel map"
            )
        if odd:
            k = min(odd)
            what = f"{_KIND_NAMES.get(col.kind, 'value')}s"
            raise RecordingError(
                f"{path}: {_cell_name(title, j, int(rows_of[k]))} holds {odd[k]!r} in column "
                f"{name!r} of {what}"
                + (f" ({len(odd)} such cells)" if len(odd) > 1 else "")
                + "; correct the cell, or clear it (an empty cell is a missing sample)"
            )
        if texts:
            k = min(texts)
            comma = " with a decimal comma" if col.mark == "," else ""
            why = (
                " (the map's [file] decimal)"
                if comma and spec.decimal
                else " (all its text numbers use one)"
                if comma
                else ""
            )
            table.notes.append(
                f"column {name!r}: {len(texts)} number(s) stored as text read as numbers"
                f"{comma}{why} (first: {_cell_name(title, j, int(rows_of[k]))} {texts[k]!r})"
            )
        errors = {k: v for k, v in col.errors.items() if k < n}
        if errors:
            k = min(errors)
            table.notes.append(
                f"column {name!r}: {len(errors)} Excel error cell(s) read as missing samples "
                f"(first: {_cell_name(title, j, int(rows_of[k]))} {errors[k]!r})"
            )
        if col.kind in ("d", "t", "m"):
            return Column(_times(col.kind, values, reader.epoch, where, name, table.notes), unit)
        return Column(values, unit)

    table.load = load
    # translate's messages on a text column: its row as the sheet's (Excel's) row number
    table.line_of = lambda k: int(rows_of[k]) if 0 <= k < n else None  # type: ignore[attr-defined]
    return table


def _refuse_formulas_without_values(
    path: Path, title: str, j: int, name: str, rows_of: np.ndarray, values: np.ndarray
) -> None:
    """Raise where the empty cells of a column are formulas without a saved value: a
    workbook written by a script (openpyxl, xlsxwriter) and never opened in Excel holds the
    formulas only, read as empty (values only), and the error had spoken of NaN samples. The
    workbook is opened again for its formulas, only for a column mostly empty."""
    import openpyxl

    empty = ~np.isfinite(values)
    found, first = 0, None
    with contextlib.suppress(Exception), path.open("rb") as fh:
        wb = openpyxl.load_workbook(fh, read_only=True, data_only=False)
        try:
            ws = wb[title]
            lo, hi = int(rows_of[0]), int(rows_of[-1])
            for r, (v,) in enumerate(
                ws.iter_rows(
                    min_row=lo, max_row=hi, min_col=j + 1, max_col=j + 1, values_only=True
                ),
                start=lo,
            ):
                k = int(np.searchsorted(rows_of, r))
                if isinstance(v, str) and v.startswith("=") and k < empty.size and empty[k]:
                    found += 1
                    first = first or r
        finally:
            wb.close()
    if found:
        raise RecordingError(
            f"{path}: cells of column {name!r} are formulas without saved values ({found} "
            f"cells, first {_cell_name(title, j, first)}): the workbook was written by a "
            "program that does not compute formulas; open and save the workbook in Excel (or "
            "LibreOffice), or export CSV"
        )


def _text_column(values: np.ndarray, odd: dict[int, str], n: int) -> np.ndarray:
    """A column of text (an event column, timestamps written as text) as a CSV reader gives
    it: the cells' text, NaN where empty."""
    out = np.empty(n, dtype=object)
    out[:] = values
    for k, v in odd.items():
        out[k] = v
    return out


def _times(kind: str, serials: np.ndarray, epoch, where: str, name: str, notes) -> np.ndarray:
    """A date/time column as ``datetime64[us]`` (dates and times) or ``timedelta64[us]``
    (times of day, unwrapped at midnight; durations), exactly to the microsecond."""
    ok = np.isfinite(serials)
    us = np.zeros(serials.size, dtype=np.int64)
    us[ok] = _serial_us(serials[ok])
    _check_resolution(us[ok], serials[ok], where, name)
    if kind == "t" and (np.diff(us[ok]) < -_US_PER_DAY // 2).any():
        wraps = np.concatenate([[0], np.cumsum(np.diff(us[ok]) < -_US_PER_DAY // 2)])
        us[ok] += wraps * _US_PER_DAY
        notes.append(f"column {name!r}: times of day unwrapped at midnight")
    if kind == "d":
        out = np.datetime64(epoch, "us") + us.astype("timedelta64[us]")
        out[~ok] = np.datetime64("NaT")
        return out
    out = us.astype("timedelta64[us]")
    out[~ok] = np.timedelta64("NaT")
    return out


def _check_resolution(us: np.ndarray, serials: np.ndarray, where: str, name: str) -> None:
    """Refuse date/time cells that cannot time the samples: steps finer than 50 times what
    the day number resolves (its last written digit, about 1 µs), or rounded to the
    millisecond (steps of a rate that is no whole number of milliseconds, such as 333 and
    334 µs at 3 kHz)."""
    if us.size < 3:
        return
    steps = np.diff(us)
    step = float(np.median(steps))
    # a day number is written with 16 significant digits (openpyxl; Excel 15-17): 0.86 µs in
    # this century, above the float's own last bit
    top = max(float(np.abs(serials).max()), 1.0)
    digits = 10.0 ** (math.floor(math.log10(top)) - 15)
    resolution = max(float(np.spacing(top)), digits) * _US_PER_DAY
    fix = (
        "; write the time as a column of numbers (seconds since the start, or a sample rate "
        "with [time] sample_rate_Hz in the channel map)"
    )
    if 0 < step < 50 * resolution:
        raise RecordingError(
            f"{where}: column {name!r}: its date/time cells resolve {resolution:.2g} µs (an "
            f"Excel day number), too coarse for samples {step:g} µs apart{fix}"
        )
    on_ms = (np.abs((us + 500) % 1000 - 500) <= 2).all()  # whole ms, to the day number's µs
    if on_ms and 900 < steps.max() - steps.min() <= 1004 and step < 50_000:
        raise RecordingError(
            f"{where}: column {name!r}: its date/time cells are rounded to the millisecond "
            f"(as Excel shows them), so steps of {round(steps.min() / 1000)} and "
            f"{round(steps.max() / 1000)} ms alternate and cannot give the sample rate{fix}"
        )


_MERGE = re.compile(rb'<(?:\w+:)?mergeCell\s+ref="([A-Z]+[0-9]+:[A-Z]+[0-9]+)"')


def _refuse_merged_header(path: Path, ws, title: str, layout) -> None:
    """Raise where cells merged across columns lie in the names or units row (a name over
    two columns leaves the second without one); merged title rows above them are fine."""
    from openpyxl.utils import get_column_letter
    from openpyxl.utils.cell import range_boundaries

    rows = {r + 1 for r in (layout.header_line, layout.units_line) if r is not None}
    member = getattr(ws, "_worksheet_path", None)
    if not rows or member is None:
        return
    with zipfile.ZipFile(path) as z, z.open(member) as fh:
        carry = b""
        while chunk := fh.read(1 << 20):
            text = carry + chunk
            for m in _MERGE.finditer(text):
                ref = m.group(1).decode()
                c0, r0, c1, r1 = range_boundaries(ref)
                if c1 > c0 and any(r0 <= r <= r1 for r in rows):
                    raise RecordingError(
                        f"{path}: merged cells {_cell_name(title, c0 - 1, r0)}:"
                        f"{get_column_letter(c1)}{r1} in the sheet's names or units "
                        "row: each column needs a name (and unit) of its own; unmerge them "
                        "in Excel and name every column"
                    )
            carry = text[-200:]
