"""Channel maps: which column of a DAQ file is which canonical quantity, in which unit.

A channel map is a small TOML file (see ``data/example_channel_map.toml``)::

    [time]
    column = "Time"           # or: sample_rate_Hz = 250
    unit = "s"                # s or ms

    [channels.torque]
    column = "Torque_Roller"  # TDMS: "Group/Channel"; MDF4: the channel name
    unit = "N.m"
    scale = 1.0               # physical = scale * raw + offset (in `unit`), then -> SI
    offset = 0.0

    [extra.motor_current]     # non-canonical channels: explicit unit required
    column = "I_AM"
    unit = "A"

Canonical names and their SI units are :data:`rollerrig.measure.recording.CANONICAL_CHANNELS`.
Units are converted to SI here, at the edge, with the small per-quantity tables
:data:`UNIT_FACTORS` (SI unit -> accepted unit -> factor to SI).
"""

from __future__ import annotations

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
    "TIME_UNITS",
    "UNIT_FACTORS",
    "ChannelMap",
    "ChannelSpec",
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

TIME_UNITS: dict[str, float] = {"s": 1.0, "ms": 1e-3}
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
        ``"s"`` or ``"ms"`` (time column only).
    sample_rate_Hz : float or None
        Sampling rate [Hz] for files without a time column (time starts at 0 s).
    """

    column: str | None = None
    unit: str = "s"
    sample_rate_Hz: float | None = None


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
    """

    name: str
    column: str
    unit: str | None = None
    scale: float = 1.0
    offset: float = 0.0
    canonical: bool = True

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


@dataclass(frozen=True)
class ChannelMap:
    """Validated translation from a file's columns to canonical channels in SI units.

    Parameters
    ----------
    time : TimeSpec or None
        Where time comes from; None: from the file's own time base (TDMS waveform properties,
        MDF4 master channel).
    channels : tuple of ChannelSpec
        Canonical channels.
    extra : tuple of ChannelSpec
        Non-canonical channels, each with an explicit unit.
    source : str
        Where the map came from (a path, ``"<dict>"`` or ``"<default>"``).
    auto : bool
        True for :func:`default_channel_map`: every column whose name (without a ``[unit]``
        suffix) is canonical is read, others are kept as extras when their unit is known.

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
        _check_keys(data, {"time", "channels", "extra", "description", "name"}, where)
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
        return cls(time=time, channels=tuple(channels), extra=tuple(extra), source=source)

    def to_dict(self) -> dict[str, Any]:
        """The map in the structure of the TOML file (for provenance)."""
        out: dict[str, Any] = {}
        if self.auto:
            out["auto"] = True
        if self.time is not None:
            t: dict[str, Any] = {}
            if self.time.column is not None:
                t["column"] = self.time.column
                t["unit"] = self.time.unit
            if self.time.sample_rate_Hz is not None:
                t["sample_rate_Hz"] = self.time.sample_rate_Hz
            out["time"] = t
        for key, specs in (("channels", self.channels), ("extra", self.extra)):
            if specs:
                out[key] = {
                    s.name: {
                        "column": s.column,
                        **({"unit": s.unit} if s.unit is not None else {}),
                        "scale": s.scale,
                        "offset": s.offset,
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
    _check_keys(t, {"column", "unit", "sample_rate_Hz"}, f"{where}[time]: ")
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
    return TimeSpec(column=column, unit=normalize_unit(unit), sample_rate_Hz=rate)


def _parse_entry(name: str, entry: Any, where: str, *, canonical: bool) -> ChannelSpec:
    table = "channels" if canonical else "extra"
    here = f"{where}[{table}.{name}]: "
    e = _table(entry, here)
    _check_keys(e, {"column", "unit", "scale", "offset", "description"}, here)
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
    spec = ChannelSpec(name, column, unit, scale, offset, canonical)
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
