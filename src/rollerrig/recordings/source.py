"""Chunked access to long recordings: read only the part of a file that is needed.

One hour at 19.2 kHz × 4 channels is 276 M samples (2.2 GB as float64); :func:`read_recording`
would hold all of it. :func:`open_recording` opens the same files with the same channel map and
gives the channels in SI units chunk by chunk, reading from disk only the slice asked for:

========  ==================================================================================
TDMS      ``nptdms.TdmsFile.open`` (streaming) and ``channel[a:b]``
MDF4      ``asammdf.MDF.get(..., record_offset=a, record_count=b - a)``
Parquet   the row groups that hold rows ``a:b`` (``ParquetFile.read_row_groups``)
MAT       v7.3 / HDF5: ``h5py`` dataset slices; v4-v7 (no partial reads): read whole, noted
CSV/text  the layout :func:`read_recording` sniffs, rows read in blocks (``pandas.read_csv``
          with ``chunksize``); blank lines skipped and a last line cut by an interrupted
          writer dropped (noted) as there, another row cut short is an error, and no
          ``.metadata.json`` sidecar is read
LVM       read whole (as :func:`read_recording` does), noted
========  ==================================================================================

The channel map is resolved exactly as :func:`read_recording` resolves it (the same code runs on
the first samples of the file: columns, units, notes and errors are the same), and every chunk
is converted with the same calibration and unit factors. Chunked reading is strict: a NaN/inf
sample, a time that does not increase, or a gap is an error naming the channel and the sample.
Only channels that share one time base can be read in chunks; a multi-rate file (DAQmx tasks at
different rates, MDF groups at different rasters) is an error that says to use
:func:`read_recording` (which resamples onto a common base) or to map channels of one rate.

Examples
--------
>>> import tempfile, pathlib
>>> import numpy as np
>>> from rollerrig.recordings.recording import Recording
>>> from rollerrig.recordings.writers import write_recording
>>> t = np.arange(10_000) / 1000.0
>>> f = pathlib.Path(tempfile.mkdtemp()) / "run.tdms"
>>> _ = write_recording(Recording(t, {"torque": np.sin(t)}, {"torque": "N.m"}), f)
>>> with open_recording(f) as src:
...     sizes = [len(c) for c in src.iter_chunks(("torque",), chunk_samples=4096)]
...     round(src.sample_rate, 6), src.n_samples, sizes
(1000.0, 10000, [4096, 4096, 1808])
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from rollerrig.output.provenance import file_sha256
from rollerrig.recordings.channels import ChannelMap, ChannelSpec
from rollerrig.recordings.formats import open_table
from rollerrig.recordings.formats._table import Column, Slicer, Table, require_module
from rollerrig.recordings.formats.csv import unreadable
from rollerrig.recordings.formats.sniff import sniff_layout
from rollerrig.recordings.formats.timestamps import times_of_day
from rollerrig.recordings.formats.twincat import reads_as_twincat
from rollerrig.recordings.readers import (
    ChannelMapLike,
    recording_metadata,
    require_channels,
    resolve_inputs,
)
from rollerrig.recordings.recording import ChannelLookup, RecordingError
from rollerrig.recordings.translate import (
    apply_map,
    as_float,
    auto_entries,
    foreign_time,
    resolve_column,
    text_decimal,
    time_seconds,
)
from rollerrig.recordings.uniform import UNIFORM_STEP_TOLERANCE
from rollerrig.recordings.validate import (
    GAP_FACTOR,
    check_sample_rate,
    check_time_unit,
    require_two_samples,
)

__all__ = ["DEFAULT_CHUNK_SAMPLES", "Chunk", "RecordingSource", "open_recording"]

DEFAULT_CHUNK_SAMPLES = 1 << 20
"""Samples per chunk when none is given (8 MiB per float64 channel)."""

_TIME_TAIL = 16
"""Time cells of a part kept to read with the next (:func:`_time`): enough for a median step
when the parts are a sample or two long [samples]."""
_PROBE_SAMPLES = 4096
"""Samples the channel map is first applied to (columns, units, rates, notes) [samples]."""


@dataclass(frozen=True)
class Chunk(ChannelLookup):
    """Consecutive samples of a recording, in SI units.

    Attributes
    ----------
    start_index : int
        Index of the first sample in the whole recording.
    time : ndarray, shape (n,)
        Sample times [s] on the recording's clock (as :func:`read_recording` gives them).
    channels : mapping of str to ndarray, shape (n,)
        Channel values in SI units (float64).
    """

    start_index: int
    time: np.ndarray
    channels: Mapping[str, np.ndarray]
    what = "chunk"

    def __len__(self) -> int:
        return int(self.time.size)


class _Whole:
    """A :class:`Slicer` for formats without partial reads: columns loaded whole, cached."""

    def __init__(self, table: Table):
        self._table = table
        self._cols: dict[str, Column] = {}

    def _col(self, name: str) -> Column:
        if name not in self._cols:
            self._cols[name] = self._table.load(name)
        return self._cols[name]

    def slicer(self) -> Slicer:
        def read(name: str, a: int, b: int) -> Column:
            col = self._col(name)
            own = None if col.time is None else np.asarray(col.time)[a:b]
            return Column(np.asarray(col.values)[a:b], col.unit, own)

        return Slicer(length=lambda n: len(self._col(n).values), read=read)


class _TextRows:
    """Rows of a delimited text file read in blocks with :func:`pandas.read_csv` (chunksize),
    with the layout :func:`rollerrig.recordings.formats.sniff.sniff_layout` finds (the one
    :func:`read_recording` uses). Blank lines are skipped, as there; the file is re-read from the
    start only when an earlier row is asked for.
    """

    def __init__(self, layout, block: int = 1 << 16):
        from rollerrig.recordings.formats.csv import cut_last_line, footer_of

        self._layout = layout
        self._block = block
        self._n: int | None = None
        # A footer below the numbers and a last line cut by an interrupted writer are left
        # out, as read_recording leaves them.
        self._nrows, self.footer_note = footer_of(layout)
        self.cut_note = None if self.footer_note else cut_last_line(layout)
        self._reset()

    def _reader(self, source):
        pd = require_module("pandas", "CSV files")

        try:
            kwargs = self._layout.pandas_kwargs()
            # NaN words stay words here (as_float reads them): a row of only NaN words is a
            # sample, not a blank line to drop; dropped, it shifted every later sample of a
            # sample-rate map by one, and read_recording kept it
            kwargs.update(keep_default_na=False, na_values=[""])
            return pd.read_csv(
                source,
                chunksize=self._block,
                nrows=self._nrows,  # the lines above a footer (None: all)
                **kwargs,
            )
        except (ValueError, OSError) as exc:
            raise RecordingError(f"{self._layout.path}: not a readable CSV file: {exc}") from None

    def _reset(self) -> None:
        self._it = self._frames()
        self._buf = None  # DataFrame of rows [self._start, self._start + len)
        self._start = 0

    def _frames(self):
        """The file's blocks from its start (above a footer, ``footer_note``), blank lines
        dropped, and a cut last line (``cut_note``) dropped from the last block: one block is
        read ahead to know which is the last."""
        with self._layout.readable(skip_lines=True) as source:
            reader = iter(self._reader(source))
            frame = self._read_block(reader)
            while frame is not None:
                ahead = self._read_block(reader)
                if ahead is None and self.cut_note:
                    frame = frame.iloc[:-1]
                yield frame
                frame = ahead

    def _read_block(self, reader):
        pd = require_module("pandas", "CSV files")

        try:
            frame = next(reader)
        except StopIteration:
            return None
        except UnicodeDecodeError as exc:
            raise RecordingError(f"{self._layout.path}: not a readable CSV file: {exc}") from None
        except (pd.errors.ParserError, ValueError) as exc:
            raise unreadable(self._layout, exc) from None
        if self._layout.trailing:
            frame = frame.drop(columns="__trailing__")
        return frame[~frame.isna().all(axis=1)]  # blank lines

    def _next(self):
        return next(self._it, None)

    def __len__(self) -> int:
        if self._n is None:
            self._n = sum(len(frame) for frame in self._frames())
        return self._n

    def rows(self, a: int, b: int):
        pd = require_module("pandas", "CSV files")

        if a < self._start:
            self._reset()
        buf = self._buf
        while buf is None or self._start + len(buf) < b:
            frame = self._next()
            if frame is None:
                break
            buf = frame if buf is None else pd.concat([buf, frame])
            if self._start + len(buf) <= a:  # wholly before the range: drop
                self._start += len(buf)
                buf = None
        if buf is None:
            buf = pd.DataFrame(columns=list(self._layout.names))
        skip = max(0, a - self._start)
        if skip:
            buf = buf.iloc[skip:]
            self._start += skip
        self._buf = buf
        return buf.iloc[: b - a]


def _text_table(path: Path, spec) -> Table:
    """A streaming :class:`Table` of a delimited text file (columns read in blocks)."""
    from rollerrig.recordings.formats.csv import layout_table

    pd = require_module("pandas", "CSV files")

    layout = sniff_layout(path, spec)
    table = layout_table(pd.DataFrame(columns=list(layout.names)), layout)
    table.notes = list(layout.notes)
    rows = _TextRows(layout)
    for note in (rows.footer_note, rows.cut_note):
        if note:
            table.notes.append(note)
    unit_of = {n: table.load(n).unit for n in table.names}  # the empty frame: units only

    def read(name: str, a: int, b: int) -> Column:
        return Column(rows.rows(a, b)[name].to_numpy(), unit_of[name])

    table.slicer = Slicer(length=lambda n: len(rows), read=read)
    table.load = lambda n: read(n, 0, len(rows))
    return table


def _head_table(table: Table, slicer: Slicer, stop: int) -> Table:
    """``table`` whose columns are their first ``stop`` samples (own notes list)."""
    return dataclasses.replace(
        table, load=lambda n: slicer.read(n, 0, stop), notes=list(table.notes)
    )


class RecordingSource:
    """An open recording read in chunks (from :func:`open_recording`).

    Attributes
    ----------
    names : tuple of str
        Channels available (canonical names and extras), in map order.
    units : mapping of str to str
        SI unit of each channel.
    sample_rate : float
        Rate of the common time base [Hz] (median interval of the first samples).
    n_samples : int
        Samples per channel.
    duration : float
        Time from the first to the last sample [s].
    metadata : mapping
        Provenance as :func:`read_recording` gives it (``source``, ``format``, ``sha256``,
        ``channel_map``, ``columns``, ``source_units``, ``notes``, ``stored_metadata``), plus
        ``chunked`` (how the file is read).
    """

    def __init__(self, stack: contextlib.ExitStack, **state: Any):
        self._stack = stack
        self._state = state
        self.names: tuple[str, ...] = state["names"]
        self.units: Mapping[str, str] = MappingProxyType(state["units"])
        self.sample_rate: float = state["sample_rate"]
        self.n_samples: int = state["n_samples"]
        self.duration: float = state["duration"]
        self.metadata: Mapping[str, Any] = MappingProxyType(state["metadata"])

    # -- context
    def close(self) -> None:
        """Close the file."""
        self._stack.close()

    def __enter__(self) -> RecordingSource:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- reading
    def _names(self, names: Iterable[str] | None) -> tuple[str, ...]:
        if names is None:
            return self.names
        if isinstance(names, str):
            names = (names,)
        out = tuple(str(n) for n in names)
        missing = [n for n in out if n not in self.names]
        if missing:
            raise RecordingError(
                f"{self._state['where']} channel(s) {missing} not in the recording; it has "
                f"{list(self.names)}"
            )
        return out

    def read(self, names: Iterable[str] | None = None, start: int = 0, stop: int | None = None):
        """Samples ``start:stop`` of the channels ``names`` (default: all) as one :class:`Chunk`.

        Raises
        ------
        RecordingError
            A NaN/inf sample (naming the channel and the sample), a time that does not increase,
            a gap, or a channel that is not in the recording.
        """
        names = self._names(names)
        n = self.n_samples
        a = max(0, int(start))
        b = n if stop is None else min(n, int(stop))
        if b <= a:
            raise RecordingError(f"{self._state['where']} empty sample range {a}..{b}")
        return self._chunk(names, a, b, None)

    def _chunk(self, names: tuple[str, ...], a: int, b: int, t_prev: float | None) -> Chunk:
        st = self._state
        where = st["where"]
        slicer: Slicer = st["slicer"]
        channels: dict[str, np.ndarray] = {}
        first: Column | None = None
        for name in names:
            column, scale, offset, factor = st["conv"][name]
            col = slicer.read(column, a, b)
            first = first or col
            what = f"{where} column {column!r} (channel {name!r})"
            raw = as_float(col.values, what, decimal=st["decimal"], memo=st["marks"], row_offset=a)
            if raw.size != b - a:
                raise RecordingError(
                    f"{what} gave {raw.size} samples for {a}..{b}; the file is damaged"
                )
            with np.errstate(over="ignore", invalid="ignore"):  # inf is caught below, by name
                values = (scale * raw + offset) * factor
            bad = ~np.isfinite(values)
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                raise RecordingError(
                    f"{where} channel {name!r} has a NaN/inf sample at sample {a + k} "
                    f"({int(bad.sum())} in samples {a}..{b - 1}); chunked reading is strict: "
                    "read_recording(validate='lenient') interpolates short runs"
                )
            values.setflags(write=False)
            channels[name] = values
        time = _time(st, a, b, first, t_prev)
        self._check_time(time, a, t_prev)
        time.setflags(write=False)
        return Chunk(a, time, MappingProxyType(channels))

    def _check_time(self, time: np.ndarray, a: int, t_prev: float | None) -> None:
        where = self._state["where"]
        bad = ~np.isfinite(time)
        if bad.any():
            raise RecordingError(
                f"{where} time is not finite at sample {a + int(np.flatnonzero(bad)[0])}"
            )
        t = time if t_prev is None else np.concatenate([[t_prev], time])
        k0 = a if t_prev is None else a - 1
        dt = np.diff(t)
        if dt.size and np.any(dt <= 0):
            k = int(np.flatnonzero(dt <= 0)[0])
            raise RecordingError(
                f"{where} time does not increase at sample {k0 + k + 1}: "
                f"{t[k]:.9g} s -> {t[k + 1]:.9g} s; time must be strictly increasing"
            )
        step = 1.0 / self.sample_rate
        if dt.size and np.any(dt > GAP_FACTOR * step):
            k = int(np.flatnonzero(dt > GAP_FACTOR * step)[0])
            raise RecordingError(
                f"{where} gap (dropped samples) between sample {k0 + k} (t = {t[k]:.9g} s) and "
                f"{k0 + k + 1} (t = {t[k + 1]:.9g} s): {dt[k]:.6g} s at {self.sample_rate:.6g} Hz;"
                " chunked reading is strict: read_recording(validate='lenient') keeps gaps"
            )

    def iter_chunks(
        self,
        names: Iterable[str] | None = None,
        chunk_samples: int = DEFAULT_CHUNK_SAMPLES,
        *,
        start: int = 0,
        stop: int | None = None,
    ) -> Iterator[Chunk]:
        """Consecutive chunks of ``chunk_samples`` samples (the last may be shorter).

        Parameters
        ----------
        names : iterable of str, optional
            Channels to read (default: all); only their columns are read from disk.
        chunk_samples : int
            Samples per chunk [samples], >= 1.
        start, stop : int
            Sample range to read (default: the whole recording).

        Yields
        ------
        Chunk
            Time [s] and channels in SI units; concatenated, they equal what
            :func:`read_recording` gives for the same file and map.
        """
        names = self._names(names)
        if isinstance(chunk_samples, bool) or not isinstance(chunk_samples, int | np.integer):
            raise RecordingError(f"chunk_samples must be an integer, got {chunk_samples!r}")
        if chunk_samples < 1:
            raise RecordingError(f"chunk_samples must be >= 1, got {chunk_samples}")
        a = max(0, int(start))
        b = self.n_samples if stop is None else min(self.n_samples, int(stop))
        t_prev = None
        while a < b:
            e = min(b, a + int(chunk_samples))
            chunk = self._chunk(names, a, e, t_prev)
            t_prev = float(chunk.time[-1])
            yield chunk
            a = e


def _time(
    st: Mapping[str, Any], a: int, b: int, first: Column | None, t_prev: float | None = None
) -> np.ndarray:
    """Times [s] of samples ``a:b`` (``first``: a column already read for them, if any).

    Times of day are unwrapped at midnight against the file's first sample (a step back by more
    than 12 h is a new day), and against ``t_prev`` (the last time of the part before, where
    known): a part of a recording longer than 12 h was a day early. So a long recording reads
    in parts as it reads whole.

    The last cells of the part before (kept in ``st["time_tail"]``) are read with the part's
    own, so that the check for a daylight-saving step sees the step between two parts (a clock
    that went forward an hour right at a chunk's end had been read as a gap of dropped samples).
    """
    kind = st["time_kind"]
    if kind == "rate":
        return (a + np.arange(b - a)) / st["rate_stated"]
    if kind == "own":
        own = first.time if first is not None else None
        if own is None:
            own = st["slicer"].read(st["time_ref"], a, b).time
        return np.array(own, dtype=float)
    col = st["slicer"].read(st["time_column"], a, b)
    own = np.asarray(col.values)
    values = own
    before = np.asarray([], dtype=own.dtype)
    tail_end, tail = st.get("time_tail", (None, None))
    if a > 0 and tail_end == a:  # the part before, read last: its last cells are neighbours
        before = tail
    if a > 0:  # anchor timestamps / offsets on the file's first sample, as read_recording does
        values = np.concatenate([np.asarray(st["time_first"]), before, own])
    secs = time_seconds(
        values,
        st["time_unit"],
        f"{st['where']} time column {st['time_column']!r}",
        [],
        file=st["cmap"].file,
        decimal=st["decimal"],
        anchors=1 if a > 0 else 0,
        first_row=a - before.size if a > 0 else 0,
    )
    if own.size:
        kept = np.concatenate([before, own])[-_TIME_TAIL:]
        st["time_tail"] = (b, kept)
    out = np.array(secs[1 + before.size :] if a > 0 else secs, dtype=float)
    if st.get("time_of_day") and t_prev is not None and out.size:
        days = np.floor((t_prev - out[0]) / 86400.0 + 0.5)  # whole days behind the part before
        if days > 0:
            out += days * 86400.0
    return out


def _signature(table: Table, slicer: Slicer, name: str, use_own: bool) -> tuple:
    """What decides a column's time base: its length and, when used, its own first/last time."""
    n = slicer.length(name)
    if not use_own or n == 0:
        return (n, None, None)
    first = slicer.read(name, 0, 1).time
    if first is None:
        return (n, None, None)
    last = slicer.read(name, n - 1, n).time
    return (n, round(float(first[0]), 9), round(float(last[0]), 9))


def _describe(sig: tuple) -> str:
    n, t0, t1, *clock = sig
    if clock:
        return f"{n} samples on its group's time channel {clock[0]!r}"
    if t0 is None:
        return f"{n} samples"
    rate = (n - 1) / (t1 - t0) if n > 1 and t1 > t0 else float("nan")
    return f"{n} samples, {t0:.6g}..{t1:.6g} s, {rate:.6g} Hz"


def _one_time_base(
    table: Table,
    slicer: Slicer,
    cmap: ChannelMap,
    columns: Mapping[str, str],
    needed: list[str] | None,
    use_own: bool,
    where: str,
    clocks: Mapping[str, str] | None = None,
) -> tuple[ChannelMap, list[str]]:
    """The map narrowed to one time base, and the entries dropped for it.

    All ``columns`` (channel -> file column) must share one time base; with ``needed``, the
    needed ones must, and the others on another base are dropped from the map. ``clocks``:
    channel -> the time channel of its own group where that is not the time column's
    (:func:`~rollerrig.recordings.translate.foreign_time`): another time base.
    """
    clocks = clocks or {}
    sigs = {
        name: (slicer.length(col), None, None, clocks[name])
        if name in clocks
        else _signature(table, slicer, col, use_own)
        for name, col in columns.items()
    }
    if len(set(sigs.values())) <= 1:
        return cmap, []
    need = {sigs[n] for n in needed or () if n in sigs}
    if len(need) == 1 and not cmap.auto:
        dropped = sorted(n for n, sig in sigs.items() if sig not in need)
        narrowed = dataclasses.replace(
            cmap,
            channels=tuple(e for e in cmap.channels if e.name not in dropped),
            extra=tuple(e for e in cmap.extra if e.name not in dropped),
        )
        return narrowed, dropped
    shown = "; ".join(f"{n} ({columns[n]!r}): {_describe(s)}" for n, s in sigs.items())
    raise RecordingError(
        f"{where} the mapped channels have different time bases ({shown}); chunked reading "
        "needs one: use read_recording (it resamples onto a common base, [time] "
        "resample_Hz), or map (or pass channels=) only channels of one rate"
    )


def _mapped_columns(table: Table, cmap: ChannelMap, path: Path, needed) -> dict[str, str]:
    """Map entry name -> file column, for the entries read_recording would read."""
    if cmap.auto:
        return {s.name: s.column for s in auto_entries(table, cmap, path)}
    scratch = dataclasses.replace(table, notes=[])
    out = {}
    for spec in cmap.entries:
        optional = spec.optional or (needed is not None and spec.name not in needed)
        name = resolve_column(
            scratch, spec.column, spec.entry, cmap, path, skip="?" if optional else None
        )
        if name is not None:
            out[spec.name] = name
    return out


def open_recording(
    path: str | Path,
    channel_map: ChannelMapLike = None,
    *,
    format: str | None = None,
    channels: Iterable[str] | None = None,
) -> RecordingSource:
    """Open a recording for chunked reading (see the module docstring).

    Parameters
    ----------
    path : str or path-like
        The file (opened read-only; never modified).
    channel_map : ChannelMap, path, dict or None
        As for :func:`rollerrig.recordings.readers.read_recording`.
    format : str, optional
        Overrides the format implied by the suffix.
    channels : iterable of str, optional
        Channels the caller needs: a missing one is an error; map entries not needed may be
        absent (noted).

    Returns
    -------
    RecordingSource
        Use it as a context manager (it holds the file open).

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    RecordingError
        Everything :func:`read_recording` refuses, and channels on different time bases.
    """
    p, fmt, cmap, needed = resolve_inputs(path, channel_map, format, channels)
    where = f"{p}:"
    stack = contextlib.ExitStack()
    try:
        if fmt != "csv":
            table = stack.enter_context(open_table(p, fmt, cmap.file))
        elif reads_as_twincat(p, cmap.file):  # asked once: the file's head is read for it
            table = stack.enter_context(open_table(p, "twincat", cmap.file))
        else:
            table = _text_table(p, cmap.file)
        chunked = "partial reads" if table.slicer is not None else "read whole"
        slicer = table.slicer or _Whole(table).slicer()
        state = _prepare(table, slicer, cmap, p, fmt, needed, where)
        state["metadata"]["chunked"] = chunked
        if table.slicer is None:
            kind = {"mat": "MATLAB v4-v7"}.get(fmt, fmt.upper())
            state["metadata"]["notes"].append(
                f"{kind} files cannot be read in parts: the mapped columns are held in memory "
                "(for long recordings use TDMS, MDF4, Parquet, CSV or MATLAB v7.3)"
            )
        state["metadata"]["sha256"] = file_sha256(p)
    except BaseException:
        stack.close()
        raise
    return RecordingSource(stack, **state)


def _prepare(table, slicer, cmap, p, fmt, needed, where) -> dict[str, Any]:
    tspec = cmap.time
    rate_stated = getattr(tspec, "sample_rate_Hz", None)
    has_time_column = tspec is not None and tspec.column is not None
    if rate_stated is None and not has_time_column and table.stated_rate:
        rate_stated = table.stated_rate  # the file's own (an oscilloscope's 1/Increment)

    # --- one time base for the channels read (channels= narrows the map to the needed base)
    use_own = rate_stated is None and (table.own_time_exact or not has_time_column)
    columns = _mapped_columns(table, cmap, p, needed)
    clocks = {}
    if has_time_column and rate_stated is None and table.time_of:
        time_col = resolve_column(
            dataclasses.replace(table, notes=[]), tspec.column, "[time]", cmap, p
        )
        for name, col in columns.items():
            clock = foreign_time(table, col, time_col, where)
            if clock is not None:
                clocks[name] = clock
    cmap, dropped = _one_time_base(table, slicer, cmap, columns, needed, use_own, where, clocks)

    # --- the channel map, applied exactly as read_recording applies it, to the first samples
    head = _head_table(table, slicer, _PROBE_SAMPLES)
    time_h, chans_h, units, info = apply_map(head, cmap, p, needed)
    if dropped:
        head.notes.append(
            f"channels {dropped} not offered for chunked reading: on another time base than "
            f"the needed {sorted(needed or ())} (read_recording resamples them)"
        )
    n = slicer.length(info["columns"][next(iter(chans_h))])
    require_two_samples(n, where, table.notes)
    require_channels(where, needed, chans_h, cmap)
    specs = {s.name: s for s in (auto_entries(table, cmap, p) if cmap.auto else cmap.entries)}
    conv = {}
    for name in chans_h:
        spec: ChannelSpec = specs[name]
        _, factor = spec.conversion(info["source_units"][name])
        conv[name] = (info["columns"][name], spec.scale, spec.offset, factor)
    if time_h.size != min(n, _PROBE_SAMPLES):
        raise RecordingError(
            f"{where} the channels' time bases do not line up sample by sample; use read_recording"
        )

    state: dict[str, Any] = {
        "where": where,
        "slicer": slicer,
        "cmap": cmap,
        "conv": conv,
        "decimal": text_decimal(table, cmap),
        "marks": {},  # the decimal mark a column's cells decided, for all (as_float's memo)
    }
    time_column = info["columns"].get("time")
    if rate_stated is not None:
        state["time_kind"] = "rate"
        state["rate_stated"] = float(rate_stated)
    elif time_column is not None and time_column in table.names:
        state["time_kind"] = "column"
        state["time_column"] = time_column
        state["time_unit"] = info["source_units"].get("time", "s")
        state["time_first"] = np.asarray(slicer.read(time_column, 0, 1).values)
        first_cell = state["time_first"][0] if state["time_first"].size else ""
        state["time_of_day"] = state["time_first"].dtype.kind in "OUS" and times_of_day(
            first_cell, cmap.file.date_format
        )
    else:
        state["time_kind"] = "own"
        state["time_ref"] = info["columns"][next(iter(chans_h))]
    names = tuple(chans_h)
    source = dict(names=names, units=dict(units), n_samples=int(n))
    source["sample_rate"] = float(1.0 / np.median(np.diff(time_h)))
    check_sample_rate(source["sample_rate"], where, "1 / the median sample interval")
    t_last = _time(state, n - 1, n, None)
    source["duration"] = float(t_last[-1] - time_h[0])
    # The span's rate where it agrees with the median step's, as read_recording's uniform base
    # has it: stamps written with few decimals (19.2 kHz to whole µs steps by 52 and 53 µs) have
    # a median step off by the rounding (19 231 Hz); a gap moves the span's rate more, and the
    # chunks' check reports the gap.
    span_rate = (n - 1) / source["duration"] if source["duration"] > 0 else 0.0
    if abs(span_rate - source["sample_rate"]) <= UNIFORM_STEP_TOLERANCE * source["sample_rate"]:
        source["sample_rate"] = float(span_rate)
    if info.pop("time_unit_assumed", None) is not None:
        check_time_unit(source["sample_rate"], source["duration"], where, info["columns"]["time"])
    metadata = recording_metadata(
        p, fmt, cmap, head, info, validate="strict", gaps=[], interpolated=[]
    )
    return {**state, **source, "metadata": metadata}
