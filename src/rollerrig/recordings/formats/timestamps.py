"""Date/time strings in a time column as seconds since the first sample: one format per column.

Text exports of acquisition software write absolute timestamps (``05.08.24 13:46:13,250``,
``2024-08-05T13:46:13.250Z``, ``13:46:13``); :func:`parse_timestamps` decides one format for the
whole column (never a per-row guess) and applies it to every row. Used for any format's time
column that holds strings (:mod:`rollerrig.recordings.translate`).
"""

from __future__ import annotations

import functools
import re
import unicodedata
from collections.abc import Callable

import numpy as np

from rollerrig.recordings.formats._table import require_module
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "looks_like_timestamp",
    "parse_timestamps",
    "suggest_date_format",
    "times_of_day",
]

_DATE_CODES = re.compile(r"%[dmyYjbBaAUWGuVxc]")
"""strftime codes of a date (a format without any is a time of day)."""

_TIME_OF_DAY = r"(?P<H>\d{1,2}):(?P<M>\d{2})(?::(?P<S>\d{2})(?:[.,](?P<f>\d+))?)?"
_ELAPSED_OR_TIME_OF_DAY = r"(?P<H>\d+):(?P<M>\d{2})(?::(?P<S>\d{2})(?:[.,](?P<f>\d+))?)?"
"""A time without a date: hours of any digits (an endurance run's elapsed ``100:00:00.000``
had been no time, the rest of its file dropped as a footer)."""
_TZ = r"(?:\s*(?P<tz>Z|[+-]\d{2}:?\d{2}))?"
_MONTH_NAMES = {
    "English": "january february march april may june july august september october november "
    "december",
    "German": "januar|jänner februar|feber märz april mai juni juli august september oktober "
    "november dezember",
    "French": "janvier février mars avril mai juin juillet août septembre octobre novembre "
    "décembre",
    "Spanish": "enero febrero marzo abril mayo junio julio agosto septiembre|setiembre octubre "
    "noviembre diciembre",
    "Italian": "gennaio febbraio marzo aprile maggio giugno luglio agosto settembre ottobre "
    "novembre dicembre",
    "Dutch": "januari februari maart april mei juni juli augustus september oktober november "
    "december",
    "Portuguese": "janeiro fevereiro março abril maio junho julho agosto setembro outubro "
    "novembro dezembro",
}
"""Month names of the languages whose dates acquisition software writes (Excel, LabVIEW and
Windows loggers in the user's language), January first; ``|`` between a month's names.
Languages in the order a column that several fit is read in (English first, as before)."""
_MONTH_ABBREVIATIONS = {
    "German": {"mrz": 3},  # Excel's and Windows' short German March ("Mär" elsewhere)
    "Dutch": {"mrt": 3},
}
"""Abbreviations that are no prefix of the month's name."""


def _plain(word: str) -> str:
    """``word`` lower case without accents and a final point: ``Déc.`` -> ``dec``."""
    decomposed = unicodedata.normalize("NFKD", word.strip().rstrip(".").lower())
    return "".join(c for c in decomposed if not unicodedata.combining(c))


def _month_words() -> dict[str, dict[str, int]]:
    """Language -> {plain word: month}: each month's names, their prefixes of three letters
    and more that no other month of the language shares (``Dez``, ``déc.``, ``févr.``,
    ``juil.``, ``sept``), and :data:`_MONTH_ABBREVIATIONS`."""
    out: dict[str, dict[str, int]] = {}
    for language, names in _MONTH_NAMES.items():
        owners: dict[str, set[int]] = {}
        for month, spellings in enumerate(names.split(), start=1):
            for name in spellings.split("|"):
                plain = _plain(name)
                for k in range(3, len(plain) + 1):
                    owners.setdefault(plain[:k], set()).add(month)
        words = {w: m.pop() for w, m in owners.items() if len(m) == 1}
        words.update(_MONTH_ABBREVIATIONS.get(language, {}))
        out[language] = words
    return out


_MONTH_WORDS = _month_words()
_SPELLED = {
    language: {
        name[:k]
        for spellings in names.split()
        for name in spellings.split("|")
        for k in range(3, len(name) + 1)
    }
    | _MONTH_ABBREVIATIONS.get(language, {}).keys()
    for language, names in _MONTH_NAMES.items()
}
"""Language -> the beginnings of its month names as it spells them (accents kept)."""


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
    # day, month name, year: 05-Aug-2024 13:46:13.250 (MATLAB's datetime, Oracle, SAS), in
    # the languages of _MONTH_NAMES: 05-Dez-2024, 05 déc. 2024 (a word that is no month's
    # name is no such date: _kind_of)
    "dmony": re.compile(
        r"^(?P<a>\d{1,2})(?P<sep>[-./ ])(?P<mon>[^\W\d_]{3,12}\.?)(?P=sep)"
        rf"(?P<y>\d{{4}}|\d{{2}})(?:[ T:]+{_TIME_OF_DAY})?{_TZ}$"
    ),
    # pandas' Timedelta as text (DataFrame.to_csv): 0 days 23:59:59.750000, -1 days +23:59:59
    "days": re.compile(
        r"^(?P<days>[-+]?\d+) days? \+?(?P<H>\d{1,2}):(?P<M>\d{2}):(?P<S>\d{2})"
        r"(?:[.,](?P<f>\d+))?$"
    ),
    # time of day only: 13:46:13,250; or an elapsed time, hours of any digits: 100:00:00.000
    "tod": re.compile(rf"^{_ELAPSED_OR_TIME_OF_DAY}$"),
}


def _kind_of(cell: str) -> str | None:
    """The key of :data:`_DATE_PATTERNS` that reads ``cell`` (a month name of a language of
    :data:`_MONTH_NAMES` for ``"dmony"``), or None."""
    for kind, pattern in _DATE_PATTERNS.items():
        m = pattern.match(cell)
        if m and (kind != "dmony" or any(_plain(m["mon"]) in w for w in _MONTH_WORDS.values())):
            return kind
    return None


def _languages(words) -> list[str]:
    """The languages of :data:`_MONTH_NAMES` in which every one of ``words`` names a month:
    first those that spell each with its accents (``Mär`` is German, ``déc.`` French, though
    English reads ``mar`` and ``dec``), then in that order."""
    plain = {_plain(w) for w in words}
    fits = [lang for lang, known in _MONTH_WORDS.items() if plain <= known.keys()]
    spelled = {w.strip().rstrip(".").lower() for w in words}
    return sorted(fits, key=lambda lang: not spelled <= _SPELLED[lang])


def _month_language(words, decided: dict | None) -> tuple[str, str]:
    """(language, note) in which the month names ``words`` of one column are read: the first
    of :data:`_MONTH_NAMES` that names a month by each (a column read in chunks: the one the
    first chunk decided, ``decided``). The note says the language where it is not English, and
    where another fits that reads a word as another month. "" where none fits."""
    if decided and "language" in decided:
        return decided["language"], ""
    fits = _languages(words)
    if not fits:
        return "", ""
    language = fits[0]
    if decided is not None:
        decided["language"] = language
    plain = {_plain(w) for w in words}
    other = [
        lang for lang in fits[1:]
        if any(_MONTH_WORDS[lang][w] != _MONTH_WORDS[language][w] for w in plain)
    ]  # fmt: skip
    if other:
        return language, (
            f"; month names AMBIGUOUS: read as {language}, but {', '.join(other)} reads them as "
            "other months"
        )
    if language == "English":
        return language, ""
    also = f" (the same months in {', '.join(fits[1:])})" if len(fits) > 1 else ""
    return language, f"; month names read as {language}{also}"


def _month_numbers(cells, date_format: str, decided: dict | None):
    """``(cells, format, note)`` with the month names of ``cells`` (non-English: ``Dez``,
    ``févr.``) written as numbers and ``%b`` / ``%B`` of ``date_format`` as ``%m``, so that
    they are read without the machine's locale; None where no language of
    :data:`_MONTH_NAMES` names a month by every word of the cells that the format does not
    spell out itself."""
    literal = {_plain(w) for w in _WORD.findall(re.sub(r"%.", " ", date_format))}
    words = {w for c in cells.unique()[:10000] for w in _WORD.findall(c)}
    words = {w for w in words if _plain(w) not in literal}
    language, note = _month_language(words, decided)
    if not language:
        return None
    known = _MONTH_WORDS[language]
    # a format that spells the abbreviation's point ('%d. %b. %Y', .NET's de-DE 'dd. MMM.
    # yyyy') keeps it after the number; else the point goes with the word
    point = "." if re.search(r"%[bB]\.", date_format) else ""

    def number(m: re.Match) -> str:
        word = _plain(m[0])
        if word not in known:
            return m[0]
        return f"{known[word]:02d}" + (point if m[0].endswith(".") else "")

    def numbered(cell: str) -> str:
        return _WORD.sub(number, cell)

    fmt = re.sub(r"%[bB]", "%m", date_format)
    return cells.map(numbered), fmt, note


_WORD = re.compile(r"[^\W\d_]{3,}\.?")
"""A word of letters (a month's name or abbreviation, with its point)."""


_DATELIKE = re.compile(r"\d{1,4}[./-]\d{1,2}[./-]\d{1,4}|\d{1,2}:\d{2}")
"""A date or a time of day somewhere in a cell (also in forms :func:`parse_timestamps` does not
know without ``[file] date_format``: ``08/05/2024 01:46:13 PM``, ``Mon 05.08.2024``)."""
_PLAIN_NUMBER = re.compile(r"[+-]?[\d.,]+(?:[eE][+-]?\d+)?")


def looks_like_timestamp(cell: str) -> bool:
    """Whether a cell looks like a date/time such as ``05.08.24 13:46:13`` (not a plain number).

    Also true for date/time forms that need ``[file] date_format`` (``08/05/2024 01:46:13 PM``):
    :func:`parse_timestamps` then names that key with an example for the cell.
    """
    c = str(cell).strip()
    if _kind_of(c) is not None:
        return True
    return bool(_DATELIKE.search(c)) and not _PLAIN_NUMBER.fullmatch(c)


_SUGGEST = re.compile(
    r"(?P<dmon>\d{1,2}(?P<msep>[-./ ])(?P<dmonname>[A-Za-z]{3,9})(?P=msep)(?P<my>\d{2}|\d{4})\b)"
    r"|(?P<mondy>(?P<mdname>[A-Za-z]{3,9}) \d{1,2}(?P<comma>,?) (?P<mdy>\d{4})\b)"
    r"|(?P<date>(?P<a>\d{1,4})(?P<sep>[./-])(?P<b>\d{1,2})(?P=sep)(?P<y>\d{1,4}))"
    r"|(?P<minsec>\d{1,2}:\d{2}(?P<mark>[.,])\d+)"  # elapsed mm:ss,f (Excel's [mm]:ss,0)
    r"|(?P<time>\d{1,2}:\d{2}(?P<sec>:\d{2}(?P<frac>[.,]\d+)?)?)"
    r"|(?P<ampm>\b(?:AM|PM|am|pm|a\.m\.|p\.m\.)(?![A-Za-z]))"
    r"|(?P<tz>(?<=\d)\s*[+-]\d{2}:?\d{2}\b)"
    r"|(?P<mon>\b(?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]*\b)"
    r"|(?P<day>\b(?:Mon|Tue|Wed|Thu|Fri|Sat|Sun)[a-z]*\b)"
)


def times_of_day(first_cell, date_format: str | None = None) -> bool:
    """Whether a time column whose first cell is ``first_cell`` holds times of day without a
    date (``13:46:13``, or a ``date_format`` without date codes): the readers unwrap them at
    midnight.

    Examples
    --------
    >>> times_of_day("23:59:58.5"), times_of_day("05.08.24 23:59"), times_of_day("1", "%H:%M")
    (True, False, True)
    """
    if date_format is not None:
        return not _DATE_CODES.search(date_format)
    return bool(_DATE_PATTERNS["tod"].match(str(first_cell).strip()))


def suggest_date_format(cell: str) -> str | None:
    """A :func:`time.strptime` format that reads ``cell`` (an example for ``[file]
    date_format``), or None when none is found. Slash dates are taken month-first unless the
    first field exceeds 12, other dates day-first: the user checks the order.

    Examples
    --------
    >>> suggest_date_format("08/05/2024 01:46:13.000000 PM")
    '%m/%d/%Y %I:%M:%S.%f %p'
    >>> suggest_date_format("Mon 05.08.2024 13:46")
    '%a %d.%m.%Y %H:%M'
    >>> suggest_date_format("01:59,5")
    '%M:%S,%f'
    >>> suggest_date_format("05-August-2024 23:59:59.000")
    '%d-%B-%Y %H:%M:%S.%f'
    """
    c = str(cell).strip()
    twelve = bool(re.search(r"\b(?:AM|PM|am|pm)\b", c))
    out: list[str] = []
    pos = 0
    for m in _SUGGEST.finditer(c):
        out.append(c[pos : m.start()].replace("%", "%%"))
        pos = m.end()
        if m.group("dmon"):
            sep, name = m.group("msep"), m.group("dmonname")
            month = "%B" if len(name) > 3 else "%b"
            out.append(f"%d{sep}{month}{sep}{'%Y' if len(m.group('my')) == 4 else '%y'}")
        elif m.group("mondy"):
            month = "%B" if len(m.group("mdname")) > 3 else "%b"
            out.append(f"{month} %d{m.group('comma')} %Y")
        elif m.group("date"):
            a, sep, y = m.group("a"), m.group("sep"), m.group("y")
            year = "%Y" if len(y) == 4 else "%y"
            if len(a) == 4:
                out.append(f"%Y{sep}%m{sep}%d")
            elif sep == "/" and int(a) <= 12:
                out.append(f"%m{sep}%d{sep}{year}")
            else:
                out.append(f"%d{sep}%m{sep}{year}")
        elif m.group("minsec"):
            out.append("%M:%S" + m.group("mark") + "%f")
        elif m.group("time"):
            fmt = ("%I" if twelve else "%H") + ":%M"
            if m.group("sec"):
                fmt += ":%S"
            if m.group("frac"):
                fmt += m.group("frac")[0] + "%f"
            out.append(fmt)
        elif m.group("ampm"):
            out.append("%p")
        elif m.group("tz"):
            out.append(m.group("tz")[: len(m.group("tz")) - len(m.group("tz").lstrip())] + "%z")
        elif m.group("mon"):
            out.append("%B" if len(m.group("mon")) > 3 else "%b")
        else:
            out.append("%A" if len(m.group("day")) > 3 else "%a")
    out.append(c[pos:].replace("%", "%%"))
    fmt = "".join(out)
    if "%" not in fmt or re.search(r"\d", re.sub(r"%.", "", fmt)):
        return None  # no code, or a day, year or count of days copied from the cell
    try:
        import datetime

        datetime.datetime.strptime(c, fmt)
    except ValueError:
        return None
    return fmt


def _date_format_hint(cell: str) -> str:
    """``e.g. '<format>' for <cell>`` to give with ``[file] date_format`` in a message."""
    fmt = suggest_date_format(cell)
    if fmt is None:
        return "e.g. '%d.%m.%Y %H:%M:%S'; codes as Python's time.strptime"
    order = " (check the day/month order)" if "%d" in fmt else ""
    return f"e.g. date_format = {fmt!r} reads {cell!r}{order}; codes as Python's time.strptime"


_DST_MONTHS = (3, 4, 9, 10, 11)
"""Months in which a clock goes forward by an hour somewhere (Europe and North America:
March, April; Chile, New Zealand, Australia, formerly Brazil: September to November)."""


def _check_spring_forward(
    wall: np.ndarray,
    s,
    what: str,
    line_of: Callable[[int], int | None] | None,
    anchors: int = 0,
    first_row: int = 0,
) -> None:
    """RecordingError when local wall-clock times ``wall`` [s since 1970, no offset] step forward
    by one hour (± a sample interval) in a month where daylight saving time may begin: the
    clock went forward, no samples were dropped (read as a gap, the recording had been an hour
    longer).

    The first ``anchors`` rows are no neighbours of the rows after them (the file's first
    sample, put before a part of the column read alone): the steps from them are not checked
    (a part that starts an hour into the recording is no clock step), and row ``anchors`` is
    named as row ``first_row``.
    """
    wall, s = wall[anchors:], s.iloc[anchors:]
    if first_row and line_of is not None:
        line_of = functools.partial(_shifted, line_of, first_row)
    if wall.size < 3:
        return
    steps = np.diff(wall)
    median = float(np.median(steps))
    if not 0.0 < median <= 60.0:
        return
    hits = np.flatnonzero(np.abs(steps - 3600.0) <= median * (1.0 + 1e-6))
    for k in hits.tolist():
        month = int(np.datetime64(int(wall[k]), "s").astype(object).month)
        if month not in _DST_MONTHS:
            continue
        here, there = _row_name(k, line_of, first_row), _row_name(k + 1, line_of, first_row)
        raise RecordingError(
            f"{what}: the time steps forward by {steps[k]:.6g} s between {here} "
            f"{s.iloc[k]!r} and {there} {s.iloc[k + 1]!r} at a median "
            f"interval of {median:.6g} s: local clock times across the start of daylight "
            "saving time (the clock went forward an hour; no samples are missing)? Export the "
            "times in UTC or with their UTC offset (31.03.2024 03:00:00+02:00), or, where the "
            "samples are evenly spaced, give [time] sample_rate_Hz in the channel map instead "
            "of the time column"
        )


def _shifted(line_of: Callable[[int], int | None], by: int, k: int) -> int | None:
    return line_of(k + by)


def _row_name(k: int, line_of: Callable[[int], int | None] | None, first_row: int = 0) -> str:
    line = line_of(k) if line_of is not None else None
    return f"row {k + first_row}" + (f" (file line {line})" if line is not None else "")


def _unwrapped_times_of_day(tod: np.ndarray, first: str) -> tuple[np.ndarray, str]:
    """Seconds since the first sample of times of day [s], unwrapped at midnight, and a note."""
    steps = np.diff(tod)
    wraps = np.concatenate(([0.0], np.cumsum(np.where(steps < -43200.0, 86400.0, 0.0))))
    what = "times of day" if np.max(tod) < 86400.0 else "elapsed times, hours:minutes:seconds"
    note = f"{what} (first {first!r}) converted to seconds since the first sample"
    if wraps[-1]:
        note += f"; {int(wraps[-1] // 86400)} midnight crossing(s) unwrapped"
    t = tod + wraps
    return t - t[0], note


def _fixed_width_times_of_day(s, first: str) -> np.ndarray | None:
    """Seconds of the day of ``hh:mm:ss[.f]`` cells laid out exactly as ``first`` (the same
    width, the separators in the same places, digits elsewhere), from their bytes at once;
    None where any cell differs (the regular expression then reads and names it).

    A million cells took 5 s through pandas' regular expression, and take 0.2 s here: a
    logger's export of an hour at 1 kHz is 3.6 million of them.
    """
    m = _DATE_PATTERNS["tod"].match(first)
    if m is None or m.group("S") is None or not first.isascii():
        return None
    if m.group("f") is not None and len(m.group("f")) > 15:  # beyond int64's digits
        return None
    width = len(first)
    try:
        cells = np.asarray(s.to_numpy(), dtype=f"S{width}")  # longer cells are cut: checked
    except (UnicodeEncodeError, ValueError):
        return None
    if not bool((s.str.len() == width).all()):
        return None
    b = cells.view(np.uint8).reshape(-1, width).astype(np.int64) - ord("0")
    is_digit = np.zeros(width, dtype=bool)
    for g in ("H", "M", "S", "f"):
        if m.group(g) is not None:
            is_digit[slice(*m.span(g))] = True
    template = np.frombuffer(first.encode("ascii"), dtype=np.uint8).astype(np.int64) - ord("0")
    digits = b[:, is_digit]
    if (
        not (b[:, ~is_digit] == template[~is_digit]).all()
        or not ((digits >= 0) & (digits <= 9)).all()
    ):
        return None

    def field(name: str) -> np.ndarray:
        lo, hi = m.span(name)
        return b[:, lo:hi] @ 10 ** np.arange(hi - lo - 1, -1, -1, dtype=np.int64)

    seconds = field("H") * 3600.0 + field("M") * 60.0 + field("S")
    if m.group("f") is not None:
        lo, hi = m.span("f")
        seconds = seconds + field("f") / 10.0 ** (hi - lo)
    return seconds


def _order_by_date_steps(a, b, y, tod, pd) -> bool | None:
    """Whether slash or dash dates whose fields ``a/b`` are all <= 12 are day-first (True) or
    month-first (False), from the rows where the date changes as the time of day ``tod`` [s]
    wraps past midnight: a recording crossing midnight steps its date by one day read the
    right way and by about a month read the other (``01/05/2024 23:59:59`` then
    ``02/05/2024 00:00:00``); None where the date never changes, changes without the clock
    wrapping (a daily logger's dates read both ways), or both readings (or neither) step by
    one day."""
    change = np.flatnonzero((np.diff(a) != 0) | (np.diff(b) != 0) | (np.diff(y) != 0))
    if change.size == 0 or not np.all(tod[change + 1] < tod[change]):
        return None
    rows = np.concatenate((change, change + 1))

    def one_day_steps(day, month) -> bool:
        dates = pd.to_datetime(
            pd.DataFrame({"year": y[rows], "month": month[rows], "day": day[rows]}),
            errors="coerce",
        ).to_numpy()
        if np.isnat(dates).any():
            return False
        days = dates.astype("datetime64[D]").astype(np.int64)
        return bool(np.all(days[change.size :] - days[: change.size] == 1))

    day_first, month_first = one_day_steps(a, b), one_day_steps(b, a)
    return day_first if day_first != month_first else None


def parse_timestamps(
    values,
    *,
    what: str,
    dayfirst: bool | None = None,
    date_format: str | None = None,
    line_of: Callable[[int], int | None] | None = None,
    decided: dict | None = None,
    anchors: int = 0,
    first_row: int = 0,
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
    anchors : int
        For a part of a column read alone: its first ``anchors`` rows are the file's first
        sample (the origin of the seconds), no neighbours of the rows after them; the check for
        a daylight-saving step looks only at the steps after them.
    first_row : int
        Index in the whole column of row ``anchors`` (for that check's message).

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
    pd = require_module("pandas", "date/time columns")
    at = functools.partial(_shifted, line_of, first_row) if line_of and first_row else line_of

    def row(k: int) -> str:
        """Row ``k`` of ``values`` named as in the whole column: a part read alone (a chunk)
        names its rows from ``first_row`` on, its anchors as the file's first rows."""
        return _row_name(k, line_of) if k < anchors else _row_name(k - anchors, at, first_row)

    s = pd.Series(np.asarray(values, dtype=object)).map(
        lambda v: "" if v is None or (isinstance(v, float) and v != v) else str(v).strip()
    )
    if s.empty:
        raise RecordingError(f"{what}: no timestamps")
    empty = (s == "").to_numpy()
    if empty.any():
        k = int(np.flatnonzero(empty)[0])
        raise RecordingError(f"{what}: empty timestamp at {row(k)}")
    if date_format is not None:
        stamps = pd.to_datetime(s, format=date_format, errors="coerce")
        bad = stamps.isna().to_numpy()
        language_note = ""
        if bad.any() and re.search(r"%[bB]", date_format):
            # month names of another language than the locale's (pandas reads %b in
            # English): as numbers, read with %m, whatever the machine's locale
            found = _month_numbers(s, date_format, decided)
            if found is not None:
                numbered, fmt, language_note = found
                again = pd.to_datetime(numbered, format=fmt, errors="coerce")
                if not again.isna().any():
                    stamps, bad = again, again.isna().to_numpy()
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise RecordingError(
                f"{what}: {row(k)} {s.iloc[k]!r} does not match [file] "
                f"date_format {date_format!r} ({int(bad.sum())} row(s) in total)"
            )
        if stamps.dt.tz is None and _DATE_CODES.search(date_format):
            wall = stamps.to_numpy().astype("datetime64[ns]").astype(np.int64) / 1e9
            _check_spring_forward(wall, s, what, line_of, anchors, first_row)
        ns = stamps.to_numpy().astype("datetime64[ns]").astype(np.int64)
        secs = (ns - ns[0]) / 1e9
        note = (
            f"absolute timestamps parsed with [file] date_format {date_format!r}, converted to "
            f"seconds since the first sample ({stamps.iloc[0]}){language_note}"
        )
        if not _DATE_CODES.search(date_format):
            # A time of day without a date ('%H:%M'): unwrapped at midnight, as the times of
            # day this reader recognises itself ('23:59' then '00:00' is a minute later).
            steps = np.diff(secs)
            wraps = np.concatenate(([0.0], np.cumsum(np.where(steps < -43200.0, 86400.0, 0.0))))
            if wraps[-1]:
                note += f"; {int(wraps[-1] // 86400)} midnight crossing(s) unwrapped"
            secs = secs + wraps
        return secs, note
    first = s.iloc[0]
    kind = _kind_of(first)
    if decided and kind is not None and decided.get("kind", kind) != kind:
        kind = decided["kind"]  # rows of another format are named below
    if kind is None:
        raise RecordingError(
            f"{what}: {row(0)} {first!r} is neither a number nor a date/time this "
            f"reader knows; give [file] date_format in the channel map, {_date_format_hint(first)}"
        )
    if decided is not None:
        decided.setdefault("kind", kind)
    fast = _fixed_width_times_of_day(s, first) if kind == "tod" else None
    if fast is not None:
        return _unwrapped_times_of_day(fast, first)
    parts = s.str.extract(_DATE_PATTERNS[kind].pattern)
    nomatch = parts["H" if kind in ("tod", "days") else "a"].isna().to_numpy().copy()
    if "sep" in parts:
        sep0 = parts["sep"].iloc[0]
        nomatch |= (parts["sep"] != sep0).to_numpy()
    if nomatch.any():
        k = int(np.flatnonzero(nomatch)[0])
        raise RecordingError(
            f"{what}: {row(k)} {s.iloc[k]!r} does not have the format of the "
            f"first row {first!r}; give [file] date_format in the channel map, "
            f"{_date_format_hint(s.iloc[k])}"
        )
    tod = np.zeros(len(s))
    if "H" in parts and parts["H"].notna().any():
        has_time = parts["H"].notna().to_numpy()
        if not has_time.all():
            k = int(np.flatnonzero(~has_time)[0])
            raise RecordingError(
                f"{what}: {row(k)} {s.iloc[k]!r} has no time of day, the first row {first!r} has"
            )
        frac = parts["f"].fillna("0")
        tod = (
            parts["H"].astype(int).to_numpy() * 3600.0
            + parts["M"].astype(int).to_numpy() * 60.0
            + parts["S"].fillna("0").astype(int).to_numpy()
            + pd.to_numeric("0." + frac).to_numpy()
        )
    if kind == "tod" and parts["S"].isna().all():
        # 'a:b' alone: minutes and seconds of an elapsed time or hours and minutes of a time of
        # day, 60 times apart; read as hh:mm, a 1 Hz logger's '00:01' was a minute.
        raise RecordingError(
            f"{what}: times such as {first!r} have two fields: minutes:seconds of an elapsed "
            "time, or hours:minutes of a time of day (a factor 60 apart); give [file] "
            'date_format in the channel map: "%M:%S" or "%H:%M"'
        )
    if kind == "tod":
        return _unwrapped_times_of_day(tod, first)
    if kind == "days":
        t = parts["days"].astype(int).to_numpy() * 86400.0 + tod
        return t - t[0], (
            f"elapsed times 'N days hh:mm:ss' (pandas' Timedelta as text, first {first!r}) "
            "converted to seconds since the first sample"
        )
    a = parts["a"].astype(int).to_numpy()
    language_note = ""
    if kind == "dmony":
        language, language_note = _month_language(parts["mon"].unique(), decided)
        known = _MONTH_WORDS.get(language, {})
        b = parts["mon"].map(lambda w: known.get(_plain(w), 0)).to_numpy(dtype=int)
        if not b.all():
            if not language:  # each a month's name, but of two languages: row 0's decides
                language = _languages([parts["mon"].iloc[0]])[0]
                known = _MONTH_WORDS[language]
                b = parts["mon"].map(lambda w: known.get(_plain(w), 0)).to_numpy(dtype=int)
            k = int(np.flatnonzero(b == 0)[0])
            raise RecordingError(
                f"{what}: {row(k)} {s.iloc[k]!r}: its month {parts['mon'].iloc[k]!r}"
                f" is no {language} month's name, as the column's ({s.iloc[0]!r}) are (this "
                f"reader knows {', '.join(_MONTH_NAMES)}, one per column); correct the cell, "
                "or export the dates with month numbers"
            )
    else:
        b = parts["b"].astype(int).to_numpy()
    y = parts["y"].astype(int).to_numpy()
    y = np.where(y < 100, np.where(y < 69, 2000 + y, 1900 + y), y)
    sep = parts["sep"].iloc[0]
    if kind == "ymd":
        day, month, order = a, b, "year-month-day"
    elif kind == "dmony":
        day, month, order = a, b, "day-month name-year"
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
                    f"{what}: dates are day-first at {row(ka)} "
                    f"({s.iloc[ka]!r}) but month-first at {row(kb)} "
                    f"({s.iloc[kb]!r}); give [file] date_format in the channel map"
                )
            if day_a.any():
                first_is_day, order = True, "day-first (a first field > 12)"
            elif day_b.any():
                first_is_day, order = False, "month-first (a second field > 12)"
            elif (by_steps := _order_by_date_steps(a, b, y, tod, pd)) is not None:
                first_is_day = by_steps
                order = (
                    f"{'day' if by_steps else 'month'}-first (every day and month field <= "
                    "12, but the date steps by one day read so, by a month read the other way)"
                )
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
            f"{what}: {row(k)} {s.iloc[k]!r} is not a valid date read {order}; "
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
    if not ("tz" in parts and parts["tz"].notna().any()):
        _check_spring_forward(days * 86400.0 + tod, s, what, line_of, anchors, first_row)
    t = (days - days[0]) * 86400.0 + (tod - tod[0]) - (offset - offset[0])
    start = pd.Timestamp(dates[0]) + pd.Timedelta(seconds=float(tod[0]))
    return t, (
        f"absolute timestamps read {order} (first {first!r} = {start}), converted to seconds "
        f"since the first sample{language_note}"
    )
