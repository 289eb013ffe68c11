"""A DAQ recording in SI units: the object every reader returns and every analysis takes.

Canonical channel names (SI units) let analyses find what they need whatever the file called it;
a channel map (:mod:`rollerrig.recordings.channels`) translates a file's columns into them.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from rollerrig._display import fmt, html_table, short_list, text_block
from rollerrig._validation import ParameterError
from rollerrig.recordings.uniform import uniform_sample_rate

__all__ = ["CANONICAL_CHANNELS", "ChannelLookup", "Recording", "RecordingError"]

CANONICAL_CHANNELS: dict[str, tuple[str, str]] = {
    "torque": ("N.m", "roller-shaft torque T56 (the torque sensor)"),
    "torque_request": ("N.m", "wheel torque request sent to the PMSM controller"),
    "wheel_speed": ("rad/s", "wheel angular speed"),
    "roller_speed": ("rad/s", "roller angular speed"),
    "wheel_encoder_counts": ("1", "wheel encoder count (cumulative)"),
    "roller_encoder_counts": ("1", "roller encoder count (cumulative)"),
    "air_spring_pressure": ("Pa", "air-spring gauge pressure"),
    "normal_load": ("N", "normal force N"),
    "displacement_front_bearing": ("m", "laser displacement at the front bearing"),
    "displacement_rear_bearing": ("m", "laser displacement at the rear bearing"),
    "displacement_torque_sensor": ("m", "laser displacement at the torque sensor"),
}
"""Canonical channel name -> (SI unit, meaning)."""


class RecordingError(ParameterError):
    """A recording is unusable as given: the message names the file, channel and problem."""


class RecordingFileNotFound(RecordingError, FileNotFoundError):
    """A recording or channel-map file does not exist: the package's own error (a
    :class:`ParameterError`) and a :class:`FileNotFoundError`, so either ``except`` catches it."""


class ChannelLookup:
    """``x[name]``: a channel of ``x.channels`` by name, or a :class:`RecordingError` listing
    the channels there are (``what`` names the object in the message)."""

    what = "recording"

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.channels[name]
        except KeyError:
            raise RecordingError(
                f"{self.what} has no channel {name!r}; it has {sorted(self.channels)}"
            ) from None


def _owned(values, what: str) -> np.ndarray:
    """``values`` as float64 the recording owns: a writable array given is copied (setting
    its flags had frozen the caller's arrays, and a view would let the caller write NaN into a
    recording already checked); a read-only one (a reader's, a memory map) is shared.

    ``what`` names the values in a message: complex values are refused (the conversion to
    float had dropped their imaginary part, silently) unless every imaginary part is zero.
    """
    arr = np.asarray(values)
    if np.iscomplexobj(arr):
        imaginary = np.flatnonzero(arr.imag)
        if imaginary.size:
            k = int(imaginary[0])
            raise RecordingError(
                f"{what} must be real, got complex values: {arr.ravel()[k]} at sample {k} "
                f"({imaginary.size} of {arr.size} samples with an imaginary part); pass its "
                "real part, magnitude or phase"
            )
        arr = arr.real
    try:
        arr = np.asarray(arr, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise RecordingError(f"{what} must hold numbers ({exc})") from None
    if arr.flags.writeable and isinstance(values, np.ndarray) and np.may_share_memory(arr, values):
        return arr.copy()
    return arr.view()


@dataclass(frozen=True)
class Recording(ChannelLookup):
    """Time-stamped channels in SI units.

    Parameters
    ----------
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing, finite.
    channels : mapping of str to ndarray, shape (n,)
        Channel values in SI units, by canonical name where one applies (see
        :data:`CANONICAL_CHANNELS`); other names are kept as they are.
    units : mapping of str to str
        SI unit of each channel.
    metadata : mapping
        Provenance: source file, format, SHA-256, channel map, reader notes.

    Examples
    --------
    >>> t = np.arange(5) / 250.0
    >>> r = Recording(t, {"torque": np.zeros(5)}, {"torque": "N.m"})
    >>> r.sample_rate, r["torque"].shape
    (250.0, (5,))
    """

    time: np.ndarray
    channels: Mapping[str, np.ndarray]
    units: Mapping[str, str]
    metadata: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        time = _owned(self.time, "time")
        if time.ndim != 1 or time.size < 2:
            raise RecordingError(
                f"time must be a 1-D array of at least 2 samples, got {time.shape}"
            )
        if not np.all(np.isfinite(time)):
            raise RecordingError(f"time has {int(np.sum(~np.isfinite(time)))} non-finite samples")
        if np.any(np.diff(time) <= 0):
            k = int(np.flatnonzero(np.diff(time) <= 0)[0])
            raise RecordingError(
                f"time is not strictly increasing at sample {k + 1} "
                f"({time[k]:.6g} s -> {time[k + 1]:.6g} s)"
            )
        channels = {}
        for name, values in self.channels.items():
            arr = _owned(values, f"channel {name!r}")
            if arr.shape != time.shape:
                raise RecordingError(
                    f"channel {name!r} has shape {arr.shape}, time has {time.shape}"
                )
            if name not in self.units:
                raise RecordingError(f"channel {name!r} has no unit")
            arr.setflags(write=False)
            channels[name] = arr
        time.setflags(write=False)
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "channels", MappingProxyType(channels))
        object.__setattr__(self, "units", MappingProxyType(dict(self.units)))
        object.__setattr__(self, "metadata", MappingProxyType(dict(self.metadata)))

    def __contains__(self, name: str) -> bool:
        return name in self.channels

    @functools.cached_property
    def sample_rate(self) -> float:
        """Nominal sampling rate [Hz]: ``(n − 1)`` over the time span where the time base is
        uniform (:func:`~rollerrig.recordings.uniform.uniform_sample_rate`: stamps written with
        few decimals do not bias it, where their median step read 600 Hz as 598.8), else 1 over
        the median sample interval."""
        try:
            return uniform_sample_rate(self.time)
        except ParameterError:  # jitter or gaps: the median step is the rate most steps have
            return float(1.0 / np.median(np.diff(self.time)))

    @property
    def duration(self) -> float:
        """Time span [s]."""
        return float(self.time[-1] - self.time[0])

    def require(self, *names: str) -> None:
        """Raise :class:`RecordingError` naming every missing channel."""
        missing = [n for n in names if n not in self.channels]
        if missing:
            raise RecordingError(
                f"recording lacks channel(s) {missing} needed here; it has {sorted(self.channels)}"
            )

    def with_channels(
        self, *, units: Mapping[str, str] | None = None, **new: np.ndarray
    ) -> Recording:
        """A copy with channels added or replaced.

        Units come from ``units`` or, for canonical names, :data:`CANONICAL_CHANNELS`; a new
        channel of any other name without a unit is refused (never labelled "1" by default).
        """
        channels = dict(self.channels)
        all_units = dict(self.units)
        for name, values in new.items():
            channels[name] = values
            if units is not None and name in units:
                all_units[name] = units[name]
            elif name in CANONICAL_CHANNELS:
                all_units.setdefault(name, CANONICAL_CHANNELS[name][0])
            elif name not in all_units:
                raise RecordingError(
                    f"channel {name!r}: no unit given; pass units={{{name!r}: ...}}"
                )
        return Recording(self.time, channels, all_units, self.metadata)

    def select(self, start: float, end: float) -> Recording:
        """The part of the recording with start <= t <= end [s]."""
        keep = (self.time >= start) & (self.time <= end)
        return Recording(
            self.time[keep],
            {k: v[keep] for k, v in self.channels.items()},
            self.units,
            self.metadata,
        )

    def _repr_lines(self) -> tuple[str, list[str]]:
        source = self.metadata.get("source")
        title = (
            f"Recording: {self.time.size} samples at {fmt(self.sample_rate)} Hz, "
            f"{fmt(self.duration)} s"
        )
        lines = [
            f"channels ({len(self.channels)}): "
            + short_list([f"{k} [{self.units[k]}]" for k in self.channels])
        ]
        if source:
            fmt_name = self.metadata.get("format")
            lines.append(f"from {Path(str(source)).name}" + (f" ({fmt_name})" if fmt_name else ""))
        notes = list(self.metadata.get("notes") or [])
        if notes:
            lines.append(f"{len(notes)} reader note(s): .metadata['notes']")
        return title, lines

    def __repr__(self) -> str:
        """A few lines: size, rate, duration, channels with units, source file."""
        return text_block(*self._repr_lines())

    def _repr_html_(self) -> str:
        """A small table for notebooks: each channel with its unit and range."""
        title, lines = self._repr_lines()
        rows = []
        for name, values in self.channels.items():
            finite = values[np.isfinite(values)]
            low, high = (finite.min(), finite.max()) if finite.size else (None, None)
            rows.append((name, self.units[name], fmt(low), fmt(high)))
        note = "; ".join(lines[1:])
        return html_table(title, rows, header=("channel", "unit", "min", "max"), note=note)

    def to_dataset(self):
        """The recording as an ``xarray.Dataset`` (units in the attributes)."""
        from rollerrig._optional import require

        xr = require("xarray", "io", "a recording as an xarray Dataset")

        from rollerrig.output.labelled import xarray_variable

        data = {
            k: xarray_variable(("time",), v, {"units": self.units[k]})
            for k, v in self.channels.items()
        }
        time = xarray_variable(("time",), self.time, {"units": "s"})
        ds = xr.Dataset(data, coords={"time": time})
        ds.attrs.update({k: str(v) for k, v in self.metadata.items()})
        return ds
