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
    sheet = "Data"            # Excel workbook: the sheet to read (name or 0-based index)

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

Canonical names and their SI units are :data:`rollerrig.recordings.recording.CANONICAL_CHANNELS`.
Units are converted to SI here, at the edge, through the package's one unit registry
(:mod:`rollerrig.units`). The map file is validated with pydantic (its form:
:mod:`rollerrig.recordings.mapfile`) and reported in the package's one error format
(:mod:`rollerrig._validation`), every problem at once::

    channel map bench.toml: channels.torque.unit: unit not accepted for torque [N.m]; allowed
    'N.m', 'kN.m' (also written 'Nm', 'kNm'); got 'bar'
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from rollerrig._toml import read_toml
from rollerrig._validation import Problem, did_you_mean, pydantic_problems
from rollerrig.recordings.mapfile import DECIMALS, SEPARATORS, EntrySection, FileSpec, MapFile
from rollerrig.recordings.recording import CANONICAL_CHANNELS, RecordingError, RecordingFileNotFound
from rollerrig.units import (
    ALIASES,
    QUANTITIES,
    UNITS_BY_SI,
    UnitError,
    labelled,
    normalize_unit,
    si_factor,
)

__all__ = [
    "DECIMALS",
    "RATE_TOLERANCE",
    "SEPARATORS",
    "TIME_NAMES",
    "TIME_UNITS",
    "TIME_WORDS",
    "UNIT_FACTORS",
    "ChannelMap",
    "ChannelSpec",
    "FileSpec",
    "TimeSpec",
    "default_channel_map",
    "example_channel_map_path",
    "format_unit_header",
    "load_channel_map",
    "split_unit_header",
    "time_named",
    "time_unit",
]

TIME_UNITS: Mapping[str, float] = QUANTITIES["time"].units
"""Accepted time units -> factor to seconds (a view of :data:`rollerrig.units.QUANTITIES`)."""

_TIME_CASELESS = {
    spelling.lower(): unit
    for spelling, unit in [*((u, u) for u in TIME_UNITS), *ALIASES.items()]
    if unit in TIME_UNITS
}


def time_unit(unit: str) -> str | None:
    """The key of :data:`TIME_UNITS` that a time column's unit means, or None.

    Any spelling :func:`~rollerrig.units.normalize_unit` reads, and in a time column in any
    letter case (``mS``, ``MSEC``, ``Sec`` are milliseconds and seconds there, whatever the
    same letters mean in a channel of another quantity).

    Examples
    --------
    >>> time_unit("mS"), time_unit("msec"), time_unit("[min]".strip("[]")), time_unit("V")
    ('ms', 'ms', 'min', None)
    """
    u = normalize_unit(unit)
    if u in TIME_UNITS:
        return u
    return _TIME_CASELESS.get(u.lower()) or _TIME_CASELESS.get(str(unit).strip().lower())


TIME_NAMES = frozenset(
    {"time", "zeit", "t", "x_value", "timestamp", "timestamps", "time_s", "time_ms", "datetime"}
)
"""Column names (lower case, unit stripped) taken as a time column when checking a stated rate."""

TIME_WORDS = frozenset(
    {"time", "zeit", "temps", "tiempo", "tempo", "timestamp", "zeitstempel", "horodatage"}
)
"""Words that make a longer column name a time's: catman's ``Zeit  1 - Standardmessrate``,
``Relative Time``, ``Temps relatif``."""


def time_named(base: str) -> bool:
    """Whether a column's name (lower case, unit stripped) is a time column's:
    :data:`TIME_NAMES`, or a name holding one of :data:`TIME_WORDS` as a word."""
    return base in TIME_NAMES or not TIME_WORDS.isdisjoint(re.split(r"[\W_\d]+", base))


UNIT_FACTORS: Mapping[str, Mapping[str, float]] = UNITS_BY_SI
"""SI unit -> {accepted unit: factor to SI} (:data:`rollerrig.units.UNITS_BY_SI`). For angular
speed ``Hz`` means rev/s."""

# A unit in brackets may hold parentheses (``Druck [bar(g)]``); one in parentheses may not.
_HEADER = re.compile(
    r"^\s*(?P<name>.*?)\s*(?:\[(?P<unit>[^\[\]]*)\]|\((?P<paren>[^\[\]()]*)\))\s*$"
)


def _extra_si(unit: str) -> tuple[str, float]:
    """(SI unit, factor) for a non-canonical channel: prefixed units convert, others stay."""
    u = normalize_unit(unit)
    if u == "Hz":  # a frequency, not a rotation speed, for a channel of unknown meaning
        return u, 1.0
    for si, table in UNITS_BY_SI.items():
        if u in table:
            return si, table[u]
    return u, 1.0


def split_unit_header(header: str) -> tuple[str, str | None]:
    """Split a column header ``"torque [N.m]"`` (or ``"torque (N.m)"``) into name and unit.

    Examples
    --------
    >>> split_unit_header("torque [N.m]"), split_unit_header("Time")
    (('torque', 'N.m'), ('Time', None))
    >>> split_unit_header("Druck [bar(g)]"), split_unit_header("Drehzahl (1/min)")
    (('Druck', 'bar(g)'), ('Drehzahl', '1/min'))
    """
    m = _HEADER.match(str(header))
    if m and m.group("name"):
        unit = m.group("unit") if m.group("unit") is not None else m.group("paren")
        return m.group("name"), unit.strip() or None
    return str(header).strip(), None


def format_unit_header(name: str, unit: str) -> str:
    """Column header with the unit in brackets, e.g. ``"torque [N.m]"``, ``"coa [-]"``
    (:func:`rollerrig.units.labelled`)."""
    return labelled(name, unit)


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
        default, see :mod:`rollerrig.recordings.timebase`).
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
            try:
                return si, si_factor(u, si, what=f"channel map entry {self.entry}: ")
            except UnitError as exc:
                raise RecordingError(str(exc)) from None
        return _extra_si(u)


RATE_TOLERANCE = 1e-3
"""Relative difference above which a stated sample rate contradicts the file's (0.1 %)."""


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
    file: FileSpec = field(default_factory=FileSpec)

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
            Every problem of the map, one line each in the package's error format
            (``channel map <source>: <dotted key>: <what> [<unit>]; allowed ...; got ...``):
            unknown key (with close matches), unknown canonical name, unit not accepted for
            the quantity, missing column, non-finite or zero scale, ...
        """
        where = f"channel map {source}"
        try:
            form = MapFile.model_validate(data)
        except ValidationError as exc:
            raise _map_error(where, pydantic_problems(exc, model=MapFile)) from None
        channels = [_spec(name, entry, True) for name, entry in form.channels.items()]
        extra = [_spec(name, entry, False) for name, entry in form.extra.items()]
        # A map of only [file] or [time] settings (the decimal mark, the time's unit): the
        # default mapping by canonical column names with those settings. The reader's own
        # errors ask for exactly such a map ("give [file] decimal = ..."), which was refused
        # as "maps no channels".
        settings_only = not channels and not extra and (form.file or form.time) is not None
        problems = [] if settings_only else _entry_problems(channels, extra)
        if problems:
            raise _map_error(where, problems)
        time = None
        if form.time is not None:
            t = form.time
            time = TimeSpec(
                column=t.column,
                unit=normalize_unit(t.unit),
                sample_rate_Hz=t.sample_rate_Hz,
                resample_Hz=t.resample_Hz,
                unit_stated="unit" in t.model_fields_set,
            )
        if settings_only:
            default = default_channel_map().time
            if time is None:
                time = default
            elif time.column is None and time.sample_rate_Hz is None:
                time = replace(time, column=default.column)
        return cls(
            time=time,
            channels=tuple(channels),
            extra=tuple(extra),
            source=source,
            file=form.file or FileSpec(),
            auto=settings_only,
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


def _spec(name: str, entry: EntrySection, canonical: bool) -> ChannelSpec:
    return ChannelSpec(
        name, entry.column, entry.unit, entry.scale, entry.offset, canonical, entry.optional
    )


def _entry_problems(channels: list[ChannelSpec], extra: list[ChannelSpec]) -> list[Problem]:
    """What pydantic cannot see: canonical names, units that fit them, extras with units."""
    problems: list[Problem] = []
    names = list(CANONICAL_CHANNELS)
    for spec in channels:
        key = f"channels.{spec.name}"
        if spec.name not in CANONICAL_CHANNELS:
            hint = did_you_mean(spec.name, names, n=3)
            problems.append(
                Problem(
                    key,
                    f"{spec.name!r} is not a canonical channel name{hint}; put other channels "
                    f"under [extra.{spec.name}] with an explicit unit",
                    allowed=names,
                )
            )
        elif spec.unit is not None:
            si = CANONICAL_CHANNELS[spec.name][0]
            try:
                si_factor(spec.unit, si)
            except UnitError as exc:
                p = exc.problem
                problems.append(Problem(f"{key}.unit", p.message, p.unit, p.allowed, p.got))
    for spec in extra:
        key = f"extra.{spec.name}"
        if spec.name in CANONICAL_CHANNELS:
            problems.append(
                Problem(key, f"{spec.name!r} is canonical; put it under [channels.{spec.name}]")
            )
        elif spec.unit is None:
            problems.append(
                Problem(
                    f"{key}.unit",
                    "missing key (a channel outside the canonical names needs an explicit unit)",
                )
            )
    if not channels and not extra:
        problems.append(
            Problem(
                "",
                "maps no channels and sets nothing; add [channels.<name>] or [extra.<name>] "
                "tables, or [file] / [time] settings for columns named as the canonical channels",
            )
        )
    return problems


def _map_error(where: str, problems: list[Problem]) -> RecordingError:
    lines = [p.format(where) for p in problems]
    error = RecordingError("\n".join(lines))
    error.problems = tuple(lines)
    return error


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
        raise RecordingFileNotFound(f"channel map file not found: {p}")
    try:
        data = read_toml(p)
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
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
    return Path(str(resources.files("rollerrig.recordings") / "data" / "example_channel_map.toml"))
