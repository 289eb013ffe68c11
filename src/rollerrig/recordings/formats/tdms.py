"""NI TDMS files (LabVIEW, DAQmx logging).

Each channel ``Group/Channel`` carries its own time base when it was written as a waveform
(LabVIEW waveform data type, DAQmx logging): ``wf_increment`` (sample interval [s]),
``wf_start_offset`` [s] and ``wf_start_time`` (absolute start, a timestamp). Channels whose
``wf_start_time`` differ are put on one absolute clock: seconds since the earliest start time in
the file. A DAQmx file with several tasks has one group per task, each with its own rate
(e.g. 19.2 kHz torque and 10 Hz pressure); such channels are never index-aligned.

The file is opened with ``nptdms.TdmsFile.open`` (streaming): only the channels asked for are
read, and :attr:`Table.slicer` reads parts of a channel (chunked reading). A file that ends
inside a segment (cut off during acquisition or copying) is an error, not a shorter recording.

A ``<file>.tdms_index`` beside the file is never used for reading: nptdms is given the open
file, so it reads the segment headers of the data file itself (an index left from an older or
shorter file would otherwise make it read too few samples, or garbage). The index is only
compared with the file, and a note says that it was present and ignored, and whether it agrees.

A channel without samples (a spare input that was never acquired) is skipped with a note when
its name is not a canonical channel: no analysis reads it, and a channel map entry naming it is
an error saying that it holds no samples. An empty channel with a canonical name stays in the
table, so that a caller that needs it gets that error; for one that does not (``rollerrig
filters`` needs only the torque; ``analyze`` without a channel map checks its own inputs) the
reader notes it and goes on.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from rollerrig.recordings.channels import (
    CANONICAL_CHANNELS,
    split_unit_header,
    time_named,
    time_unit,
)
from rollerrig.recordings.formats._sliced import (
    add_channel,
    checked_slice,
    read_in_slices,
    store_json,
)
from rollerrig.recordings.formats._table import META_KEY, Column, Table, require_module
from rollerrig.recordings.recording import RecordingError

_TDMS_EPOCH = np.datetime64("1904-01-01T00:00:00", "us")
"""LabVIEW's zero timestamp (seconds 0, fractions 0: a ``wf_start_time`` never set)."""


_NEEDED_NAMES = frozenset(CANONICAL_CHANNELS) | {"time"}
"""Channel names an empty channel keeps its place in the table under (reading it is an error)."""


class _Collect(logging.Handler):
    """Collects nptdms' warnings (it reports truncated or damaged files only as warnings)."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _check(log: _Collect, path: Path, seen: int) -> int:
    """Raise when nptdms reported a truncated or damaged file since message ``seen``."""
    new = log.messages[seen:]
    damaged = [
        m
        for m in new
        if any(
            key in m
            for key in (
                "incomplete",
                "less data than expected",
                "not a multiple of the chunk size",
                "Cropping data",
            )
        )
    ]
    if damaged:
        raise RecordingError(
            f"{path}: the TDMS file is truncated or damaged (nptdms: {damaged[0]}); it ends "
            "inside a data segment, e.g. cut off during acquisition or copying; use the complete "
            "file, or repair it (LabVIEW/DIAdem 'TDMS Defragment') and read the repaired copy"
        )
    return len(log.messages)


def _start_time(props) -> tuple[int, int] | None:
    """``wf_start_time`` as LabVIEW stores it: (seconds since 1904, 2^-64 s fractions); None
    where unset (LabVIEW's zero) or not a timestamp."""
    st = props.get("wf_start_time")
    seconds = getattr(st, "seconds", None)
    fractions = getattr(st, "second_fractions", None)
    if isinstance(seconds, int | np.integer) and isinstance(fractions, int | np.integer):
        if seconds or fractions:
            return int(seconds), int(fractions)
    return None


def _seconds_between(a: tuple[int, int], b: tuple[int, int]) -> float:
    """``a − b`` [s] of two LabVIEW timestamps, exact to the float (2^-64 s fractions)."""
    return float(a[0] - b[0]) + (a[1] - b[1]) / 2.0**64


def _as_datetime64(stamp: tuple[int, int]) -> np.datetime64:
    """A LabVIEW timestamp as numpy's datetime64 [ns] (for notes)."""
    nanos = stamp[0] * 1_000_000_000 + (stamp[1] * 1_000_000_000 >> 64)
    return _TDMS_EPOCH.astype("datetime64[ns]") + np.timedelta64(nanos, "ns")


def _timestamp_seconds(values, first: tuple[int, int]) -> np.ndarray:
    """Seconds since ``first`` of a TDMS timestamp channel read raw (nptdms' TimestampArray:
    seconds since 1904 and 2^-64 s fractions): exact to the float. As datetime64[us] (nptdms'
    default) a 51.2 kS/s clock came back in steps of 19 and 20 µs, its rate 50 000 Hz."""
    seconds = np.asarray(values["seconds"], dtype=np.int64) - first[0]
    fractions = np.asarray(values["second_fractions"], dtype=np.uint64)
    # the fractions below and above the first's, apart: a uint64 difference would wrap
    above = fractions >= np.uint64(first[1])
    delta = np.where(
        above,
        (fractions - np.uint64(first[1])).astype(float),
        -((np.uint64(first[1]) - fractions).astype(float)),
    )
    return seconds.astype(float) + delta / 2.0**64


@contextlib.contextmanager
def open_tdms(path: Path) -> Iterator[Table]:
    nptdms = require_module("nptdms", "TDMS files")
    log = _Collect()
    logger = logging.getLogger("nptdms")
    # nptdms prints its warnings itself; they become the error message here instead
    console = getattr(
        getattr(getattr(nptdms, "log", None), "log_manager", None), "console_handler", None
    )
    level = console.level if console is not None else None
    if console is not None:
        console.setLevel(logging.CRITICAL + 1)
    try:
        index_path = Path(f"{path}_index")
        indexed = _index_lengths(nptdms, index_path) if index_path.is_file() else None
        logger.addHandler(log)
        try:
            # nptdms given a path reads <path>_index instead of the file's own segment headers
            fh = path.open("rb")
        except OSError as exc:
            raise RecordingError(f"{path}: cannot be opened: {exc}") from exc
        with fh:
            try:
                # raw: LabVIEW's timestamps to 2^-64 s, not numpy's datetime64[us]
                tdms = nptdms.TdmsFile.open(fh, raw_timestamps=True)
            except Exception as exc:
                raise RecordingError(f"{path}: not a readable TDMS file: {exc}") from exc
            with tdms:
                seen = _check(log, path, 0)
                try:
                    table = _table(tdms, path, log, seen)
                except RecordingError:
                    raise
                except Exception as exc:  # damaged metadata nptdms read without complaint
                    raise RecordingError(f"{path}: not a readable TDMS file: {exc}") from exc
                if index_path.is_file():
                    table.notes.append(_index_note(index_path, indexed, tdms))
                yield table
    finally:
        logger.removeHandler(log)
        if console is not None:
            console.setLevel(level)


def _index_lengths(nptdms, index_path: Path) -> dict[str, int] | str:
    """Samples per channel (``group/channel``) that ``index_path`` promises; text if unreadable."""
    try:
        meta = nptdms.TdmsFile.read_metadata(str(index_path))
        return {f"{g.name}/{c.name}": len(c) for g in meta.groups() for c in g.channels()}
    except Exception as exc:  # a damaged index: only its note depends on it
        return f"unreadable ({type(exc).__name__}: {exc})"


def _index_note(index_path: Path, indexed: dict[str, int] | str | None, tdms) -> str:
    """The note on an index file beside the TDMS file: ignored, and whether it agrees."""
    head = (
        f"TDMS index file {index_path.name!r} beside the file ignored: the data file's own "
        "segment headers were read"
    )
    if not isinstance(indexed, dict):
        return f"{head}; the index is {indexed or 'unreadable'}"
    actual = {f"{g.name}/{c.name}": len(c) for g in tdms.groups() for c in g.channels()}
    if indexed == actual:
        return f"{head}; the index agrees with the file"
    differ = [
        f"{n!r} {indexed.get(n, 'absent')} in the index, {actual.get(n, 'absent')} in the file"
        for n in [*actual, *(n for n in indexed if n not in actual)]
        if indexed.get(n) != actual.get(n)
    ]
    return (
        f"{head}; the index is stale (it disagrees with the file, samples per channel: "
        + "; ".join(differ[:5])
        + (f"; and {len(differ) - 5} more" if len(differ) > 5 else "")
        + "); delete it or write it again (nptdms, LabVIEW 'TDMS Defragment')"
    )


def _group_times(tdms, table: Table) -> None:
    """Each group's time channels (DIAdem / LabVIEW style: a ``Time`` channel per group, named
    as a time column is, :func:`~rollerrig.recordings.channels.time_named`, in a time unit or
    none) as the time base of the group's other channels (:attr:`Table.time_of`)."""
    for group in tdms.groups():
        names = [f"{group.name}/{ch.name}" for ch in group.channels()]
        names = [n for n in names if n in table.names]
        times = []
        for ch in group.channels():
            name = f"{group.name}/{ch.name}"
            unit = ch.properties.get("unit_string")
            if name not in table.names or not time_named(
                split_unit_header(ch.name)[0].strip().lower()
            ):
                continue
            if isinstance(unit, str) and unit.strip() and time_unit(unit) is None:
                continue  # named so, but in another unit: no time
            times.append(name)
        if times:
            for name in names:
                if name not in times:
                    table.time_of[name] = tuple(times)


def _table(tdms, path: Path, log: _Collect, seen: int) -> Table:
    chans = {}
    table = Table(names=[], load=lambda n: None)  # type: ignore[arg-type,return-value]
    waveform: dict[str, tuple[float, float]] = {}  # name -> (wf_start_offset [s], increment [s])
    starts: dict[str, tuple[int, int]] = {}
    empty: dict[str, list[str]] = {}  # channels without samples (not in table.names): aliases
    for group in tdms.groups():
        for ch in group.channels():
            name = f"{group.name}/{ch.name}"
            chans[name] = ch
            props = ch.properties
            ni_name = props.get("NI_ChannelName")
            aliases = [ch.name, ch.path]
            if isinstance(ni_name, str) and ni_name not in (ch.name, name):
                aliases.append(ni_name)
            if len(ch) == 0 and not any(a in _NEEDED_NAMES for a in aliases):
                empty[name] = aliases  # skipped; a map entry naming it: "holds no samples"
                continue
            add_channel(table, name, ch.name, groups=[group.name], aliases=aliases)
            try:
                inc = float(props.get("wf_increment", 0.0))
                offset = float(props.get("wf_start_offset", 0.0))
            except (TypeError, ValueError):
                inc, offset = 0.0, 0.0
            if inc > 0 and np.isfinite(inc) and np.isfinite(offset):
                waveform[name] = (offset, inc)
                st = _start_time(props)
                if st is not None:
                    starts[name] = st
            n_wf = props.get("wf_samples")
            if isinstance(n_wf, int | np.integer) and 0 < len(ch) < int(n_wf):
                table.notes.append(
                    f"TDMS channel {name!r} holds {len(ch)} samples, fewer than its wf_samples "
                    f"= {int(n_wf)}"
                )

    _group_times(tdms, table)

    for name, aliases in empty.items():  # its other names, where no channel with samples has them
        table.aliases[name] = [name]
        for alias in aliases:
            if alias not in table.names and alias not in table.aliases:
                table.aliases[alias] = [name]
    if empty:
        table.skipped.extend(f"{n} (TDMS channel without samples)" for n in empty)
        table.notes.append(
            f"TDMS channels without samples skipped: {list(empty)} (not canonical channels; a "
            "channel map entry that names one is an error)"
        )

    # one absolute clock: seconds since the earliest wf_start_time
    shift: dict[str, float] = {}
    if starts:
        t_ref = min(starts.values())
        for name, st in starts.items():
            shift[name] = _seconds_between(st, t_ref)
        table.notes.append(
            f"absolute start time (earliest TDMS wf_start_time): {_as_datetime64(t_ref)}"
        )
        if any(s != 0.0 for s in shift.values()):
            table.notes.append(
                "TDMS channels start at different absolute times (wf_start_time); put on one "
                "clock, seconds since the earliest: "
                + ", ".join(f"{n} +{s:.9g} s" for n, s in shift.items() if s != 0.0)
            )
        unset = sorted(set(waveform) - set(starts))
        if unset:
            table.notes.append(
                f"TDMS channels {unset} have no wf_start_time; assumed to start at "
                f"{_as_datetime64(t_ref)}"
            )

    def length(name: str) -> int:
        return len(chans[name])

    firsts: dict[str, tuple[int, int]] = {}  # a timestamp channel's first sample

    clocks = sorted({t for times in table.time_of.values() for t in times})  # groups' times

    def first_stamp(name: str) -> tuple[int, int] | None:
        head = chans[name][0:1]
        if getattr(head.dtype, "names", None) != ("second_fractions", "seconds") or not len(head):
            return None
        return int(head["seconds"][0]), int(head["second_fractions"][0])

    def timestamps(name: str, values) -> np.ndarray:
        if name not in firsts:
            firsts[name] = first_stamp(name)
            since = "its first sample"
            if name in clocks:  # the groups' time channels on one clock: their earliest stamp
                stamps = [s for n in clocks if (s := first_stamp(n)) is not None]
                if len(stamps) > 1:
                    firsts[name] = min(stamps)
                    since = "the earliest first sample of the groups' time channels"
            table.notes.append(
                f"TDMS timestamp channel {name!r} converted to seconds since {since} "
                f"({_as_datetime64(firsts[name])})"
            )
        return _timestamp_seconds(values, firsts[name])

    def read(name: str, start: int, stop: int) -> Column:
        nonlocal seen
        ch = chans[name]
        n = len(ch)
        if n == 0:
            raise RecordingError(
                f"{path}: TDMS channel {name!r} holds no samples (it was created but never "
                "written); map another channel, or use a file in which it was acquired"
            )
        start, stop = max(0, start), min(n, stop)

        def get() -> tuple[np.ndarray]:
            nonlocal seen
            values = ch[start:stop]
            seen = _check(log, path, seen)  # nptdms reports damage as log warnings
            if getattr(values.dtype, "names", None) == ("second_fractions", "seconds"):
                return (timestamps(name, values),)
            values = np.asarray(values)
            return (values,)

        (values,) = checked_slice(
            f"{path}: TDMS channel {name!r} (samples {start}..{stop})",
            get,
            stop - start,
            "the file's index",
        )
        own = None
        if name in waveform:
            offset, inc = waveform[name]
            own = shift.get(name, 0.0) + offset + np.arange(start, stop) * inc
        if name in firsts:  # timestamps, now seconds since the first (whatever unit_string says)
            return Column(values, "s", own)
        props = ch.properties
        unit = props.get("unit_string") or props.get("NI_UnitDescription") or None
        return Column(values, unit if isinstance(unit, str) else None, own)

    raw = tdms.properties.get(META_KEY)
    if raw:
        store_json(table, raw)
    return read_in_slices(table, length, read)
