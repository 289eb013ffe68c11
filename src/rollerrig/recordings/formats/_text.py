"""Cells, lines and bytes of text files: what the CSV and LVM readers share.

- cell kinds (:func:`cell_kind`: empty, number, timestamp, NaN/inf word, text) and the words
  that stand for a missing or infinite sample (:data:`NAN_WORDS`);
- numbers written with a decimal mark and maybe thousands marks (:func:`parse_number`,
  :func:`decimal_marks`): the one place that decides what ``85,928`` or ``86.021`` means;
- :func:`split_cells`: one line into its cells;
- :func:`decode_text`: the bytes of a file as text (the map's ``[file] encoding``, UTF-16 with
  BOM, UTF-8 with or without BOM, else a fallback code page, noted);
- :func:`exact_offsets`: large numbers (absolute times in seconds since an epoch) read
  exactly relative to a whole origin, not first rounded to a float;
- :func:`unique_names`: column names made unique (``name``, ``name.1``, ...);
- :func:`footer_rows`: the lines of text below the numbers at a file's end.
"""

from __future__ import annotations

import codecs
import csv
import re
from collections import Counter
from decimal import Decimal, InvalidOperation
from pathlib import Path

import numpy as np

from rollerrig.recordings.recording import RecordingError

__all__ = [
    "EXACT_ABOVE",
    "INTEGER",
    "NAN_WORDS",
    "NEGATIVE_INFINITY_WORDS",
    "POSITIVE_INFINITY_WORDS",
    "cell_kind",
    "code_unit",
    "datalike",
    "decimal_marks",
    "decode_text",
    "exact_offsets",
    "footer_rows",
    "lead_column",
    "number_kinds",
    "parse_number",
    "sample_in_footer",
    "split_cells",
    "thousands_mark_beside_integers",
    "unique_names",
]

NUMBER = re.compile(r"[+-]?(?:\d+(?:[.,]\d*)?|[.,]\d+)(?:[eE][+-]?\d+)?")
"""A number with a decimal point or comma."""
_DECIMAL = {
    ".": re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"),
    ",": re.compile(r"[+-]?(?:\d+(?:,\d*)?|,\d+)(?:[eE][+-]?\d+)?"),
}
"""A plain number with the decimal mark (key), no thousands marks."""
THOUSANDS = {
    ".": re.compile(r"[+-]?[1-9]\d{0,2}(?:,\d{3})+(?:\.\d+)?"),
    ",": re.compile(r"[+-]?[1-9]\d{0,2}(?:\.\d{3})+(?:,\d+)?"),
}
"""A number with thousands marks under the decimal mark (key): ``85,928`` / ``1,002.13`` with a
decimal point, ``86.021`` / ``1.002,13`` with a decimal comma. Strict grouping: a first group of
1-3 digits not starting with 0, then groups of exactly three digits (Excel's ``#,##0``)."""
GROUP_MARKS = " \u00a0\u202f'\u2019"
"""Thousands marks that are never a decimal mark: a space, a no-break space and a narrow one
(French and ISO 31-0 ``1 500,00``, French Excel writes U+00A0) and apostrophes (Swiss
``1'800.00``)."""
GROUPED = re.compile(r"[+-]?[1-9]\d{0,2}(?:[ \u00a0\u202f'\u2019]\d{3})+(?:[.,]\d+)?")
"""A number in strict groups of three digits split by one of :data:`GROUP_MARKS`."""


def without_group_marks(cell: str) -> str:
    """``cell`` without :data:`GROUP_MARKS` where it is a number in strict groups of three
    (:data:`GROUPED`), else unchanged.

    Examples
    --------
    >>> without_group_marks("1\u00a0500,00"), without_group_marks("1'800.00")
    ('1500,00', '1800.00')
    >>> without_group_marks("12 34"), without_group_marks("Rolle 1")
    ('12 34', 'Rolle 1')
    """
    c = cell.strip()
    if GROUPED.fullmatch(c):
        return c.translate(_NO_GROUP_MARKS)
    return cell


_NO_GROUP_MARKS = str.maketrans("", "", GROUP_MARKS)

MARKED_NUMBER = re.compile(r"[+-]?[\d.,]*\d[\d.,]*(?:[eE][+-]?\d+)?")
"""A cell made of digits and decimal / thousands marks (a number under some reading)."""
_TIMESTAMP = re.compile(
    r"(?:\d{1,4}[./-]\d{1,2}[./-]\d{1,4}(?:[ T]+\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d+)?)?)?"
    r"|\d+:\d{2}:\d{2}(?:[.,]\d+)?)"  # hours of any digits: elapsed 100:00:00.000
    r"(?:\s*(?:Z|[+-]\d{2}:?\d{2}))?"
)
POSITIVE_INFINITY_WORDS = frozenset(
    {"∞", "+∞", "inf", "+inf", "infinity", "+infinity", "1.#inf"}  # 1.#INF: old MS C runtimes
)
"""Cells that stand for +inf (lower case)."""
NEGATIVE_INFINITY_WORDS = frozenset({"-∞", "-inf", "-infinity", "-1.#inf"})
"""Cells that stand for -inf (lower case)."""
NAN_WORDS = frozenset(
    {"nan", "-nan", "+nan", "na", "n/a", "#n/a", "null", "none"}
    # the rest of pandas' default NA strings (Excel's #NA, MSVC's 1.#QNAN): read as NaN there,
    # so one rule says which rows hold no value (footer_rows, the blank rows of the readers)
    | {"#na", "#n/a n/a", "<na>", "1.#ind", "-1.#ind", "1.#qnan", "-1.#qnan"}
    | POSITIVE_INFINITY_WORDS
    | NEGATIVE_INFINITY_WORDS
)
"""Cells that stand for a missing or infinite sample (case-insensitive)."""


def cell_kind(cell: str) -> str:
    """Classify one cell: "empty", "num", "time", "nan" or "text"."""
    c = cell.strip()
    if not c:
        return "empty"
    if NUMBER.fullmatch(c) or GROUPED.fullmatch(c):
        return "num"
    if c.lower() in NAN_WORDS:
        return "nan"
    if _TIMESTAMP.fullmatch(c):
        return "time"
    return "text"


def parse_number(cell: str, decimal: str) -> float | None:
    """The number in ``cell`` when the file's decimal mark is ``decimal``; None when ``cell`` is
    not a number under that mark.

    The other mark is read as a thousands mark only in strict groups of three digits
    (:data:`THOUSANDS`); anything else with the other mark (``0,45`` under ``"."``, ``86.02``
    under ``","``) is not a number under ``decimal``, never a silent decimal point.

    Examples
    --------
    >>> parse_number("85,928", "."), parse_number("86.021", ","), parse_number("-0,45", ",")
    (85928.0, 86021.0, -0.45)
    >>> parse_number("0,45", "."), parse_number("86.02", ","), parse_number("8,5928", ".")
    (None, None, None)
    """
    c = cell.strip()
    if _DECIMAL[decimal].fullmatch(c):
        return float(c.replace(",", "."))
    if THOUSANDS[decimal].fullmatch(c):
        other = "," if decimal == "." else "."
        return float(c.replace(other, "").replace(",", "."))
    return None


def decimal_marks(cell: str) -> frozenset[str]:
    """The decimal marks under which ``cell`` (with a ``.`` or ``,`` in it) is a number.

    Empty for a cell without a mark (an integer, text) or one that no mark makes a number.

    Examples
    --------
    >>> [sorted(decimal_marks(c)) for c in ("85,928", "0,45", "1,002.5")]
    [[',', '.'], [','], ['.']]
    """
    c = cell.strip()
    if ("." not in c and "," not in c) or not MARKED_NUMBER.fullmatch(c):
        return frozenset()
    return frozenset(d for d in ".," if parse_number(c, d) is not None)


INTEGER = re.compile(r"[+-]?\d+")
"""A cell of digits only (no mark)."""


def thousands_mark_beside_integers(cell: str) -> str | None:
    """The thousands mark of ``cell`` when it sits in a column of plain integers, else None.

    A cell that both marks read (``1,000``, ``1.000``) and that ends in 0 beside integers
    (``999``) is an integer with a thousands mark: a writer of fixed decimals writes
    ``999,000``, one of shortest decimals ``1``, neither writes ``999`` and ``1,000``. ``1``
    beside ``1,125`` says nothing (1.125 from a shortest writer, 1125 from a grouping one).

    Examples
    --------
    >>> thousands_mark_beside_integers("1,000"), thousands_mark_beside_integers("1.250")
    (',', '.')
    >>> thousands_mark_beside_integers("1,125") is None, thousands_mark_beside_integers("0,50")
    (True, None)
    """
    c = cell.strip()
    if not c.endswith("0") or len(decimal_marks(c)) != 2:
        return None
    return "," if "," in c else "."


EXACT_ABOVE = 1e8
"""Magnitude from which a number with a fraction is read exactly relative to a whole origin
(:func:`exact_offsets`): absolute times in seconds since an epoch (LabVIEW's 1904, about
3.8e9 s; Unix's 1970, about 1.7e9 s). A float64 steps by 0.24-0.48 µs there, so parsed as
floats a 100 kHz clock read as 99 864 Hz with steps of 9.5 and 10.0 µs."""


def exact_offsets(cells, decimal: str, origin: int | None = None) -> tuple[np.ndarray, int] | None:
    """``(values - origin, origin)`` of a column of number cells, each difference exact to
    the float (:class:`decimal.Decimal`); ``origin`` None: the whole part of the first cell.

    For numbers of :data:`EXACT_ABOVE` and more, whose fraction a float64 rounds. NaN/inf
    words give NaN/inf. None when a cell is not a plain number under the decimal mark
    ``decimal`` (the caller's own parser then names it).

    Examples
    --------
    >>> v, origin = exact_offsets(["3805984573.00001", "3805984573.00002"], ".")
    >>> origin, v.tolist()
    (3805984573, [1e-05, 2e-05])
    """
    out = np.empty(len(cells))
    try:
        for k, cell in enumerate(cells):
            text = str(cell).strip()
            if decimal == ",":
                if "." in text:
                    return None  # under a decimal comma a point is no decimal mark
                text = text.replace(",", ".")
            elif "," in text:
                return None
            number = Decimal(text)
            if origin is None:
                origin = int(number) if number.is_finite() else 0
            out[k] = float(number - origin) if number.is_finite() else float(number)
    except (InvalidOperation, ValueError):
        return None
    return out, 0 if origin is None else origin


def datalike(fields: list[str]) -> bool:
    """Whether a row is one of numbers: no text cell, at least one number or timestamp."""
    kinds = [cell_kind(f) for f in fields]
    return all(k != "text" for k in kinds) and any(k in ("num", "time") for k in kinds)


def split_cells(line: str, sep: str) -> list[str]:
    """The cells of ``line`` (``sep`` ``" "``: any run of whitespace; else CSV quoting)."""
    if sep == " ":
        return line.split()
    return [f.strip() for f in next(csv.reader([line], delimiter=sep, quotechar='"'), [""])]


def code_unit(encoding: str) -> int:
    """Bytes of one code unit of ``encoding`` (any spelling Python's codecs know): 2 for UTF-16,
    4 for UTF-32, else 1 (the encodings where a line end is one byte)."""
    try:
        name = codecs.lookup(encoding).name
    except LookupError:
        return 1
    return 2 if name.startswith("utf-16") else 4 if name.startswith("utf-32") else 1


def decode_text(
    path: Path,
    raw: bytes,
    encoding: str | None,
    notes: list[str],
    *,
    truncated: bool,
    fallback: str,
    fallback_name: str,
    binary_hint: str,
) -> tuple[str, str]:
    """(encoding, text) of the bytes of a text file.

    ``encoding`` (the map's ``[file] encoding``) when given; else UTF-16 when the bytes start
    with its BOM, or look like it without one (ASCII text with NUL bytes between, noted), UTF-8
    (with or without BOM), else ``fallback`` (noted as ``fallback_name``).
    With ``truncated`` (``raw`` is the head of a longer file) a character cut at the end of
    ``raw`` is dropped.

    Raises
    ------
    RecordingError
        Bytes that are not valid text in ``encoding`` (naming the line and ``[file] encoding``),
        a NUL byte without a UTF-16 BOM (a binary file; ``binary_hint`` says what to do).
    """
    if encoding is not None:
        try:
            return encoding, raw.decode(encoding)
        except UnicodeDecodeError as exc:
            if not truncated or exc.start < len(raw) - 4:
                line = raw[: exc.start].count(b"\n") + 1
                raise RecordingError(
                    f"{path}: line {line} is not valid {encoding!r} text ({exc.reason}); "
                    "fix [file] encoding in the channel map"
                ) from None
            return encoding, raw[: exc.start].decode(encoding)
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return "utf-16", raw.decode("utf-16", errors="ignore")
    nul = raw.find(b"\x00")
    bare = bom_less_utf16(raw) if nul >= 0 else None
    if bare is not None:
        notes.append(f"the file is UTF-16 without a byte-order mark; read as {bare.upper()}")
        return bare, raw[: len(raw) - len(raw) % 2].decode(bare, errors="ignore")
    if nul >= 0:
        raise RecordingError(f"{path}: not a text file (a NUL byte at byte {nul}); {binary_hint}")
    try:
        return "utf-8-sig", raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if truncated and exc.start >= len(raw) - 4:
            return "utf-8-sig", raw[: exc.start].decode("utf-8-sig")
    notes.append(f"the file is not UTF-8; read as {fallback_name}")
    return fallback, raw.decode(fallback, errors="replace")


def bom_less_utf16(raw: bytes) -> str | None:
    """``"utf-16-le"`` / ``"utf-16-be"`` when ``raw`` is UTF-16 text without a byte-order mark
    (as some loggers and scripts write it: ASCII text with a NUL byte after, or before, every
    character), else None. Checked on the first 4 KiB: the bytes at the odd (LE) or even (BE)
    offsets NUL (all but 2 %), none at the others, and a line end among them; binary data
    has NUL bytes in both lanes; NUL bytes that end the first 4 KiB (a padded tail) are left
    out of the check."""
    head = raw[:4096]
    if head.endswith(b"\x00\x00"):  # a NUL-padded tail (a logger that lost power) in it
        head = head.rstrip(b"\x00")
        head += b"\x00" * (len(head) % 2)  # the last character's own zero byte (LE)
    head = head[: len(head) - len(head) % 2]
    if len(head) < 8:
        return None
    even, odd = head[0::2], head[1::2]
    for name, zeros, chars in (("utf-16-le", odd, even), ("utf-16-be", even, odd)):
        # a few characters beyond Latin-1 ('Ω', '€') put a byte in the NUL lane
        other = len(zeros) - zeros.count(b"\x00")
        if other <= len(zeros) // 50 and b"\x00" not in chars and b"\n" in chars:
            return name
    return None


def whole_text(
    path: Path, encoding: str | None, notes: list[str], *, fallback: str, fallback_name: str,
    binary_hint: str, end: int | None = None,
) -> str:  # fmt: skip
    """The whole text file ``path`` decoded (:func:`decode_text`; ``encoding`` the map's
    ``[file] encoding``), for the readers of formats with a structure of their own (LabVIEW
    .lvm, TwinCAT Scope exports) that read every line; ``end``: only its first ``end`` bytes
    (a NUL-padded tail left out: :func:`rollerrig.recordings.formats.sniff.text_end`).

    Raises
    ------
    RecordingError
        An empty file (only white space), and what :func:`decode_text` refuses.
    """
    raw = path.read_bytes()
    if end is not None:
        raw = raw[:end]
    if not raw.strip():
        raise RecordingError(f"{path}: the file is empty")
    return decode_text(
        path,
        raw,
        encoding,
        notes,
        truncated=False,
        fallback=fallback,
        fallback_name=fallback_name,
        binary_hint=binary_hint,
    )[1]


def unique_names(names: list[str], repeated: dict | None = None) -> list[str]:
    """``names`` with repeats renamed ``name.1``, ``name.2``, ... (pandas' convention), a
    suffix skipped where the file has a column of that name already.

    ``repeated``, where given, gets each repeated name with the names its columns now have
    (:attr:`rollerrig.recordings.formats.Table.repeated`).

    Examples
    --------
    >>> unique_names(["t", "U", "U", "U"])
    ['t', 'U', 'U.1', 'U.2']
    >>> unique_names(["U", "U.1", "U"])
    ['U', 'U.1', 'U.2']
    """
    seen: Counter = Counter()
    taken = set(names)
    unique = []
    for nm in names:
        seen[nm] += 1
        if seen[nm] == 1:
            unique.append(nm)
            continue
        k = seen[nm] - 1
        while f"{nm}.{k}" in taken:
            k += 1
        seen[nm] = k + 1
        taken.add(f"{nm}.{k}")
        unique.append(f"{nm}.{k}")
    if repeated is not None:
        for nm, new in zip(names, unique, strict=True):
            if names.count(nm) > 1:
                repeated.setdefault(nm, []).append(new)
    return unique


def footer_rows(rows: list[list[str]]) -> int:
    """How many of ``rows`` (a file's last lines, as cells) a footer below the numbers takes,
    from its first line to the end: ``End of measurement``, ``Mean;0,1234``, a statistics
    block (with the blank lines among and after its lines).

    The lead column is the first that the samples hold numbers (or timestamps) in, the time
    column of most files. Walking up from the last row, a row with text and no number in its
    lead column is footer; rows of only empty or NaN cells are passed over (not counted: the
    readers drop them as blank); the first row with a number in its lead column ends the
    footer. So a sample keeps its place whatever text its other columns hold (an event
    column, a stray ``ERR``, which the readers then report). 0 where no sample is found among
    ``rows`` (nothing is known about the file's end).

    Examples
    --------
    >>> rows = [["0.000", "1.5"], ["0.001", "1.6"], ["Mean", "1.55"], ["End of data"]]
    >>> footer_rows(rows), footer_rows(rows[:2]), footer_rows([["ok", "1"], ["ok", "2"]])
    (2, 0, 0)
    >>> footer_rows([["0.000", "1.5"], ["0.001", "ERR"], [""], ["", ""]])
    0
    >>> footer_rows([["0.000", "1.5"], [""], ["End"], ["n/a"], ["Operator", "Smith"], [""]])
    4
    """
    return _footer(rows)[0]


def sample_in_footer(rows: list[list[str]]) -> int | None:
    """The index in ``rows`` of the first footer row (:func:`footer_rows`) laid out as a
    sample: the samples' number of cells, and a lead cell with a digit and no letter that is no
    number or time this reader knows (an elapsed ``100:00:00.000`` had been no time, and the
    rest of the file was dropped as a footer with only a note); None where there is none. A
    footer's words (``Mean;24,5``, ``End of data``, ``***``) are no sample.

    Examples
    --------
    >>> rows = [["0.5", "1"], ["1.0", "2"], ["1.00:00:00", "3"], ["Mean", "2"], ["End"]]
    >>> sample_in_footer(rows), sample_in_footer(rows[:2] + rows[3:])
    (2, None)
    """
    count, n, lead = _footer(rows)
    for i in range(len(rows) - count, len(rows)):
        cells = rows[i]
        if len(cells) != n or lead is None:
            continue
        cell = cells[lead].strip()
        if any(c.isdigit() for c in cell) and not any(c.isalpha() for c in cell):
            return i
    return None


def _footer(rows: list[list[str]]) -> tuple[int, int, int | None]:
    """``(rows of the footer, cells per sample, lead column)`` of :func:`footer_rows`."""
    kinds = [number_kinds(r) for r in rows]
    numbered = [k for k in kinds if any(x in ("num", "time") for x in k)]
    if not numbered:
        return 0, 0, None
    n = Counter(len(k) for k in numbered).most_common(1)[0][0]
    # the rows without text where there are any, else the upper rows (a footer is at the end)
    ref = [k for k in numbered if len(k) == n and "text" not in k]
    if not ref:
        ref = [k for k in numbered if len(k) == n]
        ref = ref[: max(1, len(ref) // 2)]
    lead = lead_column(ref, n)
    if lead is None:
        return 0, n, None
    top = len(kinds)  # the footer's first row
    for i in range(len(kinds) - 1, -1, -1):
        k = kinds[i]
        if "text" not in k:
            if any(x in ("num", "time") for x in k):
                return len(kinds) - top, n, lead  # a sample
            continue  # empty or NaN cells only: no value, in the footer or below it
        if lead < len(k) and k[lead] in ("num", "time"):
            return len(kinds) - top, n, lead  # a sample with text beside its number
        top = i
    return 0, n, lead  # no sample above the text: not a footer


def number_kinds(cells: list[str]) -> list[str]:
    """:func:`cell_kind` of each cell, a number with thousands marks (``1,000.00``, which
    :func:`cell_kind` calls text) a number."""
    return [
        "num" if (k := cell_kind(c)) == "text" and MARKED_NUMBER.fullmatch(c.strip()) else k
        for c in cells
    ]


def lead_column(kinds: list[list[str]], n: int) -> int | None:
    """The first of ``n`` columns that at least 80 % of the rows ``kinds`` (cell kinds, of
    :func:`number_kinds`) hold numbers or timestamps in; None when none does."""
    rows = [k for k in kinds if len(k) == n]
    if not rows:
        return None
    return next(
        (j for j in range(n) if sum(k[j] in ("num", "time") for k in rows) >= 0.8 * len(rows)),
        None,
    )
