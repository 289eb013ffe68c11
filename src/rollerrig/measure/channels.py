"""Channel maps: which column of a DAQ file is which canonical quantity, in which unit.

A channel map is a small TOML file (see ``data/example_channel_map.toml``)::

    [file]                    # optional: how to read the file; every key optional (sniffed)
    separator = ";"           # text files: ",", ";", "\t", " " (whitespace), "|"
    decimal = ","             # "." or ","
    header_row = 3            # 0-based line of the column names (counting every line)
    units_row = 4             # 0-based line of a units row, or false for none
    data_row = 5              # 0-based line where the numbers start
    encoding = "latin-1"      # default: utf-8-sig, falling back to latin-1 (noted)
    dayfirst = true           # 05/08/24 is 5 August (dotted dates are day-first anyway)
    date_format = "%d.%m.%y %H:%M:%S"   # strptime format of a timestamp time column
    group = "Fast"            # TDMS / MDF group the columns default to (MDF: name or index)

    [time]
    column = "Time"           # or: sample_rate_Hz = 250
    unit = "s"                # s, ms, us, ns
    resample_Hz = 1000        # optional: common time base of channels with their own rates

    [channels.torque]
    column = "Torque_Roller"  # TDMS: "Group/Channel"; MDF4: the channel name
    unit = "N.m"
    scale = 1.0               # physical = scale * raw + offset (in `unit`), then -> SI
    offset = 0.0
    optional = true           # missing in the file: a note, not an error

    [extra.motor_current]     # non-canonical channels: explicit unit required
    column = "I_AM"
    unit = "A"

Canonical names and their SI units are :data:`rollerrig.measure.recording.CANONICAL_CHANNELS`.
Units are converted to SI here, at the edge, with the small per-quantity tables
:data:`UNIT_FACTORS` (SI unit -> accepted unit -> factor to SI).
"""

from __future__ import annotations

import codecs
import difflib
import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig.measure.recording import CANONICAL_CHANNELS, RecordingError

__all__ = [
    "DECIMALS",
    "RATE_TOLERANCE",
    "SEPARATORS",
    "TIME_UNITS",
    "UNIT_FACTORS",
    "ChannelMap",
    "ChannelSpec",
    "FileSpec",
    "TimeSpec",
    "default_channel_map",
    "example_channel_map_path",
    "format_unit_header",
    "load_channel_map",
    "normalize_unit",
    "si_factor",
    "split_unit_header",
    "to_si",
]

TIME_UNITS: dict[str, float] = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
"""Accepted time units -> factor to seconds."""

UNIT_FACTORS: dict[str, dict[str, float]] = {
    "N.m": {"N.m": 1.0, "kN.m": 1e3},
    "rad/s": {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0, "Hz": 2.0 * math.pi},
    "1": {"1": 1.0},
    "Pa": {"Pa": 1.0, "kPa": 1e3, "bar": 1e5, "MPa": 1e6},
    "N": {"N": 1.0, "kN": 1e3},
    "m": {"m": 1.0, "mm": 1e-3, "um": 1e-6},
    "s": dict(TIME_UNITS),
}
"""SI unit -> {accepted unit: factor to SI}. For angular speed ``Hz`` means rev/s."""

_ALIASES: dict[str, str] = {
    "Nm": "N.m",
    "N*m": "N.m",
    "N·m": "N.m",
    "N m": "N.m",
    "kNm": "kN.m",
    "kN*m": "kN.m",
    "kN·m": "kN.m",
    "rad/sec": "rad/s",
    "1/min": "rpm",
    "min^-1": "rpm",
    "min-1": "rpm",
    "U/min": "rpm",
    "rev/min": "rpm",
    "rev/s": "Hz",
    "µm": "um",
    "μm": "um",
    "µs": "us",
    "μs": "us",
    "Newtons": "N",
    "counts": "1",
    "count": "1",
    "-": "1",
    "sec": "s",
}

_HEADER = re.compile(r"^\s*(?P<name>.*?)\s*[\[(](?P<unit>[^\[\]()]*)[\])]\s*$")


def normalize_unit(unit: str) -> str:
    """The spelling of ``unit`` used in :data:`UNIT_FACTORS` (``"Nm"`` -> ``"N.m"``, ...).

    Examples
    --------
    >>> normalize_unit(" Nm "), normalize_unit("1/min"), normalize_unit("µm")
    ('N.m', 'rpm', 'um')
    """
    u = str(unit).strip()
    return _ALIASES.get(u, u)


def si_factor(unit: str, si_unit: str, *, what: str = "") -> float:
    """Factor that converts values in ``unit`` into ``si_unit``.

    Parameters
    ----------
    unit : str
        Unit the values are in, e.g. ``"rpm"``.
    si_unit : str
        Target SI unit, a key of :data:`UNIT_FACTORS`, e.g. ``"rad/s"``.
    what : str
        Where the unit came from, for the error message.

    Raises
    ------
    RecordingError
        When ``unit`` is not a known unit of that quantity (the message lists the allowed units).

    Examples
    --------
    >>> round(si_factor("rpm", "rad/s"), 6), si_factor("bar", "Pa")
    (0.10472, 100000.0)
    """
    table = UNIT_FACTORS.get(si_unit)
    if table is None:
        raise RecordingError(f"{what}no unit table for SI unit {si_unit!r}")
    u = normalize_unit(unit)
    if u not in table:
        raise RecordingError(
            f"{what}unit {unit!r} is not a unit of this quantity (SI unit {si_unit!r}); "
            f"allowed: {sorted(table)}"
        )
    return table[u]


def to_si(values, unit: str, si_unit: str) -> np.ndarray:
    """``values`` in ``unit`` converted to ``si_unit`` (a float array).

    Examples
    --------
    >>> to_si([60.0], "rpm", "rad/s").round(6).tolist(), to_si([2.0], "kN", "N").tolist()
    ([6.283185], [2000.0])
    """
    return np.asarray(values, dtype=float) * si_factor(unit, si_unit)


def _extra_si(unit: str) -> tuple[str, float]:
    """(SI unit, factor) for a non-canonical channel: prefixed units convert, others stay."""
    u = normalize_unit(unit)
    if u == "Hz":  # a frequency, not a rotation speed, for a channel of unknown meaning
        return u, 1.0
    for si, table in UNIT_FACTORS.items():
        if u in table:
            return si, table[u]
    return u, 1.0


def split_unit_header(header: str) -> tuple[str, str | None]:
    """Split a column header ``"torque [N.m]"`` (or ``"torque (N.m)"``) into name and unit.

    Examples
    --------
    >>> split_unit_header("torque [N.m]"), split_unit_header("Time")
    (('torque', 'N.m'), ('Time', None))
    """
    m = _HEADER.match(str(header))
    if m and m.group("name"):
        return m.group("name"), m.group("unit").strip() or None
    return str(header).strip(), None


def format_unit_header(name: str, unit: str) -> str:
    """Column header with the unit in brackets, e.g. ``"torque [N.m]"``."""
    return f"{name} [{unit}]"


@dataclass(frozen=True)
class TimeSpec:
    """Where the time of a file comes from.

    Parameters
    ----------
    column : str or None
        Time column (TDMS ``"Group/Channel"``); None when time is implied.
    unit : str
        A key of :data:`TIME_UNITS` (time column only; timestamps need none).
    sample_rate_Hz : float or None
        Sampling rate [Hz] for files without a time column (time starts at 0 s). A file whose
        own rate contradicts it by more than :data:`RATE_TOLERANCE` is an error.
    resample_Hz : float or None
        Common time base [Hz] for channels recorded at different rates (None: the reader's
        default, see :mod:`rollerrig.measure.timebase`).
    unit_stated : bool
        Whether the map gave ``unit``; when not, a time unit stored in the file (header
        ``[ms]``, units row ``(ms)``) is used instead of the default seconds.
    """

    column: str | None = None
    unit: str = "s"
    sample_rate_Hz: float | None = None
    resample_Hz: float | None = None
    unit_stated: bool = True


@dataclass(frozen=True)
class ChannelSpec:
    """One channel of a channel map.

    Parameters
    ----------
    name : str
        Name in the recording (canonical, or any name for extras).
    column : str
        Column / channel name in the file.
    unit : str or None
        Unit of ``scale * raw + offset``; None: take the unit stored in the file.
    scale, offset : float
        Linear calibration, physical = scale * raw + offset [unit].
    canonical : bool
        Whether ``name`` is one of :data:`CANONICAL_CHANNELS`.
    optional : bool
        A column missing from the file is noted, not an error (unless the caller needs it).
    """

    name: str
    column: str
    unit: str | None = None
    scale: float = 1.0
    offset: float = 0.0
    canonical: bool = True
    optional: bool = False

    @property
    def entry(self) -> str:
        """The TOML table of this entry, e.g. ``[channels.torque]``."""
        return f"[{'channels' if self.canonical else 'extra'}.{self.name}]"

    @property
    def si_unit(self) -> str | None:
        """SI unit of the channel in the recording (None until the unit is known)."""
        if self.canonical:
            return CANONICAL_CHANNELS[self.name][0]
        return None if self.unit is None else _extra_si(self.unit)[0]

    def conversion(self, unit: str | None = None) -> tuple[str, float]:
        """(SI unit, factor) for values in ``unit`` (default: this entry's unit)."""
        u = self.unit if unit is None else unit
        if u is None:
            raise RecordingError(f"channel map entry {self.entry}: no unit given")
        if self.canonical:
            si = CANONICAL_CHANNELS[self.name][0]
            return si, si_factor(u, si, what=f"channel map entry {self.entry}: ")
        return _extra_si(u)


SEPARATORS: dict[str, str] = {
    ",": "comma",
    ";": "semicolon",
    "\t": "tab",
    " ": "whitespace: any run of spaces or tabs",
    "|": "pipe",
}
"""Column separators of text files accepted in ``[file] separator``."""

DECIMALS: tuple[str, ...] = (".", ",")
"""Decimal marks accepted in ``[file] decimal``."""

RATE_TOLERANCE = 1e-3
"""Relative difference above which a stated sample rate contradicts the file's (0.1 %)."""


@dataclass(frozen=True)
class FileSpec:
    """How to read a file: the ``[file]`` section of a channel map. None: sniffed.

    Parameters
    ----------
    separator : str or None
        Column separator of a text file, a key of :data:`SEPARATORS` (``" "``: any run of
        whitespace).
    decimal : str or None
        Decimal mark of a text file, ``"."`` or ``","``.
    header_row : int or None
        0-based line index of the column names, counting every line of the file (preamble and
        blank lines included).
    units_row : int, False or None
        0-based line index of a units row (e.g. ``s;N.m;1/min`` under the header); False: the file
        has none; None: detected (a non-numeric row between the header and the numbers whose
        cells look like units).
    data_row : int or None
        0-based line index of the first row of numbers (default: the first non-blank line after
        the header / units row).
    encoding : str or None
        Text encoding (default: UTF-8 with or without BOM, falling back to Latin-1, noted).
    dayfirst : bool or None
        Whether slash dates (``05/08/24``) are day-first. Dotted dates (``05.08.24``) are
        day-first by convention; ISO dates (``2024-08-05``) are year-month-day.
    date_format : str or None
        :func:`time.strptime` format of a timestamp time column (beats ``dayfirst``).
    group : str, int or None
        TDMS / MDF group that channel names default to (MDF: the group's name or index).
    """

    separator: str | None = None
    decimal: str | None = None
    header_row: int | None = None
    units_row: int | bool | None = None
    data_row: int | None = None
    encoding: str | None = None
    dayfirst: bool | None = None
    date_format: str | None = None
    group: str | int | None = None

    def to_dict(self) -> dict[str, Any]:
        """The keys that are set (for provenance)."""
        return {
            k: getattr(self, k) for k in self.__dataclass_fields__ if getattr(self, k) is not None
        }


@dataclass(frozen=True)
class ChannelMap:
    """Validated translation from a file's columns to canonical channels in SI units.

    Parameters
    ----------
    time : TimeSpec or None
        Where time comes from; None: from the file's own time base (TDMS waveform properties,
        MDF4 master channel, LVM X column).
    channels : tuple of ChannelSpec
        Canonical channels.
    extra : tuple of ChannelSpec
        Non-canonical channels, each with an explicit unit.
    source : str
        Where the map came from (a path, ``"<dict>"`` or ``"<default>"``).
    auto : bool
        True for :func:`default_channel_map`: every column whose name (without a ``[unit]``
        suffix) is canonical is read, others are kept as extras when their unit is known.
    file : FileSpec
        How to read the file (``[file]``: text dialect, rows, dates, group); default: sniffed.

    Examples
    --------
    >>> cmap = ChannelMap.from_dict({"time": {"column": "t", "unit": "ms"},
    ...                              "channels": {"torque": {"column": "T", "unit": "kN.m"}}})
    >>> cmap.channels[0].conversion()
    ('N.m', 1000.0)
    """

    time: TimeSpec | None = None
    channels: tuple[ChannelSpec, ...] = ()
    extra: tuple[ChannelSpec, ...] = ()
    source: str = "<dict>"
    auto: bool = False
    file: FileSpec = FileSpec()

    @property
    def entries(self) -> tuple[ChannelSpec, ...]:
        """Canonical channels followed by extras."""
        return self.channels + self.extra

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, source: str = "<dict>") -> ChannelMap:
        """Build and validate a map from the structure of the TOML file.

        Raises
        ------
        RecordingError
            Unknown key, unknown canonical name (with close matches), unit not valid for the
            quantity, missing column, non-finite or zero scale.
        """
        where = f"channel map {source}: "
        if not isinstance(data, Mapping):
            raise RecordingError(f"{where}expected a table, got {type(data).__name__}")
        _check_keys(data, {"file", "time", "channels", "extra", "description", "name"}, where)
        file = _parse_file(data.get("file"), where)
        time = _parse_time(data.get("time"), where)
        channels = []
        for name, entry in _table(data.get("channels", {}), f"{where}[channels]: ").items():
            if name not in CANONICAL_CHANNELS:
                close = difflib.get_close_matches(name, list(CANONICAL_CHANNELS), n=3)
                raise RecordingError(
                    f"{where}[channels.{name}]: {name!r} is not a canonical channel name"
                    f"{f' (did you mean {close}?)' if close else ''}; canonical names: "
                    f"{list(CANONICAL_CHANNELS)}; put other channels under [extra.{name}] "
                    "with an explicit unit"
                )
            channels.append(_parse_entry(name, entry, where, canonical=True))
        extra = []
        for name, entry in _table(data.get("extra", {}), f"{where}[extra]: ").items():
            if name in CANONICAL_CHANNELS:
                raise RecordingError(
                    f"{where}[extra.{name}]: {name!r} is canonical; put it under [channels.{name}]"
                )
            if not isinstance(entry, Mapping) or "unit" not in entry:
                raise RecordingError(f"{where}[extra.{name}]: an explicit 'unit' is required")
            extra.append(_parse_entry(name, entry, where, canonical=False))
        if not channels and not extra:
            raise RecordingError(f"{where}maps no channels ([channels.<name>] or [extra.<name>])")
        return cls(
            time=time, channels=tuple(channels), extra=tuple(extra), source=source, file=file
        )

    def to_dict(self) -> dict[str, Any]:
        """The map in the structure of the TOML file (for provenance)."""
        out: dict[str, Any] = {}
        if self.auto:
            out["auto"] = True
        file = self.file.to_dict()
        if file:
            out["file"] = file
        if self.time is not None:
            t: dict[str, Any] = {}
            if self.time.column is not None:
                t["column"] = self.time.column
                if self.time.unit_stated:
                    t["unit"] = self.time.unit
            if self.time.sample_rate_Hz is not None:
                t["sample_rate_Hz"] = self.time.sample_rate_Hz
            if self.time.resample_Hz is not None:
                t["resample_Hz"] = self.time.resample_Hz
            out["time"] = t
        for key, specs in (("channels", self.channels), ("extra", self.extra)):
            if specs:
                out[key] = {
                    s.name: {
                        "column": s.column,
                        **({"unit": s.unit} if s.unit is not None else {}),
                        "scale": s.scale,
                        "offset": s.offset,
                        **({"optional": True} if s.optional else {}),
                    }
                    for s in specs
                }
        out["source"] = self.source
        return out


def _check_keys(data: Mapping, allowed: set[str], where: str) -> None:
    unknown = [k for k in data if k not in allowed]
    if unknown:
        hints = {k: difflib.get_close_matches(k, sorted(allowed), n=1) for k in unknown}
        hint = "; ".join(f"{k!r} -> did you mean {v[0]!r}?" for k, v in hints.items() if v)
        raise RecordingError(
            f"{where}unknown key(s) {unknown}; allowed: {sorted(allowed)}"
            + (f" ({hint})" if hint else "")
        )


def _table(value: Any, where: str) -> Mapping:
    if not isinstance(value, Mapping):
        raise RecordingError(f"{where}expected a table, got {value!r}")
    return value


def _number(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise RecordingError(f"{what} must be a number, got {value!r}")
    if not math.isfinite(value):
        raise RecordingError(f"{what} must be finite, got {value!r}")
    return float(value)


def _parse_time(value: Any, where: str) -> TimeSpec | None:
    if value is None:
        return None
    t = _table(value, f"{where}[time]: ")
    _check_keys(t, {"column", "unit", "sample_rate_Hz", "resample_Hz"}, f"{where}[time]: ")
    column = t.get("column")
    rate = t.get("sample_rate_Hz")
    if column is not None and rate is not None:
        raise RecordingError(f"{where}[time]: give either 'column' or 'sample_rate_Hz', not both")
    if column is not None and (not isinstance(column, str) or not column):
        raise RecordingError(f"{where}[time]: 'column' must be a non-empty string")
    unit = t.get("unit", "s")
    if not isinstance(unit, str) or normalize_unit(unit) not in TIME_UNITS:
        raise RecordingError(
            f"{where}[time]: unit {unit!r} is not a time unit; allowed: {sorted(TIME_UNITS)}"
        )
    if rate is not None:
        rate = _number(rate, f"{where}[time]: sample_rate_Hz [Hz]")
        if rate <= 0:
            raise RecordingError(f"{where}[time]: sample_rate_Hz must be > 0 Hz, got {rate}")
    resample = t.get("resample_Hz")
    if resample is not None:
        resample = _number(resample, f"{where}time.resample_Hz [Hz]")
        if resample <= 0:
            raise RecordingError(f"{where}time.resample_Hz must be > 0 Hz, got {resample}")
    return TimeSpec(
        column=column,
        unit=normalize_unit(unit),
        sample_rate_Hz=rate,
        resample_Hz=resample,
        unit_stated="unit" in t,
    )


def _row(value: Any, key: str, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise RecordingError(
            f"{where}file.{key} must be a 0-based line index (an integer >= 0), got {value!r}"
        )
    return value


def _parse_file(value: Any, where: str) -> FileSpec:
    if value is None:
        return FileSpec()
    f = _table(value, f"{where}[file]: ")
    _check_keys(f, set(FileSpec.__dataclass_fields__), f"{where}[file]: ")
    sep = f.get("separator")
    if sep is not None and sep not in SEPARATORS:
        raise RecordingError(
            f"{where}file.separator = {sep!r} is not allowed; allowed: "
            + ", ".join(f"{k!r} ({v})" for k, v in SEPARATORS.items())
        )
    decimal = f.get("decimal")
    if decimal is not None and decimal not in DECIMALS:
        raise RecordingError(
            f"{where}file.decimal = {decimal!r} is not allowed; allowed: {list(DECIMALS)}"
        )
    if sep is not None and decimal is not None and sep == decimal:
        raise RecordingError(f"{where}file.separator and file.decimal are both {sep!r}")
    header = None if f.get("header_row") is None else _row(f["header_row"], "header_row", where)
    units = f.get("units_row")
    if units is True:
        raise RecordingError(
            f"{where}file.units_row must be a 0-based line index or false, got true"
        )
    if units is not None and units is not False:
        units = _row(units, "units_row", where)
    data = None if f.get("data_row") is None else _row(f["data_row"], "data_row", where)
    if isinstance(units, int) and not isinstance(units, bool):
        if header is not None and units <= header:
            raise RecordingError(
                f"{where}file.units_row = {units} must come after file.header_row = {header}"
            )
    last = max([r for r in (header, units) if isinstance(r, int) and r is not False] or [-1])
    if data is not None and data <= last:
        raise RecordingError(
            f"{where}file.data_row = {data} must come after the header / units rows ({last})"
        )
    encoding = f.get("encoding")
    if encoding is not None:
        if not isinstance(encoding, str):
            raise RecordingError(f"{where}file.encoding must be a string, got {encoding!r}")
        try:
            codecs.lookup(encoding)
        except LookupError:
            raise RecordingError(
                f"{where}file.encoding = {encoding!r} is not a known text encoding; e.g. "
                "'utf-8', 'utf-8-sig', 'latin-1', 'cp1252', 'utf-16'"
            ) from None
    dayfirst = f.get("dayfirst")
    if dayfirst is not None and not isinstance(dayfirst, bool):
        raise RecordingError(f"{where}file.dayfirst must be true or false, got {dayfirst!r}")
    fmt = f.get("date_format")
    if fmt is not None and (not isinstance(fmt, str) or "%" not in fmt):
        raise RecordingError(
            f"{where}file.date_format must be a strptime format such as "
            f"'%d.%m.%y %H:%M:%S', got {fmt!r}"
        )
    group = f.get("group")
    if group is not None and (
        isinstance(group, bool)
        or not isinstance(group, str | int)
        or (isinstance(group, str) and not group)
        or (isinstance(group, int) and group < 0)
    ):
        raise RecordingError(
            f"{where}file.group must be a group name or a 0-based group index, got {group!r}"
        )
    return FileSpec(
        separator=sep,
        decimal=decimal,
        header_row=header,
        units_row=units,
        data_row=data,
        encoding=encoding,
        dayfirst=dayfirst,
        date_format=fmt,
        group=group,
    )


def _parse_entry(name: str, entry: Any, where: str, *, canonical: bool) -> ChannelSpec:
    table = "channels" if canonical else "extra"
    here = f"{where}[{table}.{name}]: "
    e = _table(entry, here)
    _check_keys(e, {"column", "unit", "scale", "offset", "description", "optional"}, here)
    column = e.get("column")
    if not isinstance(column, str) or not column:
        raise RecordingError(f"{here}'column' (the file's column / channel name) is required")
    unit = e.get("unit")
    if unit is not None and (not isinstance(unit, str) or not unit.strip()):
        raise RecordingError(f"{here}'unit' must be a non-empty string, got {unit!r}")
    scale = _number(e.get("scale", 1.0), f"{here}scale")
    if scale == 0.0:
        raise RecordingError(f"{here}scale must be non-zero")
    offset = _number(e.get("offset", 0.0), f"{here}offset")
    optional = e.get("optional", False)
    if not isinstance(optional, bool):
        raise RecordingError(f"{here}'optional' must be true or false, got {optional!r}")
    spec = ChannelSpec(name, column, unit, scale, offset, canonical, optional)
    if unit is not None:
        try:
            spec.conversion()  # raises for a unit that does not fit the quantity
        except RecordingError as exc:
            raise RecordingError(f"{where}{exc}") from None
    return spec


def load_channel_map(path: str | Path) -> ChannelMap:
    """Read and validate a channel map TOML file.

    Parameters
    ----------
    path : str or path-like
        The TOML file.

    Raises
    ------
    FileNotFoundError
        When the file does not exist.
    RecordingError
        When the file is not valid TOML or not a valid channel map.

    Examples
    --------
    >>> cmap = load_channel_map(example_channel_map_path())
    >>> [c.name for c in cmap.channels][:2]
    ['torque', 'roller_speed']
    """
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"channel map file not found: {p}")
    try:
        with p.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise RecordingError(f"channel map {p}: not valid TOML: {exc}") from exc
    return ChannelMap.from_dict(data, source=str(p))


def default_channel_map() -> ChannelMap:
    """The map for files written by rollerrig: canonical names as columns, units in the file.

    The time is the column ``time`` (unit from its header, seconds by default) or the file's
    own time base; every column whose name is canonical is read with the unit given in its
    header (``torque [N.m]``) or stored in the file (TDMS ``unit_string``, MDF4 unit, Parquet
    field metadata); other columns with a unit are kept as extras.

    Examples
    --------
    >>> default_channel_map().auto
    True
    """
    return ChannelMap(time=TimeSpec(column="time", unit="s"), source="<default>", auto=True)


def example_channel_map_path() -> Path:
    """Path of the bundled example channel map (``data/example_channel_map.toml``)."""
    return Path(str(resources.files("rollerrig.measure") / "data" / "example_channel_map.toml"))
