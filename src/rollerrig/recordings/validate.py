"""Validation of a recording at the boundary: time, NaN/inf samples, gaps.

- time must be finite and strictly increasing (duplicated or backward time: an error with the
  sample index and the times);
- NaN/inf samples: ``mode="strict"`` raises, naming the channel, the count and the first run of
  bad samples; ``mode="lenient"`` linearly interpolates runs of at most
  :data:`MAX_INTERPOLATED_NAN_RUN` samples and still raises for longer runs;
- gaps (dropped samples: an interval > :data:`GAP_FACTOR` x the median interval,
  :func:`find_gaps`): strict raises with the gap's location and size, lenient keeps them;
- the sampling rate (1 / median interval) may not exceed :data:`MAX_SAMPLE_RATE_HZ`, and no
  time base is built with more than :data:`MAX_GRID_SAMPLES` samples
  (:func:`check_sample_rate`, :func:`check_grid`): a time in the wrong unit (picoseconds read
  as seconds) or an absurd ``sample_rate_Hz``/``resample_Hz`` is refused before anything is
  allocated for it. The limits live here, and only here;
- a time column of serial day numbers (an Excel serial date, a MATLAB ``datenum``) is an error
  naming the dates it stands for and how to convert it (:func:`check_serial_days`): read as
  seconds, a 1 kHz recording was one of 86.4 MHz lasting a few milliseconds;
- a time column without a unit (in the file or the channel map), read as seconds, whose
  sampling rate is about 1/1000 of a rig's DAQ rate (or whose duration is implausibly long at
  an implausibly low rate) is a :class:`~rollerrig._warnings.DomainWarning` naming the file
  and how to declare the unit (:func:`check_time_unit`).
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Mapping
from datetime import datetime, timedelta
from typing import Any

import numpy as np

from rollerrig._validation import ParameterError, require_increasing
from rollerrig._warnings import DomainWarning
from rollerrig.recordings.recording import RecordingError

__all__ = [
    "GAP_FACTOR",
    "MAX_GRID_SAMPLES",
    "MAX_INTERPOLATED_NAN_RUN",
    "MAX_SAMPLE_RATE_HZ",
    "RIG_DAQ_RATE_HZ",
    "check_grid",
    "check_nan_runs",
    "check_sample_rate",
    "check_serial_days",
    "check_time_unit",
    "describe_gap",
    "find_gaps",
    "require_two_samples",
    "true_runs",
    "validate_samples",
]

MAX_INTERPOLATED_NAN_RUN = 3
"""Longest run of NaN/inf samples that ``validate="lenient"`` interpolates [samples]."""

GAP_FACTOR = 1.5
"""A sample interval longer than this multiple of the median interval is a gap."""

MAX_SAMPLE_RATE_HZ = 1e8
"""Highest sampling rate of a recording [Hz] (100 MHz: above the fastest transient recorders
on a test rig; a higher rate is a time in the wrong unit or a damaged header)."""

MAX_GRID_SAMPLES = 2**28
"""Most samples of a time base the readers build (a resampling grid, a time from a stated
rate) [-]: 2 GiB per channel of float64."""


def check_sample_rate(rate: float, where: str, source: str) -> None:
    """RecordingError when ``rate`` [Hz] is not finite or above :data:`MAX_SAMPLE_RATE_HZ`.

    ``source`` says where the rate comes from (``"median interval of column 'time'"``).

    Examples
    --------
    >>> check_sample_rate(19200.0, "run.csv:", "the time column")
    >>> try:
    ...     check_sample_rate(1e12, "run.csv:", "the time column")
    ... except RecordingError as exc:
    ...     print(str(exc)[:71])
    run.csv: sampling rate 1e+12 Hz (the time column) is above the limit of
    """
    if not (np.isfinite(rate) and rate <= MAX_SAMPLE_RATE_HZ):
        raise RecordingError(
            f"{where} sampling rate {rate:.6g} Hz ({source}) is above the limit of "
            f"{MAX_SAMPLE_RATE_HZ:g} Hz (MAX_SAMPLE_RATE_HZ); check the time unit (ms or µs "
            "read as s?) or the stated rate"
        )


SERIAL_DAYS: dict[str, tuple[float, float, datetime]] = {
    "Excel serial dates (days since 1899-12-30)": (25569.0, 73051.0, datetime(1899, 12, 30)),
    "MATLAB datenum values (days since year 0)": (719529.0, 767011.0, datetime(1, 1, 1)),
}
"""Serial day numbers of 1970-2100 -> (first, last, their day 0 as :mod:`datetime` counts it;
a datenum's day 1 is 0000-01-01, :meth:`datetime.fromordinal`'s 0001-01-01 is day 367)."""

SERIAL_DAY_STEP = 1e-6
"""Largest median step of a time column in serial days [d] taken as a sampled signal: above
11.6 Hz. Read as seconds it is a rate above 1 MHz at 7 to 213 hours since its zero, which no
recording in seconds has; a slower clock in serial days is not refused."""


def check_serial_days(values: np.ndarray, what: str) -> None:
    """RecordingError when a time column's numbers (``values``, as in the file, before the
    unit) are serial day numbers: an Excel serial date or a MATLAB ``datenum`` of 1970-2100
    (:data:`SERIAL_DAYS`) whose median step is at most :data:`SERIAL_DAY_STEP` (a sampled
    signal). Read in seconds they gave a recording of tens of MHz lasting milliseconds,
    without a word; no time unit of the channel map means days, so the file must be
    converted (the message says how). ``what`` names the file and the column.

    Examples
    --------
    >>> check_serial_days(np.arange(5) / 1000.0, "run.csv: time column 't'")
    >>> try:
    ...     check_serial_days(45509.5 + np.arange(5) / 86.4e6, "run.csv: time column 't'")
    ... except RecordingError as exc:
    ...     print(str(exc)[:88])
    run.csv: time column 't' holds serial day numbers, not seconds: Excel serial dates (days
    """
    v = np.asarray(values, dtype=float).ravel()[:1001]
    v = v[np.isfinite(v)]
    if v.size < 2:
        return
    step = float(np.median(np.diff(v)))
    if not 0.0 < step <= SERIAL_DAY_STEP:
        return
    for kind, (low, high, zero) in SERIAL_DAYS.items():
        if low <= v[0] <= high:
            day0 = zero + timedelta(days=float(v[0]) - (367.0 if zero.year == 1 else 0.0))
            raise RecordingError(
                f"{what} holds serial day numbers, not seconds: {kind}, the first {float(v[0])!r} "
                f"is {day0:%Y-%m-%d %H:%M:%S.%f}, a step of {step * 86400.0:.6g} s "
                f"({1.0 / (step * 86400.0):.6g} Hz); read as seconds it is {1.0 / step:.4g} "
                "Hz. No time unit means days (and a float64 of days resolves 6-10 µs only): "
                "convert the time to seconds where the file is written (Excel: =(A2-$A$2)*86400;"
                " MATLAB: t = (t - t(1)) * 86400), or write it as date/time text "
                "(yyyy-mm-dd HH:MM:SS.FFF), and read that file"
            )


RIG_DAQ_RATE_HZ = 250.0
"""The default rig's DAQ rate (``sensors.daq_rate`` of the default parameter set) [Hz]: the
readers do not know the rig, and a time in ms read as s is 1000 x off any rig's rate."""

MIN_PLAUSIBLE_RATE_HZ = 50.0
"""Slowest sampling of a rig's torque and speed channels [Hz] (the rigs record at 250 Hz to
19.2 kHz); a long recording below it with a time of no unit is a time in ms read as s."""

MAX_PLAUSIBLE_DURATION_S = 3600.0
"""Longest adhesion test [s] taken as plausible at a rate below :data:`MIN_PLAUSIBLE_RATE_HZ`."""


_FINER_UNITS = (
    ("ms", 1e3, "milliseconds"),
    ("us", 1e6, "microseconds"),
    ("ns", 1e9, "nanoseconds"),
)
"""Time units a time read in seconds may have been written in: (unit of the channel map, factor
to the rate, name)."""


def check_time_unit(
    rate: float,
    duration: float,
    where: str,
    column: str,
    *,
    daq_rate: float = RIG_DAQ_RATE_HZ,
) -> str | None:
    """A :class:`~rollerrig._warnings.DomainWarning` (and its text) when a time column that had
    no unit, in the file or the channel map, and was read in seconds looks like milliseconds.

    It does when the sampling rate ``rate`` [Hz] it implies, times 1000, is within a factor 4
    of the DAQ rate ``daq_rate`` [Hz], or when the recording lasts longer than
    :data:`MAX_PLAUSIBLE_DURATION_S` at a rate below :data:`MIN_PLAUSIBLE_RATE_HZ`. Call it
    only for a time whose unit was assumed; None when the time looks right.

    Examples
    --------
    >>> check_time_unit(250.0, 30.0, "run.csv:", "time") is None
    True
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     print(check_time_unit(0.25, 30000.0, "run.csv:", "time")[:59])
    run.csv: the time column 'time' has no unit (in the file or
    """
    if not (np.isfinite(rate) and rate > 0.0 and np.isfinite(duration)):
        return None
    near_ms = daq_rate / 4.0 <= rate * 1e3 <= daq_rate * 4.0
    too_long = duration > MAX_PLAUSIBLE_DURATION_S and rate < MIN_PLAUSIBLE_RATE_HZ
    if not (near_ms or too_long):
        return None
    # the smallest unit that makes the rate a rig's: ms, else µs or ns (an elapsed count of
    # µs read as s had been advised as ms, and read so was 1 Hz without a word)
    unit, factor, name = "ms", 1e3, "milliseconds"
    if not near_ms:
        unit, factor, name = next(
            (c for c in _FINER_UNITS if rate * c[1] >= MIN_PLAUSIBLE_RATE_HZ), _FINER_UNITS[0]
        )
    text = (
        f"{where} the time column {column!r} has no unit (in the file or the channel map) and "
        f"was read in seconds: {rate:.4g} Hz over {duration:.6g} s, where a rig's DAQ records "
        f"at about {daq_rate:g} Hz for minutes; it looks like {name} ({rate * factor:.4g} "
        f'Hz over {duration / factor:.6g} s). Declare the unit: unit = "{unit}" in the channel '
        f'map\'s [time] section, or the header "{column} [{unit}]" in the file'
    )
    warnings.warn(text, DomainWarning, stacklevel=2)
    return text


def check_grid(duration: float, rate: float, where: str, source: str) -> int:
    """The number of samples of a ``rate`` [Hz] grid over ``duration`` [s], or a
    RecordingError when it exceeds :data:`MAX_GRID_SAMPLES` (checked before allocation)."""
    check_sample_rate(rate, where, source)
    n = float(duration) * float(rate) + 1.0
    if not (np.isfinite(n) and n <= MAX_GRID_SAMPLES):
        raise RecordingError(
            f"{where} a {rate:.6g} Hz time base over {duration:.6g} s ({source}) would hold "
            f"{n:.3g} samples, above the limit of {MAX_GRID_SAMPLES} (MAX_GRID_SAMPLES); "
            "choose a lower rate"
        )
    return int(n)


def find_gaps(time: np.ndarray) -> tuple[float, list[dict[str, Any]]]:
    """The median sample interval [s] and the gaps (dropped samples) of ``time`` [s], finite
    and strictly increasing (else a :class:`~rollerrig._validation.ParameterError`).

    A gap is an interval longer than :data:`GAP_FACTOR` x the median; each is a dict with
    ``sample`` (the index before it), ``start_s``, ``end_s``, ``duration_s`` [s] and
    ``missing_samples`` (about how many samples at the median interval are missing).

    Examples
    --------
    >>> step, gaps = find_gaps(np.array([0.0, 0.1, 0.2, 0.5, 0.6]))
    >>> round(step, 3), gaps[0]["sample"], gaps[0]["missing_samples"]
    (0.1, 2, 2)
    """
    # Unsorted time had given negative intervals and a wrong median, silently; a repeated
    # instant is no sample interval (a median of 0 had divided by zero).
    time = require_increasing("time", time, "s")
    if time.size < 2:  # no interval: the median of none is NaN
        raise ParameterError(f"time must hold at least 2 samples [s], got {time.size}")
    dt = np.diff(time)
    median = float(np.median(dt))
    return median, [
        {
            "sample": int(k),
            "start_s": float(time[k]),
            "end_s": float(time[k + 1]),
            "duration_s": float(dt[k]),
            "missing_samples": round(float(dt[k]) / median) - 1,
        }
        for k in np.flatnonzero(dt > GAP_FACTOR * median)
    ]


def describe_gap(gap: Mapping[str, Any]) -> str:
    """A gap of :func:`find_gaps` in words: duration, where, about how many samples missing."""
    nan = float("nan")
    return (
        f"{gap.get('duration_s', nan):.6g} s after t = {gap.get('start_s', nan):.6g} s (sample "
        f"{gap.get('sample')}, about {gap.get('missing_samples')} missing sample(s))"
    )


def require_two_samples(n: int, where: str, notes: Iterable[str] = ()) -> None:
    """Refuse a recording of fewer than 2 samples, quoting those of the reader's ``notes``
    that say it left rows out (a last line cut by an interrupted writer, dropped or skipped
    rows): they say why a file of two lines holds one sample.

    Raises
    ------
    RecordingError
        ``n < 2``.
    """
    if n < 2:
        why = "; ".join(note for note in notes if "dropped" in note or "skipped" in note)
        because = f" (the reader: {why})" if why else ""
        raise RecordingError(f"{where} only {n} sample(s); need at least 2{because}")


def validate_samples(
    time: np.ndarray,
    channels: dict[str, np.ndarray],
    mode: str,
    where: str,
    notes: Iterable[str] = (),
) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """The channels checked (``mode`` "lenient": short NaN/inf runs interpolated) and a report.

    Parameters
    ----------
    time : ndarray
        Sample times [s].
    channels : dict of str to ndarray
        Channel values (SI units), each as long as ``time``.
    mode : {"strict", "lenient"}
        See the module docstring.
    where : str
        Prefix of error messages (the file).
    notes : iterable of str
        The reader's notes, quoted when the recording is too short (:func:`require_two_samples`).

    Returns
    -------
    channels : dict of str to ndarray
        The channels, NaN/inf runs interpolated (lenient).
    report : dict
        ``gaps`` (:func:`find_gaps`) and ``interpolated`` (channel, first and last sample,
        start and end time [s], method of each run).

    Raises
    ------
    RecordingError
        Fewer than 2 samples, non-finite or non-increasing time; strict: a gap or a NaN/inf
        sample; lenient: a NaN/inf run longer than :data:`MAX_INTERPOLATED_NAN_RUN`.
    """
    report: dict[str, Any] = {"gaps": [], "interpolated": []}
    require_two_samples(time.size, where, notes)
    bad = ~np.isfinite(time)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise RecordingError(
            f"{where} time has {int(bad.sum())} non-finite samples, first at sample {k}"
        )
    dt = np.diff(time)
    if np.any(dt <= 0):
        idx = np.flatnonzero(dt <= 0)
        k = int(idx[0])
        kind = "duplicated" if dt[k] == 0 else "goes backwards"
        raise RecordingError(
            f"{where} time {kind} at sample {k + 1}: t[{k}] = {time[k]:.9g} s, "
            f"t[{k + 1}] = {time[k + 1]:.9g} s ({idx.size} non-increasing step(s) in total); "
            "time must be strictly increasing"
            + (
                "; the time column is printed to too few digits for the rate? Where the samples "
                "are evenly spaced, give [time] sample_rate_Hz in the channel map instead"
                if dt[k] == 0 and idx.size >= 0.1 * dt.size
                else ""
            )
            + (
                "; a step back by about an hour: local clock times across the end of daylight "
                "saving time? Export times in UTC or with their offset (+01:00)"
                if abs(dt[k] + 3600.0) <= 60.0
                else ""
            )
        )
    median, gaps = find_gaps(time)
    check_sample_rate(1.0 / median, where, "1 / the median sample interval of the time")
    if gaps and mode == "strict":
        g = gaps[0]
        raise RecordingError(
            f"{where} gap (dropped samples) between sample {g['sample']} (t = {g['start_s']:.9g} s)"
            f" and {g['sample'] + 1} (t = {g['end_s']:.9g} s): {g['duration_s']:.6g} s, about "
            f"{g['missing_samples']} missing sample(s) at the median interval {median:.6g} s; "
            f"{len(gaps)} gap(s) in total; validate='lenient' (--lenient on the command line) "
            "keeps them and lists them"
        )
    report["gaps"] = gaps
    out: dict[str, np.ndarray] = {}
    for name, values in channels.items():
        out[name], runs = check_nan_runs(time, name, values, mode, where)
        report["interpolated"].extend(runs)
    return out, report


def check_nan_runs(
    time: np.ndarray,
    name: str,
    values: np.ndarray,
    mode: str,
    where: str,
    base: str = "",
) -> tuple[np.ndarray, list[dict[str, Any]]]:
    """A channel's values with its NaN/inf runs checked (``mode`` as for
    :func:`validate_samples`: strict refuses any, lenient interpolates runs of at most
    :data:`MAX_INTERPOLATED_NAN_RUN` samples) and the runs interpolated.

    ``time`` [s] is the time base the values were sampled on: the recording's, or the
    channel's own before it is resampled onto a common one (``base`` then says which, for
    the messages, e.g. " of its own time base"), so that a run counts the file's samples, not
    those of a resampling grid.
    """
    v = np.asarray(values, dtype=float)
    bad = ~np.isfinite(v)
    if not bad.any():
        return v, []
    runs = true_runs(bad)
    longest = max(runs, key=lambda r: r[1] - r[0])
    first = runs[0]

    def describe(run: tuple[int, int]) -> str:
        a, b = run
        return (
            f"samples {a}..{b}{base} (t = {time[a]:.9g} s .. {time[b]:.9g} s, {b - a + 1} samples)"
        )

    last = runs[-1]
    tail = (
        f"; the channel ends at sample {last[0]} (t = {time[last[0]]:.9g} s) while others "
        "go on: a channel recorded at a lower rate or for a shorter time (an export of "
        "several rates side by side, each with its own time column)? One file is read on "
        "one time base: export each rate to a file of its own"
        if last[1] == v.size - 1 and last[0] > 0 and last[1] - last[0] + 1 > 0.1 * v.size
        else ""
    )
    if mode == "strict" or bad.all():
        raise RecordingError(
            f"{where} channel {name!r} has {int(bad.sum())} NaN/inf samples in {len(runs)} "
            f"run(s); first run: {describe(first)}"
            + ("" if mode == "strict" else "; every sample is bad")
            + tail
            + (
                "; validate='lenient' (--lenient on the command line) interpolates runs of "
                f"at most {MAX_INTERPOLATED_NAN_RUN} samples"
                if mode == "strict"
                else ""
            )
        )
    if longest[1] - longest[0] + 1 > MAX_INTERPOLATED_NAN_RUN:
        raise RecordingError(
            f"{where} channel {name!r} has a run of NaN/inf samples too long to interpolate "
            f"(more than {MAX_INTERPOLATED_NAN_RUN}): {describe(longest)}" + tail
        )
    good = ~bad
    v = v.copy()
    v[bad] = np.interp(time[bad], time[good], v[good])
    report = [
        {
            "channel": name,
            "first_sample": a,
            "last_sample": b,
            "start_s": float(time[a]),
            "end_s": float(time[b]),
            "method": "linear" if a > 0 and b < v.size - 1 else "held (edge)",
            **({"time_base": base.strip().removeprefix("of ")} if base else {}),
        }
        for a, b in runs
    ]
    return v, report


def true_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of True in ``mask``.

    Examples
    --------
    >>> true_runs(np.array([False, True, True, False, True]))
    [(1, 2), (4, 4)]
    """
    m = np.concatenate([[False], mask, [False]]).astype(int)
    d = np.diff(m)
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    return list(zip(starts.tolist(), ends.tolist(), strict=True))
