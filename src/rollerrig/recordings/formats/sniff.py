"""Sniff the layout of a delimited text file (CSV, TSV, ASCII exports of acquisition software).

The layout is sniffed from the first lines of the file; every key of the channel map's
``[file]`` section (:class:`rollerrig.recordings.channels.FileSpec`) beats the sniffer:

- **preamble**: lines before the header (catman, DIAdem, PicoScope, CANape ASCII exports write
  the file name, date, comments there) are skipped. The numbers are the trailing block of lines
  whose every cell is a number, a timestamp, empty or a NaN/inf word; the header is the nearest
  non-blank line above it.
- **quoted line breaks**: a header cell with a line break inside its quotes (Excel's Alt+Enter,
  ``"Torque<LF>[N.m]"``) is one cell, the break read as a space (noted); its lines are one row.
- **units row**: a non-numeric row between the header and the numbers whose cells look like
  units (``(ms)``, ``[V]``, ``N·m``, ``1/min``; PicoScope, catman, DIAdem, CANape) gives the
  columns' units (:mod:`rollerrig.recordings.formats._header`). It is never used to sniff the
  decimal mark.
- **separator**: ``,`` ``;`` tab ``|`` or whitespace, the one under which the trailing block of
  numbers is longest and consistent with the header (ties: that order).
- **decimal mark**: ``,`` when the number cells of the data rows (never the header or units row)
  use it; a file mixing both marks is an error asking for ``[file] decimal``. Under the decimal
  mark (sniffed from cells such as ``-5.563`` or ``0,45``, or given) the other mark is a
  thousands mark only in strict groups of three digits (``"85,928"``, ``86.021``: noted with
  the column and an example cell); any other cell with it is an error naming line, column and
  cell, never a decimal point.
- **encoding**: UTF-8 (with or without BOM), UTF-16 with BOM (or without one, noted), else
  Latin-1 (noted).
- **exact columns**: numbers written with a fraction from 1e8 on (a time in seconds since
  LabVIEW's or Unix's epoch) are read as text, and the time reader reads them exactly.

The result, a :class:`TextLayout`, is what :func:`rollerrig.recordings.formats.csv.read_csv` and
the chunked reader (:mod:`rollerrig.recordings.source`) read the numbers with.
"""

from __future__ import annotations

import codecs
import contextlib
import csv
import dataclasses
import io
import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollerrig.recordings.channels import FileSpec
from rollerrig.recordings.formats._header import (
    column_names,
    column_units,
    ends_with_scope_extras,
    header_rows,
)
from rollerrig.recordings.formats._text import (
    EXACT_ABOVE,
    INTEGER,
    MARKED_NUMBER,
    bom_less_utf16,
    cell_kind,
    code_unit,
    datalike,
    decimal_marks,
    decode_text,
    footer_rows,
    lead_column,
    number_kinds,
    parse_number,
    split_cells,
    thousands_mark_beside_integers,
)
from rollerrig.recordings.recording import RecordingError

__all__ = ["HEAD_BYTES", "TextLayout", "sniff_layout", "sniff_rows", "where_named"]

HEAD_BYTES = 1 << 18
"""Bytes read to sniff the layout (256 KiB; the whole file when smaller)."""

_SNIFF_SEPARATORS = ("\t", ";", ",", "|", " ")


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
    thousands: tuple[str, ...] = ()  # columns written with thousands marks (strict groups)
    # columns of numbers with a fraction of EXACT_ABOVE and more (absolute times since an
    # epoch): read as text, so that translate.time_seconds reads them exactly
    exact: tuple[str, ...] = ()
    repeated: tuple[tuple[str, tuple[str, ...]], ...] = ()  # a repeated name, its columns' names
    decimal_decided: bool = True  # the decimal mark was given or sniffed, not a default
    cr_only: bool = False  # lines end in a lone CR (Mac Excel's "CSV (Macintosh)")
    rate_Hz: float | None = None  # a rate the header states (an oscilloscope's 1/Increment)
    # bytes of the file that hold its text: a NUL-padded tail (and the line it cut) left out
    # (:func:`nul_padded_end`); None: the whole file
    end: int | None = None
    # line breaks inside quoted header cells above the numbers (_join_quoted_breaks): pandas
    # skips rows, not lines, and such a cell's lines are one row
    joined: int = 0
    # a quote left open in a line above the numbers (a preamble's 'Title,"Run 7'): pandas,
    # which skips rows of CSV, would read on to the next quote as one row and lose the first
    # sample; the lines above the numbers are then skipped here, line by line
    # (:meth:`readable`'s ``skip_lines``)
    open_quote_above: bool = False

    @contextlib.contextmanager
    def readable(self, encoding: str | None = None, skip_lines: bool = False):
        """What :func:`pandas.read_csv` reads: the path, or for lines ending in a lone CR a
        text handle with universal newlines. pandas' C reader counted ``\\r\\r`` (a blank
        line) as one line end when skipping rows, so the first sample below a blank line
        was lost. A file with a NUL-padded tail (``end``): a handle on its first ``end``
        bytes. ``skip_lines`` (for :meth:`pandas_kwargs`' reader), where a quote is left open
        above the numbers (``open_quote_above``): a text handle past the lines above the
        numbers, read line by line."""
        by_lines = skip_lines and self.open_quote_above
        if not self.cr_only and self.end is None and not by_lines:
            yield self.path
            return
        with self.path.open("rb") as raw:
            fh = io.BufferedReader(_Head(raw, self.end))
            if self.cr_only or by_lines:
                fh = io.TextIOWrapper(fh, encoding=encoding or self.encoding, newline=None)
            with fh:
                for _ in range(self.data_line if by_lines else 0):
                    fh.readline()
                yield fh

    @property
    def n_fields(self) -> int:
        """Cells per data row (a trailing separator adds one empty cell)."""
        return len(self.names) + (1 if self.trailing else 0)

    def pandas_kwargs(self) -> dict:
        """Keyword arguments of :func:`pandas.read_csv` for the rows of numbers."""
        names = list(self.names) + (["__trailing__"] if self.trailing else [])
        return {
            "sep": r"\s+" if self.separator == " " else self.separator,
            # Undecided (no mark in the sniffed rows), pandas must not read a later '1.000' as
            # 1.0 itself: a decimal mark that never occurs leaves such a column as text, which
            # translate.as_float reads by the mark its own cells decide (or refuses).
            "decimal": self.decimal if self.decimal_decided else "\x00",
            "encoding": self.encoding,
            "header": None,
            "names": names,
            "skiprows": 0 if self.open_quote_above else self.data_line - self.joined,
            "skip_blank_lines": False,
            "index_col": False,
            "quotechar": '"',
            "engine": "c",
            "converters": {
                name: GroupedNumbers(self.path, name, self.decimal) for name in self.thousands
            },
            "dtype": {name: str for name in self.exact},
        }


_MOST_CELL_LINES = 8
"""Most lines one quoted header cell spans (Excel's Alt+Enter: a name over its unit)."""
_FIELD_STARTS = ",;\t|"
"""Characters after which a cell starts (any separator this sniffer tries but whitespace)."""


def _quote_state(line: str, sep: str, quoted: bool = False) -> tuple[bool, bool]:
    """``(ends inside a quoted cell, well formed)`` of ``line`` split at ``sep`` (``quoted``:
    it starts inside one), as CSV quoting reads it: a ``"`` that starts a cell opens it, ``""``
    inside is a quote, a ``"`` in the middle of an unquoted cell is a character (as pandas and
    Python's csv read it). Well formed: every quoted cell closed in the line is followed by
    ``sep`` or the line's end (``"Run 7 "Time"`` is not)."""
    start = not quoted
    well_formed = True
    k = 0
    while k < len(line):
        c = line[k]
        if quoted:
            if c == '"':
                if line[k + 1 : k + 2] == '"':
                    k += 1  # "" : a quote inside the cell
                else:
                    quoted = False
                    rest = line[k + 1 :].lstrip(" ")
                    well_formed = well_formed and (not rest or rest[0] == sep)
        elif c == '"' and start:
            quoted = True
        start = not quoted and (c == sep or (start and c == " "))
        k += 1
    return quoted, well_formed


def _data_separator(lines: list[str]) -> str | None:
    """The separator of the first line of numbers (the one of :data:`_FIELD_STARTS` that
    splits it into the most cells, all numbers), or None where no line is one."""
    for line in lines:
        found = [(len(c), sep) for sep in _FIELD_STARTS if datalike(c := split_cells(line, sep))]
        if found:
            return max(found)[1]
    return None


def _join_quoted_breaks(lines: list[str], notes: list[str]) -> tuple[list[str], list[int]]:
    """``lines`` with a quoted cell that spans lines (a header cell written with a line break
    in it, as Excel writes one typed with Alt+Enter: ``"Torque<LF>[N.m]"``) joined on its
    first line, the line break a space, and the lines it took blank, so that every line keeps
    its index; and the indices of the lines so blanked.

    Only above the first line of numbers (the header's lines), with the numbers' separator
    (a ``"`` after another character is no cell's start: ``Rad 6,"Zoll`` in a file of ``;``),
    where the cell closes within :data:`_MOST_CELL_LINES` lines that are no numbers, and where
    the joined line is well formed CSV (:func:`_quote_state`): a stray quote elsewhere, such
    as an unclosed one in a preamble line above the names, is left as it is.
    """
    out = list(lines)
    blanked: list[int] = []
    sep = _data_separator(lines)
    if sep is None:
        return out, blanked
    i = 0
    while i < len(out):
        line = out[i]
        if datalike(split_cells(line, sep)):
            break  # the numbers: a header is above them
        if '"' not in line or not _quote_state(line, sep)[0]:
            i += 1
            continue
        k, text = i, line
        while (
            k + 1 < len(out)
            and k - i < _MOST_CELL_LINES
            and _quote_state(text, sep)[0]
            and not datalike(split_cells(out[k + 1], sep))
        ):
            k += 1
            text = f"{text.rstrip()} {out[k].lstrip()}"
        still_open, well_formed = _quote_state(text, sep)
        if still_open or not well_formed:
            i += 1  # no closing quote near, or not one cell: left as it is
            continue
        notes.append(
            f"lines {i + 1}-{k + 1} are one row: a quoted cell with a line break in it (Excel's "
            f"Alt+Enter), read with a space for the break ({text.strip()[:60]!r})"
        )
        out[i] = text
        for j in range(i + 1, k + 1):
            out[j] = ""
            blanked.append(j)
        i = k + 1
    return out, blanked


def _data_block(
    rows: list[tuple[int, list[str]]],
    partial_last: bool,
    at_eof: bool = False,
    header_given: bool = False,
) -> tuple[list[tuple[int, list[str]]], int]:
    """(trailing block of data rows, cells per row).

    ``at_eof``: ``rows`` end with the file's last line; a footer below the numbers
    (:func:`~rollerrig.recordings.formats._text.footer_rows`) is then not part of the block.

    Walking up from the last row, a row belongs to the data when it has a number or timestamp
    and at most half of the numeric columns (columns that are numbers in >= 80 % of the last
    rows) hold text in it: a stray ``ERR`` cell stays in the data (reported later with its line),
    a header or units row, text in every numeric column, ends the block.
    """
    while rows and not any(c.strip() for c in rows[-1][1]):
        rows = rows[:-1]  # separator-only rows at the end (Excel's empty rows): blank
    if at_eof:
        footer = footer_rows([f for _, f in rows[-200:]])
        rows = rows[: len(rows) - footer]
    kinds = [(i, f, [cell_kind(c) for c in f]) for i, f in rows]
    tail = [x for x in kinds[-50:] if any(k in ("num", "time") for k in x[2])]
    if not tail:
        return [], 0
    sample = tail[:-1] if partial_last and len(tail) > 1 else tail
    n = Counter(len(f) for _, f, _ in sample).most_common(1)[0][0]
    ref = [x for x in sample if len(x[1]) == n]
    numeric = [j for j in range(n) if sum(x[2][j] != "text" for x in ref) >= 0.8 * len(ref)]
    allowed = len(numeric) // 2
    block: list[tuple[int, list[str]]] = []
    missing: list[tuple[int, list[str]]] = []  # rows of only NaN or empty cells, seen last
    for i, f, k in reversed(kinds):
        if n >= 2 and len(k) == n and all(x in ("nan", "empty") for x in k):
            # a sample whose every value is missing: inside the data it is a row of the table
            # (NaN, refused or interpolated by the reader's check), not the end of the block,
            # which made the rows below it look like a second recording; above the first row of
            # numbers (a blank units row) it is not data
            missing.append((i, f))
            continue
        if not any(x in ("num", "time") for x in k):
            break
        if sum(1 for j in numeric if j < len(k) and k[j] == "text") > allowed:
            break
        block.extend(missing)
        missing = []
        block.append((i, f))
    block.reverse()
    return _without_leading_names(block, kinds, n, header_given), n


def _without_leading_names(
    block: list[tuple[int, list[str]]], kinds, n: int, header_given: bool = False
) -> list[tuple[int, list[str]]]:
    """``block`` without the rows at its top that hold names, not samples.

    A row of names with numbers among them (``Time;1;2``, channels numbered) or key-value
    rows above the numbers (TwinCAT Scope's ``SampleTime[ms]<TAB>1``) fit the rule "at most
    half of the numeric columns text", and were read as samples. A row is names when its lead
    column (:func:`~rollerrig.recordings.formats._text.lead_column`, the time column of most
    files: numbers in the rows below) holds text. The top row so leaves the block unless a row
    of names (n cells, no number) sits right above it (then its text is a stray cell under the
    header); two or more such rows at the top leave it whatever is above (the rows of only
    missing values below them go too). Under a header the map gives (``header_given``), so
    does text left of the lead column in a column the samples leave empty (the key of a
    key-value row between the header and the numbers; without it, a marker column on the
    left is that). Text in other columns (an event column,
    a sensor's ``OPEN``) keeps a row a sample.
    """
    # the rows below the top, a few hundred of them (this runs for every separator tried)
    below = [number_kinds(f) for _, f in block[1:201]]
    lead = lead_column(below, n)
    if lead is None:
        return block
    # columns left of the lead that the samples leave empty: a key there beside numbers (a
    # Yokogawa export's "SampleRate,,10000,10000" between its header and its samples) makes a
    # row of names (an event column, on the right, does not)
    rows_n = [k for k in below if len(k) == n]
    empty = {
        j for j in range(lead) if sum(k[j] == "empty" for k in rows_n) >= 0.8 * max(1, len(rows_n))
    }
    if not header_given:
        # Without a header from the map, such a column is a key column only where its text
        # fills the block's top rows and nothing below them: catman's "Anzahl Werte" and
        # "dt" rows under its units row had been read as two samples (2000, 0.001). A marker
        # column's text appears among the samples too.
        empty = {j for j in empty if _text_only_at_top(block[:201], j)}
    cells = dict(block)

    def names(i: int) -> bool:
        kinds_i = number_kinds(cells[i])
        return (lead < len(kinds_i) and kinds_i[lead] == "text") or any(
            kinds_i[j] == "text" for j in empty if j < len(kinds_i)
        )

    run = 0
    while run < len(block) and names(block[run][0]):
        run += 1
    if run == 0 or run == len(block):
        return block
    if run == 1:
        above = [x for x in kinds if x[0] < block[0][0] and any(c != "empty" for c in x[2])]
        if above:
            k = above[-1][2]
            if len(k) in (n, n - 1) and not any(c in ("num", "time") for c in k):
                return block  # names right above: a stray text cell in the first sample
    rest = block[run:]
    while rest and all(c in ("nan", "empty") for c in number_kinds(rest[0][1])):
        rest = rest[1:]
    return rest if rest else block


def _text_only_at_top(block: list[tuple[int, list[str]]], column: int) -> bool:
    """True where the cells of ``column`` that hold text are the first rows of ``block``, at
    least two and no later row's, and each of those rows holds one value in every other cell
    (catman's ``Anzahl Werte<TAB>2000<TAB>2000``, ``dt<TAB>0,001<TAB>0,001``: a property of
    each channel), unlike samples beside a marker (``Start,0.000,1.0``)."""
    text = [
        i for i, (_, f) in enumerate(block)
        if column < len(f) and number_kinds(f)[column] == "text"
    ]  # fmt: skip
    if len(text) < 2 or text != list(range(len(text))):
        return False
    for i in text:
        cells = block[i][1]
        values = {c.strip() for j, c in enumerate(cells) if j != column and c.strip()}
        if len(values) != 1 or sum(1 for c in cells if c.strip()) < 3:
            return False
    return True


_MOST_KEY_ROWS = 6  # catman writes T0, dt and Anzahl Werte (and a few more keys) as rows


def _key_value_row(text: str, sep: str) -> bool:
    """True for a row of a key and then only numbers or timestamps (catman's ``T0``,
    ``dt<TAB>0,001``)."""
    kinds = number_kinds(split_cells(text, sep))
    rest = kinds[1:]
    return (
        bool(kinds)
        and kinds[0] == "text"
        and ("num" in rest or "time" in rest)
        and all(k in ("num", "time", "empty", "nan") for k in rest)
    )


def _looks_like_a_key(cell: str) -> bool:
    """True for a word such as catman's ``T0``, ``dt`` or ``Anzahl Werte``: a time or a number
    in a format the sniffer does not know has more digits."""
    return sum(c.isdigit() for c in cell) < 3


def _refuse_a_header_without_samples(p, lines: list[tuple[int, str]], sep: str) -> None:
    """Raise where the file ends in at most :data:`_MOST_KEY_ROWS` key-value rows (catman's
    ``T0`` and ``dt``) under a row of names: the header is whole but the samples are missing,
    a file cut before its data or an export of no samples. Their numbers had been taken for
    samples, and the error then asked for a date_format or found no channels."""
    k = len(lines)
    while k > 0 and len(lines) - k < _MOST_KEY_ROWS + 1:
        text = lines[k - 1][1]
        if not (_key_value_row(text, sep) and _looks_like_a_key(split_cells(text, sep)[0])):
            break
        k -= 1
    if k == len(lines) or k == 0 or len(lines) - k > _MOST_KEY_ROWS:
        return
    names = number_kinds(split_cells(lines[k - 1][1], sep))
    n = max(len(split_cells(t, sep)) for _, t in lines[k:])
    if len(names) < 2 or len(names) not in (n, n + 1) or not all(c == "text" for c in names):
        return
    keys = [split_cells(t, sep)[0].strip() for _, t in lines[k:]]
    raise RecordingError(
        f"{p}: has a header but no data rows: the rows under its names ({', '.join(keys)}) are "
        "the header's key-value rows, not samples; the file may have been cut before its "
        "data, or exported with no samples"
    )


def _without_key_rows(above: list[tuple[int, str]], sep: str, n: int) -> list[tuple[int, str]]:
    """``above`` (the lines above the numbers) without the key-value rows at its end, a key
    and then only numbers or timestamps (catman's ``T0``, ``dt<TAB>0,001`` and ``Anzahl
    Werte<TAB>2000`` under its names and units), where a row of names with no number in it
    stands above them: that row, not the last key-value row, is then the header. A row of
    names with numbers among them (``Time;1;2``, channels numbered) with no such row above
    stays the header."""

    k = len(above)
    while k > 0 and _key_value_row(above[k - 1][1], sep):
        k -= 1
    if k == len(above) or k == 0:
        return above
    names = number_kinds(split_cells(above[k - 1][1], sep))
    # every cell a name: a preamble row that Excel padded to the columns' count ("Device;DL850;"
    # above a header "Time;1;2" of numbered channels) has empty cells, and is no header
    if len(names) in (n, n + 1) and all(c == "text" for c in names[:n]):
        return above[:k]
    return above


def _score(
    lines: list[tuple[int, str]],
    sep: str,
    partial_last: bool,
    at_eof: bool = False,
    header_given: bool = False,
) -> tuple[int, int, list[tuple[int, list[str]]]]:
    """(rows with the usual cell count, cells per row, block) of ``sep``; score 0 when the
    header above the block does not fit the rows. Ties go to the earlier separator of
    :data:`_SNIFF_SEPARATORS` (whitespace last)."""
    rows = [(i, split_cells(t, sep)) for i, t in lines]
    block, n = _data_block(rows, partial_last, at_eof, header_given)
    if not block:
        return 0, 0, block
    above = [f for i, f in rows if i < block[0][0]]
    if above:
        h = len(above[-1])
        trailing = all(f[-1] == "" for _, f in block if len(f) == n)
        header_ok = (
            h == n
            or (h == n - 1 and trailing)
            or (h == n + 1 and above[-1][-1].strip() == "")
            or any(ends_with_scope_extras(f) for f in above[-2:])  # Rigol: wider header
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
    end = _text_end(p, raw, spec, notes)
    if end is not None:
        size, raw = end, raw[:end]
    if not raw.strip():
        raise RecordingError(f"{p}: the file is empty")
    encoding, text = decode_text(
        p,
        raw,
        spec.encoding,
        notes,
        truncated=size > len(raw),
        fallback="latin-1",
        fallback_name="Latin-1",
        binary_hint="is it a binary file with a text suffix? Export the recording as CSV/ASCII, "
        "or read it with its own format (format='tdms', 'mf4', 'mat', ...)",
    )
    all_lines = re.split(r"\r\n|\r|\n", text)
    truncated_head = size > len(raw)
    if truncated_head and len(all_lines) > 1:
        all_lines = all_lines[:-1]  # the head ends inside a line
    elif all_lines and all_lines[-1] == "":
        all_lines = all_lines[:-1]
    all_lines, joined = _join_quoted_breaks(all_lines, notes)
    partial_last = not truncated_head and not text.endswith(("\n", "\r"))
    return _layout_of_lines(
        p,
        all_lines,
        spec,
        notes,
        encoding=encoding,
        truncated_head=truncated_head,
        partial_last=partial_last,
        cr_only="\r" in text and "\n" not in text,
        end=end,
        joined=joined,
    )


def sniff_rows(
    where: str | Path, rows: list[list[str]], spec: FileSpec | None = None, *, complete: bool
) -> TextLayout:
    """The layout of a table of cells (a spreadsheet's rows, each a list of cell texts: numbers
    written with a decimal point, empty cells ``""``), decided by the rules of
    :func:`sniff_layout`: the preamble above the names, the names row, a units row or units in
    brackets, key-value rows, the rows of numbers and a footer below them.

    Row ``k`` of ``rows`` is "line" ``k`` of the layout (``[file] header_row``, ``units_row``
    and ``data_row`` count the rows, 0-based). ``complete``: ``rows`` are all the rows there
    are (a footer below the numbers is then found); else the head of a longer table. The
    layout's separator is a tab and its decimal mark ``"."`` (the cells are no text to sniff);
    ``where`` names the table in messages.

    Examples
    --------
    >>> lay = sniff_rows("book.xlsx", [["Test 7", ""], ["t", "F [kN]"], ["0.0", "1"],
    ...                                ["0.5", "2"]], complete=True)
    >>> lay.header_line, lay.names, lay.units, lay.data_line
    (1, ('t', 'F [kN]'), (None, None), 2)
    """
    spec = dataclasses.replace(spec or FileSpec(), separator="\t", decimal=".", encoding=None)
    lines = []
    for row in rows:
        out = io.StringIO()
        cells = [str(c).replace("\t", " ").replace("\r", " ").replace("\n", " ") for c in row]
        csv.writer(out, delimiter="\t", lineterminator="").writerow(cells)
        lines.append(out.getvalue())
    return _layout_of_lines(
        Path(where),
        lines,
        spec,
        [],
        encoding="utf-8",
        truncated_head=not complete,
        partial_last=False,
    )


def _layout_of_lines(
    p: Path,
    all_lines: list[str],
    spec: FileSpec,
    notes: list[str],
    *,
    encoding: str,
    truncated_head: bool,
    partial_last: bool,
    cr_only: bool = False,
    end: int | None = None,
    joined: list[int] | tuple[int, ...] = (),
) -> TextLayout:
    """:func:`sniff_layout` from the file's lines on (its head's, ``truncated_head``)."""
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
        score, n, block = _score(
            lines_for_sniff, sep, partial_last, not truncated_head, spec.header_row is not None
        )
        if first_data is not None:
            block = [(i, split_cells(t, sep)) for i, t in lines_for_sniff]
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
        score, n, block = _score(
            lines_for_sniff, sep, partial_last, not truncated_head, spec.header_row is not None
        )
        if first_data is not None:
            block = [(i, split_cells(t, sep)) for i, t in lines_for_sniff]
        if not block:
            if first_data is None and spec.header_row is None:
                for c in candidates:
                    _refuse_a_header_without_samples(p, lines, c)
            shown = [t[:80] for _, t in lines[:5]]
            if len(lines) <= 3:
                raise RecordingError(
                    f"{p}: has a header but no data rows (lines: {shown}); the recording is empty"
                )
            raise RecordingError(
                f"{p}: no rows of numbers found (first lines: {shown}); give the layout in the "
                "channel map's [file] section (separator, decimal, header_row, data_row)"
                + _footer_hint(lines, candidates)
            )
        best = (score, 1, block, sep)
    _, n, block, sep = best
    if (
        not truncated_head
        and n >= 20
        and n >= 10 * len(block)
        and not any(i < block[0][0] for i, _ in lines)  # a row of names rules it out
    ):
        # LabVIEW's "Write Delimited Spreadsheet" with transpose on: one channel per row; read
        # as a recording of as many samples as channels, without a word
        raise RecordingError(
            f"{p}: {len(block)} rows of {n} cells: one channel per row (a transposed export, "
            "LabVIEW's 'Write Delimited Spreadsheet' with transpose)? rollerrig reads one "
            "channel per column; write the file untransposed"
        )
    data_line = block[0][0] if first_data is None else first_data
    if first_data is None and spec.header_row is None:
        _refuse_a_header_without_samples(p, lines, sep)
    if spec.separator is None and sep != ",":
        notes.append(f"separator {sep!r} sniffed")

    if first_data is None and n >= 2:
        # rows of numbers above the header: two recordings appended, a repeated header
        earlier = [
            i
            for i, t in lines_for_sniff
            if i < data_line and len(f := split_cells(t, sep)) == n and datalike(f)
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
    marked = [
        (i, j, c, m)
        for i, f in block[:2000]
        for j, c in enumerate(x.strip() for x in f)
        if cell_kind(c) != "time" and (m := decimal_marks(c))
    ]
    integers = {
        j: c
        for i, f in reversed(block[:2000])
        for j, c in enumerate(x.strip() for x in f)
        if INTEGER.fullmatch(c)
    }
    decimal, evidence = _decimal_mark(p, spec.decimal, marked, integers)
    if spec.decimal is None and decimal == ",":
        notes.append("CSV uses decimal commas (sniffed from the data rows)")

    # --- header and units rows
    above = [(i, t) for i, t in lines if i < data_line]
    if spec.header_row is None and spec.units_row is None:
        above = _without_key_rows(above, sep, n)
    header_line, units_line = header_rows(above, sep, spec)
    if header_line is None and sep == "," and n == 2 and spec.separator is None:
        _refuse_one_column_of_decimal_commas(p, block)
    text_of = dict(lines)
    if header_line is not None and header_line >= len(all_lines):
        raise RecordingError(
            f"{p}: {where} header_row = {header_line} but the file has {len(all_lines)} lines"
        )
    # A trailing separator leaves every row's last cell empty and has no name in the header; a
    # last column the header names is a channel, empty until its sensor is switched on.
    header_cells = split_cells(text_of.get(header_line, ""), sep) if header_line is not None else []
    named_last = len(header_cells) >= n and header_cells[n - 1].strip() != ""
    trailing = n >= 2 and not named_last and all(len(f) == n and f[-1] == "" for _, f in block)
    repeated: dict[str, list[str]] = {}
    stated: dict[str, float] = {}
    names = column_names(
        p,
        text_of,
        header_line,
        sep,
        n,
        trailing,
        data_line=data_line,
        separator_given=spec.separator is not None,
        notes=notes,
        repeated=repeated,
        stated=stated,
    )
    if units_line is not None:
        if units_line >= len(all_lines):
            raise RecordingError(
                f"{p}: {where} units_row = {units_line} but the file has {len(all_lines)} lines"
            )
        if spec.units_row is None:
            notes.append(f"units row (line {units_line + 1}) used for the columns' units")
            skipped = [i for i, _ in above if units_line < i]
            if skipped:
                notes.append(
                    f"line {skipped[0] + 1} between the units row and the numbers skipped "
                    f"({text_of[skipped[0]].strip()[:60]!r}: descriptions)"
                )
    units = column_units(text_of, units_line, sep, n, len(names))
    # Thousands marks only under a decided decimal mark: undecided, '12,345' is 12345 or 12.345
    # and the column's own cells decide (translate.as_float), or it is refused.
    decided = evidence != "the default"
    thousands = (
        _thousands_columns(p, block[:2000], names, decimal, evidence, notes) if decided else []
    )
    exact = _exact_columns(block[:2000], names, decimal, thousands) if decided else []
    return TextLayout(
        path=p,
        encoding=encoding,
        separator=sep,
        decimal=decimal,
        header_line=header_line,
        units_line=units_line,
        data_line=data_line,
        names=tuple(names),
        units=tuple(units),
        trailing=trailing,
        notes=tuple(notes),
        thousands=tuple(thousands),
        exact=tuple(exact),
        repeated=tuple((k, tuple(v)) for k, v in repeated.items()),
        cr_only=cr_only,
        decimal_decided=decided,
        rate_Hz=stated.get("rate_Hz"),
        end=end,
        joined=sum(1 for i in joined if i < data_line),
        open_quote_above=any(
            '"' in t and _quote_state(t, sep)[0] for i, t in text_of.items() if i < data_line
        ),
    )


def text_end(path: Path, spec: FileSpec, notes: list[str]) -> int | None:
    """The bytes of the text file ``path`` that hold its lines where it ends in NUL padding (a
    logger that lost power; noted), else None (:func:`_text_end` on the file's head): for the
    readers that decode a whole file (LabVIEW .lvm, TwinCAT Scope exports)."""
    with path.open("rb") as fh:
        head = fh.read(HEAD_BYTES)
    return _text_end(path, head, spec, notes)


def _text_end(path: Path, head: bytes, spec: FileSpec, notes: list[str]) -> int | None:
    """The bytes of a text file that hold its lines when it ends in NUL bytes and has none
    before them (:func:`nul_padded_end`; noted), else None: a NUL byte elsewhere is refused as
    binary content (:func:`~rollerrig.recordings.formats._text.decode_text`).

    UTF-16 text (a BOM, the map's ``[file] encoding``, or its look without a BOM) has a NUL
    byte in every ASCII character: its padding is the run of NUL code units after its last
    character, found a code unit at a time (a line end ``0A 00`` keeps its zero byte)."""
    if b"\x00" not in head and len(head) < HEAD_BYTES:
        return None  # the whole file, no NUL byte
    order = _utf16_order(head, spec)
    if order is None and spec.encoding is not None and code_unit(spec.encoding) > 1:
        return None  # UTF-32: never written by a logger of ours
    found = nul_padded_end(path, order=order)
    if found is None:
        return None
    end, pad, cut = found
    if order is None and (b"\x00" in head[:end] or not head[: min(end, 4096)].strip()):
        return None  # NUL bytes before the padding (binary, or UTF-16 without a BOM)
    if order is not None and not _code_units(head[:end], order).all():
        return None  # a NUL character before the padding: binary, not UTF-16 text
    text = cut.decode(order or "latin-1", errors="replace").strip().strip("\x00")
    notes.append(
        f"the file ends in {pad} NUL bytes (from byte {end + len(cut)}), as a logger that lost "
        "power leaves it, zero-filled after the last line it wrote: left out"
        + (f", with the line they cut ({text[-40:]!r})" if text else "")
    )
    return end


def _utf16_order(head: bytes, spec: FileSpec) -> str | None:
    """``"utf-16-le"`` / ``"utf-16-be"`` where the file is UTF-16 (the map's ``[file]
    encoding``, a BOM, or the look of it without one), else None."""
    if spec.encoding is not None:
        try:
            name = codecs.lookup(spec.encoding).name
        except LookupError:
            return None
        if name in ("utf-16-le", "utf-16-be"):
            return name
        if name != "utf-16":
            return None
    if head.startswith(codecs.BOM_UTF16_BE):
        return "utf-16-be"
    if head.startswith(codecs.BOM_UTF16_LE) or spec.encoding is not None:
        return "utf-16-le"  # the codec "utf-16" without a BOM reads little-endian
    return bom_less_utf16(head)


def _code_units(raw: bytes, order: str) -> np.ndarray:
    """The UTF-16 code units of ``raw`` (``order`` ``"utf-16-le"`` / ``"utf-16-be"``; an odd
    last byte left out)."""
    dtype = "<u2" if order == "utf-16-le" else ">u2"
    return np.frombuffer(raw[: len(raw) - len(raw) % 2], dtype=dtype)


def _refuse_one_column_of_decimal_commas(path: Path, block) -> None:
    """Refuse a file without names whose every line is ``integer,digits`` with fixed-width or
    zero-led digits (``0,0000`` / ``29,5520``): one column of numbers with a decimal comma as
    likely as two columns of integers, and read as the latter it lost every decimal."""
    rows = [f for _, f in block if len(f) == 2]
    if len(rows) != len(block) or not all(INTEGER.fullmatch(c.strip()) for f in rows for c in f):
        return
    right = [f[1].strip() for f in rows]
    fixed = len({len(c) for c in right}) == 1 and len(right[0]) >= 3
    if fixed or any(len(c) > 1 and c.startswith("0") for c in right):
        raise RecordingError(
            f"{path}: every line reads as one number with a decimal comma ({rows[0][0]},"
            f"{rows[0][1]}) or as two integers; give [file] separator and decimal in the "
            'channel map (separator = ";" and decimal = "," for the first)'
        )


def _footer_hint(lines: list[tuple[int, str]], separators) -> str:
    """Where the file's last line is text below rows of numbers (a footer such as "End of
    measurement"): say so, since the rows are read up to the end of the file."""
    body = [(i, t) for i, t in lines if t.strip()]
    if len(body) < 3:
        return ""
    last_line, last = body[-1]
    for sep in separators:
        if not datalike(split_cells(last, sep)) and any(
            datalike(split_cells(t, sep)) for _, t in body[-50:-1]
        ):
            return (
                f"; the last line {last_line + 1} ({last.strip()[:60]!r}) is text below rows of "
                "numbers, which are read to the end of the file: remove that footer"
            )
    return ""


def _decimal_mark(
    path: Path,
    given: str | None,
    marked: list[tuple[int, int, str, frozenset[str]]],
    integers: dict[int, str] | None = None,
) -> tuple[str, str]:
    """(decimal mark, how it was decided) from the data cells with a ``.`` or ``,``.

    ``marked``: (line, column, cell, marks under which the cell is a number). A cell that is a
    number under one mark only (``0,45``, ``-5.563``, ``1,002.5``) decides; ``85,928`` and
    ``86.021`` (a decimal mark, or thousands marks in groups of three) decide only in a column
    that holds plain integers (``integers``: column -> an integer cell of it) beside such a
    cell ending in 0, which writes thousands marks
    (:func:`~rollerrig.recordings.formats._text.thousands_mark_beside_integers`); else the
    mark stays undecided (``"."``, ``"the default"``: :attr:`TextLayout.decimal_decided` is
    False), never guessed. The map's ``[file] decimal`` wins.
    """
    if given is not None:
        return given, "given in [file] decimal"
    only = {d: next((x for x in marked if x[3] == {d}), None) for d in ".,"}
    if only["."] is not None and only[","] is not None:
        raise RecordingError(
            f"{path}: the data rows mix decimal marks ({_at(only[','])} and {_at(only['.'])}); "
            'give [file] decimal = "." or "," in the channel map'
        )
    for d in ".,":
        if only[d] is not None:
            return d, f"sniffed from cells such as {_at(only[d])}"
    both = {d: next((c for _, _, c, _ in marked if d in c), None) for d in ".,"}
    if both["."] is not None and both[","] is not None:
        raise RecordingError(
            f"{path}: the data rows mix decimal marks ({both[',']!r} and {both['.']!r}), and "
            'either may be a thousands mark; give [file] decimal = "." or "," in the channel map'
        )
    integers = integers or {}
    for line, column, cell, _ in marked:
        thousands = thousands_mark_beside_integers(cell) if column in integers else None
        if thousands is not None:
            return ("," if thousands == "." else "."), (
                f"sniffed from column {column + 1}, which holds integers such as "
                f"{integers[column]!r} beside {cell!r} at line {line + 1}: thousands marks "
                f"{thousands!r}"
            )
    # Every marked cell reads both ways (``12,000``: 12000 or 12.0) and nothing above decides:
    # no guess (a decimal comma was guessed, reading counts of 12 000 as 12). The mark stays
    # undecided, and each column's own cells decide it, or its reading is refused naming both
    # (:func:`rollerrig.recordings.translate.as_float`).
    return ".", "the default"


def _at(cell: tuple[int, int, str, frozenset[str]]) -> str:
    line, column, text, _ = cell
    return f"{text!r} at line {line + 1}, column {column + 1}"


def _thousands_columns(
    path: Path,
    rows: list[tuple[int, list[str]]],
    names: list[str],
    decimal: str,
    evidence: str,
    notes: list[str],
) -> list[str]:
    """Names of the columns that write thousands marks (noted, with an example cell).

    Under the decimal mark ``decimal`` the other mark is a thousands mark only in strict groups
    of three digits (:func:`~rollerrig.recordings.formats._text.parse_number`); any other cell
    with it is an error naming the line, the column and the cell.
    """
    other = "," if decimal == "." else "."
    found: dict[int, tuple[int, str]] = {}
    for i, f in rows:
        for j, cell in enumerate(f[: len(names)]):
            c = cell.strip()
            if other not in c or cell_kind(c) == "time" or not MARKED_NUMBER.fullmatch(c):
                continue
            if parse_number(c, decimal) is None:
                raise RecordingError(_not_a_number(path, names[j], c, decimal, evidence, i + 1))
            found.setdefault(j, (i, c))
    for j, (i, c) in found.items():
        notes.append(
            f"column {names[j]!r} writes thousands marks {other!r} (e.g. {c!r} at line {i + 1}, "
            f"read as {parse_number(c, decimal):g}); the decimal mark is {decimal!r} ({evidence})"
        )
    return [names[j] for j in sorted(found)]


def _exact_columns(
    rows: list[tuple[int, list[str]]], names: list[str], decimal: str, thousands: list[str]
) -> list[str]:
    """Names of the columns whose first number is written with a fraction and has a magnitude of
    :data:`~rollerrig.recordings.formats._text.EXACT_ABOVE` or more (a LabVIEW or Unix time in
    seconds since its epoch): pandas would round each to a float64 of 0.24-0.48 µs steps, so
    they are read as text and converted by the time reader exactly, or as any text column."""
    out = []
    for j, name in enumerate(names):
        if name in thousands:
            continue
        first = next((f[j].strip() for _, f in rows if j < len(f) and f[j].strip()), "")
        value = parse_number(first, decimal) if cell_kind(first) == "num" else None
        # with a decimal mark or an exponent (an integer is read exactly by pandas anyway)
        written = decimal in first or "e" in first.lower()
        if value is not None and abs(value) >= EXACT_ABOVE and written:
            out.append(name)
    return out


def _not_a_number(path, column: str, cell: str, decimal: str, evidence: str, line=None) -> str:
    other = "," if decimal == "." else "."
    where = f"line {line}, " if line is not None else ""
    fix = (
        "correct [file] decimal in the channel map"
        if evidence.startswith("given")
        else "give [file] decimal in the channel map"
    )
    return (
        f"{path}: {where}column {column!r}: {cell!r} is not a number with the file's decimal mark "
        f"{decimal!r} ({evidence}), nor one with thousands marks {other!r} in groups of three "
        f"digits; fix the cell or {fix}"
    )


@dataclass(frozen=True)
class GroupedNumbers:
    """Converter of one column's cells that may hold thousands marks (``converters`` of
    :func:`pandas.read_csv`): numbers as floats, empty cells NaN, other text unchanged (NaN
    words, errors named later); a number that fits neither mark is an error naming the cell."""

    path: Path
    column: str
    decimal: str

    def __call__(self, cell: str):
        c = cell.strip()
        if not c:
            return float("nan")
        if not MARKED_NUMBER.fullmatch(c):
            return c
        value = parse_number(c, self.decimal)
        if value is None:
            raise RecordingError(
                _not_a_number(self.path, self.column, c, self.decimal, "of the first rows")
            )
        return value


class _Head(io.RawIOBase):
    """The first ``size`` bytes of the binary file ``fh`` (all of it for None)."""

    def __init__(self, fh, size: int | None):
        self._fh, self._left = fh, size

    def readable(self) -> bool:
        return True

    def readinto(self, buffer) -> int:
        view = memoryview(buffer)
        if self._left is not None:
            view = view[: self._left]
        n = self._fh.readinto(view)
        if self._left is not None:
            self._left -= n
        return n


def nul_padded_end(
    path: Path, block: int = 1 << 16, order: str | None = None
) -> tuple[int, int, bytes] | None:
    """``(end, pad, cut)`` when the file ends in a block of NUL bytes, as a logger that lost
    power leaves it (the file's space allocated and zero-filled after the last line it
    wrote): ``end`` bytes hold its complete lines, ``pad`` NUL bytes end it and ``cut`` is the
    line between them (b"" where the last line before the NUL bytes is complete). None when
    the file does not end in a NUL byte.

    ``order`` (``"utf-16-le"`` / ``"utf-16-be"``): the file is UTF-16, whose characters are
    two bytes from its start: the text ends at the code unit of its last non-NUL byte (the
    zero byte of a last ``0A 00`` is the line end's own), and lines end at the code units
    ``\\n`` / ``\\r``, never at a byte 0A inside another character.
    """
    unit = 1 if order is None else 2
    block -= block % 2
    with path.open("rb") as fh:
        size = fh.seek(0, 2)
        stop = size
        while stop > 0:
            start = max(0, stop - block)
            fh.seek(start)
            chunk = fh.read(stop - start).rstrip(b"\x00")
            if chunk:
                stop = start + len(chunk)
                break
            stop = start
        stop = min(size, stop + (-stop) % unit)  # the whole code unit of the last character
        if stop == size:
            return None
        first = max(0, stop - block)
        fh.seek(first)
        tail = fh.read(stop - first)
    if order is None:
        line_end = max(tail.rfind(b"\n"), tail.rfind(b"\r"))
    else:
        breaks = np.flatnonzero(np.isin(_code_units(tail, order), (10, 13)))  # \n, \r
        line_end = 2 * int(breaks[-1]) + 1 if breaks.size else -1
    if line_end < 0 and stop > block:  # a line longer than a block: the whole tail is cut
        return stop, size - stop, tail
    end = stop - len(tail) + line_end + 1
    return end, size - stop, tail[line_end + 1 :]


def where_named(layout: TextLayout, name: str) -> str:
    """Where the file's head names a column ``name`` on another line than the header the
    layout took (a preamble the sniffer mistook, a header of a vendor's own layout), as a
    hint for an error message: ``[file] header_row`` to give; "" where it does not."""
    try:
        with layout.path.open("rb") as fh:
            head = fh.read(HEAD_BYTES)
        text = head.decode(layout.encoding, errors="replace")
    except (OSError, LookupError):
        return ""
    for i, line in enumerate(re.split(r"\r\n|\r|\n", text)[: layout.data_line + 1]):
        if i == layout.header_line:
            continue
        cells = [c.strip().strip('"') for c in split_cells(line, layout.separator)]
        if name in cells:
            return (
                f"; line {i + 1} of the file names {name!r}: if that is the header, give "
                f"[file] header_row = {i} (and data_row, the first line of numbers, 0-based) "
                "in the channel map"
            )
    return ""
