"""Read DAQ recordings (CSV/text, LabVIEW .lvm, Parquet, NI TDMS, ASAM MDF4, MATLAB .mat).

One entry point, :func:`read_recording`: the file's columns are translated by a channel map
(:mod:`rollerrig.measure.channels`) into canonical channels in SI units, then validated at the
boundary:

- time must be finite and strictly increasing (duplicated or backward time: an error with the
  sample index and the times);
- NaN/inf samples: ``validate="strict"`` raises, naming the channel, the count and the first run
  of bad samples; ``validate="lenient"`` linearly interpolates runs of at most
  :data:`MAX_INTERPOLATED_NAN_RUN` samples (recorded in ``metadata["interpolated"]``) and still
  raises for longer runs;
- gaps (dropped samples: an interval > :data:`GAP_FACTOR` x the median interval): strict raises
  with the gap's location and size, lenient keeps them and lists them in ``metadata["gaps"]``;
- channels the caller needs (``channels=``) must be present; map entries the caller does not
  need, and entries marked ``optional = true``, are read when present and only noted when absent.

HBM catman binary files (``.bin``) are not read: the one PyPI reader (``apread``) needs
matplotlib, OpenCV and tqdm, asks on stdin which channel is the time, and prints instead of
raising; export from catman as ASCII or ASAM MDF4 instead (the error says so).

Input files are opened read-only and never modified. The optional readers (``nptdms``,
``asammdf``, ``h5py``) are imported only when their format is read.
"""

from __future__ import annotations

import difflib
import hashlib
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rollerrig.measure.channels import (
    RATE_TOLERANCE,
    TIME_UNITS,
    ChannelMap,
    ChannelSpec,
    FileSpec,
    default_channel_map,
    load_channel_map,
    normalize_unit,
)
from rollerrig.measure.formats import Table, open_table
from rollerrig.measure.recording import CANONICAL_CHANNELS, Recording, RecordingError
from rollerrig.measure.timebase import align_channels

__all__ = [
    "FORMATS",
    "GAP_FACTOR",
    "MAX_INTERPOLATED_NAN_RUN",
    "detect_format",
    "file_sha256",
    "read_recording",
]

FORMATS: dict[str, tuple[str, ...]] = {
    "csv": (".csv", ".txt", ".tsv"),
    "lvm": (".lvm",),
    "parquet": (".parquet", ".pq"),
    "tdms": (".tdms",),
    "mf4": (".mf4", ".mdf"),
    "mat": (".mat",),
}
"""Format name -> file suffixes."""

_FORMAT_ALIASES = {"mdf": "mf4", "mdf4": "mf4", "pq": "parquet", "txt": "csv", "tsv": "csv"}

_NOT_READ = {
    ".bin": (
        "HBM catman binary files (.bin) are not read (the only PyPI reader, apread, prompts on "
        "stdin and pulls in matplotlib/OpenCV); in catman export the measurement as ASCII "
        "(tab-separated, with channel names and units: read it with format='csv', or rename "
        "it to .csv) or as ASAM MDF4 (.mf4), and read that file"
    ),
    ".tdm": ("NI DIAdem TDM headers (.tdm + .tdx) are not read; export as TDMS or CSV from DIAdem"),
}

MAX_INTERPOLATED_NAN_RUN = 3
"""Longest run of NaN/inf samples that ``validate="lenient"`` interpolates [samples]."""

GAP_FACTOR = 1.5
"""A sample interval longer than this multiple of the median interval is a gap."""


def detect_format(path: str | Path, format: str | None = None) -> str:
    """Format name of ``path`` (one of :data:`FORMATS`) from ``format`` or the file suffix.

    Examples
    --------
    >>> detect_format("run.MF4"), detect_format("x.dat", format="csv")
    ('mf4', 'csv')
    """
    if format is not None:
        f = _FORMAT_ALIASES.get(format.lower().lstrip("."), format.lower().lstrip("."))
        if f not in FORMATS:
            raise RecordingError(
                f"{path}: unsupported format {format!r}; supported: {list(FORMATS)}"
            )
        return f
    suffix = Path(path).suffix.lower()
    for name, suffixes in FORMATS.items():
        if suffix in suffixes:
            return name
    if suffix in _NOT_READ:
        raise RecordingError(f"{path}: {_NOT_READ[suffix]}")
    raise RecordingError(
        f"{path}: unsupported file suffix {suffix!r}; supported: "
        f"{[s for ss in FORMATS.values() for s in ss]} (or pass format=)"
    )


def file_sha256(path: str | Path) -> str:
    """SHA-256 hex digest of a file (read-only, in chunks)."""
    h = hashlib.sha256()
    with Path(path).open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


# ---------------------------------------------------------------------------------------------
# Channel map -> SI channels


def _resolve(
    table: Table,
    column: str,
    entry: str,
    cmap: ChannelMap,
    path: Path,
    *,
    skip: str | None = None,
) -> str | None:
    """The file column that ``column`` names; missing or ambiguous: an error with close matches.

    With ``skip`` (why the entry may be absent, e.g. ``"optional"``), a missing or ambiguous
    column is noted in ``table.notes`` instead, and None is returned.
    """
    if column in table.names:
        return column
    candidates = table.aliases.get(column, [])
    if len(candidates) == 1:
        return candidates[0]
    pool = table.names + [a for a in table.aliases if a not in table.names]
    close = difflib.get_close_matches(column, pool, n=3, cutoff=0.6)
    if skip is not None:
        problem = f"ambiguous: {candidates}" if candidates else "not in the file"
        table.notes.append(
            f"channel map entry {entry} ({skip}) not read: column {column!r} is {problem}"
            + (f"; close matches: {close}" if close and not candidates else "")
        )
        return None
    if len(candidates) > 1:
        raise RecordingError(
            f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, "
            f"which is ambiguous in the file: {candidates}; give the full name"
        )
    shown = table.names if len(table.names) <= 60 else [*table.names[:60], "..."]
    raise RecordingError(
        f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, "
        f"which is not in the file"
        + (f"; close matches: {close}" if close else "")
        + f"; available columns: {shown}"
        + (f"; not readable: {table.skipped}" if table.skipped else "")
    )


def _as_float(values: np.ndarray, what: str, line_of=None) -> np.ndarray:
    """Numbers of a column; NaN/inf words (``NaN``, ``inf``, PicoScope's ``∞``) become NaN/inf.

    ``line_of`` maps a row to its 1-based file line (text files) for the error message.
    """
    arr = np.asarray(values)
    if arr.dtype.kind in "biuf":
        return arr.astype(float)
    if arr.dtype.kind in "OUT":
        import pandas as pd

        from rollerrig.measure.formats.csv import NAN_WORDS

        text = pd.Series(arr, dtype=object).map(lambda v: v.strip() if isinstance(v, str) else v)
        is_str = text.map(lambda v: isinstance(v, str)).to_numpy(dtype=bool)
        words = text.map(lambda v: v.lower() if isinstance(v, str) else "").to_numpy(dtype=object)
        infinite = np.isin(words, ["∞", "+∞", "inf", "+inf", "infinity", "+infinity"])
        neg_inf = np.isin(words, ["-∞", "-inf", "-infinity"])
        comma = text.map(
            lambda v: v.replace(",", ".") if isinstance(v, str) and _COMMA_NUM.fullmatch(v) else v
        )
        num = pd.to_numeric(comma, errors="coerce").to_numpy(dtype=float, copy=True)
        num[infinite] = np.inf
        num[neg_inf] = -np.inf
        known = np.isin(words, list(NAN_WORDS)) | (is_str & (words == ""))
        bad = np.isnan(num) & ~pd.isna(text).to_numpy() & ~known
        if not bad.any():
            return num
        k = int(np.flatnonzero(bad)[0])
        line = line_of(k) if line_of is not None else None
        raise RecordingError(
            f"{what} has {int(bad.sum())} non-numeric entries, first at row {k}: {arr[k]!r}"
            + (f" (file line {line})" if line is not None else "")
        )
    raise RecordingError(f"{what} is not numeric (dtype {arr.dtype})")


_COMMA_NUM = re.compile(r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?")


def _time_seconds(
    values: np.ndarray,
    unit: str,
    what: str,
    notes: list,
    *,
    file: FileSpec | None = None,
    line_of=None,
    decided: dict | None = None,
) -> np.ndarray:
    """A time column in seconds: numbers in ``unit``, or date/time strings (one format for the
    whole column, from ``[file] date_format`` / ``dayfirst``; see
    :func:`rollerrig.measure.formats.csv.parse_timestamps`) as seconds since the first sample.

    ``decided``: for a column read in chunks, one dict passed with every chunk, so that every
    chunk's timestamps are read in the format decided for the first."""
    from rollerrig.measure.formats.csv import looks_like_timestamp, parse_timestamps

    file = file or FileSpec()
    arr = np.asarray(values)
    if arr.dtype.kind in "OUT":
        first = next((str(v).strip() for v in arr.ravel()[:1000] if str(v).strip()), "")
        if file.date_format is not None or looks_like_timestamp(first):
            secs, note = parse_timestamps(
                arr,
                what=what,
                dayfirst=file.dayfirst,
                date_format=file.date_format,
                line_of=line_of,
                decided=decided,
            )
            notes.append(note)
            return secs
        return _as_float(arr, what, line_of) * TIME_UNITS[unit]
    if arr.dtype.kind == "M":
        t0 = arr[0]
        notes.append(f"absolute timestamps converted to seconds since the first sample ({t0})")
        return (arr - t0) / np.timedelta64(1, "s")
    return _as_float(arr, what) * TIME_UNITS[unit]


def _auto_entries(table: Table, cmap: ChannelMap, path: Path) -> list[ChannelSpec]:
    specs: list[ChannelSpec] = []
    seen: dict[str, str] = {}
    for name in table.names:
        base = table.base.get(name, name)
        if base == "time":
            continue
        canonical = base in CANONICAL_CHANNELS
        if base in seen:
            if canonical:
                raise RecordingError(
                    f"{path}: canonical channel {base!r} occurs twice ({seen[base]!r}, {name!r}); "
                    "give a channel map"
                )
            continue
        seen[base] = name
        specs.append(ChannelSpec(base, name, None, canonical=canonical))
    return specs


_TIME_NAMES = frozenset(
    {"time", "zeit", "t", "x_value", "timestamp", "timestamps", "time_s", "time_ms", "datetime"}
)
"""Column names (lower case, unit stripped) taken as a time column when checking a stated rate."""


def _check_stated_rate(table: Table, cmap: ChannelMap, loaded: list, info: dict, path, line_of):
    """Raise when the map's ``[time] sample_rate_Hz`` contradicts the file's own rate.

    The file's rate is that of each channel's own time base (TDMS ``wf_increment``, MDF master,
    LVM X column) and of a column named like a time (``Time``, ``Zeit``, ``t``, ``X_Value``;
    numbers in its stated unit, else seconds or milliseconds, or timestamps). A difference of
    more than :data:`~rollerrig.measure.channels.RATE_TOLERANCE` is an error naming both rates.
    """
    stated = cmap.time.sample_rate_Hz

    def off(rate: float) -> bool:
        return not np.isfinite(rate) or abs(rate - stated) > RATE_TOLERANCE * stated

    def fail(rate: float, source: str) -> None:
        raise RecordingError(
            f"{path}: the channel map's [time] sample_rate_Hz = {stated:g} Hz (map "
            f"{cmap.source}) contradicts the file's own rate of {rate:.6g} Hz ({source}); "
            "remove sample_rate_Hz to use the file's time base, or correct it"
        )

    def median_rate(t: np.ndarray) -> float:
        d = np.diff(t)
        d = d[np.isfinite(d)]
        med = float(np.median(d)) if d.size else 0.0
        return 1.0 / med if med > 0 else float("nan")

    for spec, _values, _si, own in loaded:
        if own is not None and own.size > 1:
            rate = median_rate(np.asarray(own, dtype=float))
            if off(rate):
                fail(rate, f"time base of column {info['columns'][spec.name]!r}")
    used = set(info["columns"].values())
    for name in table.names:
        base = str(table.base.get(name, name)).strip().lower()
        if name in used or base not in _TIME_NAMES:
            continue
        try:
            col = table.load(name)
            file_unit = normalize_unit(col.unit) if col.unit else None
            scratch: list[str] = []
            unit = file_unit if file_unit in TIME_UNITS else "s"
            secs = _time_seconds(
                col.values,
                unit,
                f"{path}: column {name!r}",
                scratch,
                file=cmap.file,
                line_of=line_of,
            )
        except RecordingError:
            table.notes.append(
                f"column {name!r} looks like a time column but is not readable; "
                "the stated sample_rate_Hz was not checked against it"
            )
            continue
        if secs.size < 2:
            continue
        rate = median_rate(secs)
        numeric = np.asarray(col.values).dtype.kind in "biuf"
        if off(rate) and not (numeric and file_unit is None and not off(rate * 1e3)):
            fail(rate, f"column {name!r}" + ("" if file_unit or not numeric else " read in s"))


def _apply_map(
    table: Table, cmap: ChannelMap, path: Path, needed: Iterable[str] | None = None
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, str], dict[str, Any]]:
    """Time [s] and channels in SI units from a table through the channel map.

    ``needed``: the channels the caller needs; entries not needed, and ``optional`` ones, are
    noted instead of failing when their column is missing (None: every entry is needed).
    """
    notes = table.notes
    info: dict[str, Any] = {"columns": {}, "source_units": {}}
    where = f"{path}:"
    needed = None if needed is None else set(needed)
    line_of = getattr(table, "line_of", None)  # text files: row -> file line

    # --- time from a column
    time = None
    tspec = cmap.time
    if tspec is not None and tspec.column is not None:
        col_name = None
        if cmap.auto:
            hits = [n for n in table.names if table.base.get(n, n) == tspec.column]
            col_name = hits[0] if hits else None
        else:
            col_name = _resolve(table, tspec.column, "[time]", cmap, path)
        if col_name is not None:
            col = table.load(col_name)
            unit = tspec.unit
            file_unit = normalize_unit(col.unit) if col.unit else None
            if cmap.auto and file_unit is not None:
                if file_unit not in TIME_UNITS:
                    raise RecordingError(
                        f"{where} time column {col_name!r} has unit {col.unit!r}; "
                        f"allowed: {sorted(TIME_UNITS)}"
                    )
                unit = file_unit
            elif file_unit in TIME_UNITS and file_unit != unit:
                if tspec.unit_stated:
                    raise RecordingError(
                        f"{where} channel map entry [time] (map {cmap.source}) says unit "
                        f"{unit!r} but column {col_name!r} says {col.unit!r}"
                    )
                unit = file_unit
                notes.append(f"time unit {col.unit!r} taken from the file (the map gives none)")
            time = _time_seconds(
                col.values,
                unit,
                f"{where} time column {col_name!r}",
                notes,
                file=cmap.file,
                line_of=line_of,
            )
            info["columns"]["time"] = col_name
            info["source_units"]["time"] = unit

    # --- channels
    specs = _auto_entries(table, cmap, path) if cmap.auto else list(cmap.entries)
    loaded: list[tuple[ChannelSpec, np.ndarray, str, np.ndarray | None]] = []
    for spec in specs:
        skip = None
        if cmap.auto:
            name = spec.column
        else:
            skip = (
                "optional"
                if spec.optional and (needed is None or spec.name not in needed)
                else "not needed here"
                if needed is not None and spec.name not in needed
                else None
            )
            name = _resolve(table, spec.column, spec.entry, cmap, path, skip=skip)
            if name is None:
                continue
            if skip is not None:  # present but unreadable (e.g. an MDF group without samples)
                try:
                    col = table.load(name)
                except RecordingError as exc:
                    notes.append(
                        f"channel map entry {spec.entry} ({skip}) not read: "
                        + str(exc).removeprefix(where).strip()
                    )
                    continue
        if skip is None:
            col = table.load(name)
        what = f"{where} column {name!r} (channel map entry {spec.entry}, map {cmap.source})"
        if cmap.auto and not spec.canonical:
            if col.unit is None or np.asarray(col.values).dtype.kind not in "biuf":
                notes.append(f"column {name!r} not read (no unit or not numeric)")
                continue
        if spec.unit is None and col.unit is None:
            raise RecordingError(
                f"{what}: no unit in the channel map nor in the file; "
                f"give 'unit' (SI unit {CANONICAL_CHANNELS.get(spec.name, ('?',))[0]!r})"
            )
        unit = spec.unit if spec.unit is not None else col.unit
        try:
            si, factor = spec.conversion(unit)
        except RecordingError as exc:
            raise RecordingError(f"{what}: {exc}") from None
        if spec.unit is not None and col.unit is not None and spec.canonical:
            if normalize_unit(col.unit) != normalize_unit(spec.unit):
                try:
                    _, file_factor = spec.conversion(col.unit)
                except RecordingError:
                    file_factor = None
                if file_factor is not None and spec.scale == 1.0 and spec.offset == 0.0:
                    raise RecordingError(
                        f"{what}: the map says unit {spec.unit!r} but the file says "
                        f"{col.unit!r}; fix the map (or give scale/offset)"
                    )
                notes.append(
                    f"{spec.name}: file unit {col.unit!r}, map unit {spec.unit!r} used "
                    f"(scale {spec.scale}, offset {spec.offset})"
                )
        raw = _as_float(col.values, what, line_of)
        # A corrupted or absurd raw value may overflow to inf here: validation then names the
        # channel and the samples; numpy's overflow warning would only say "multiply".
        with np.errstate(over="ignore", invalid="ignore"):
            values = (spec.scale * raw + spec.offset) * factor
        own = None if col.time is None else np.asarray(col.time, dtype=float)
        loaded.append((spec, values, si, own))
        info["columns"][spec.name] = name
        info["source_units"][spec.name] = unit

    if not loaded:
        raise RecordingError(
            f"{where} no channels found (map {cmap.source}); file columns: {table.names[:60]}"
        )

    # --- time from the sample rate or from the first channel's own time base
    _, first_values, _, first_own = loaded[0]
    if time is None and tspec is not None and tspec.sample_rate_Hz is not None:
        _check_stated_rate(table, cmap, loaded, info, path, line_of)
        time = np.arange(first_values.size) / tspec.sample_rate_Hz
        info["source_units"]["time"] = f"sample_rate_Hz = {tspec.sample_rate_Hz}"
        own_times: list = [None] * len(loaded)
    elif time is None:
        if first_own is None:
            raise RecordingError(
                f"{where} no time: the channel map (map {cmap.source}) gives no [time] column "
                "nor sample_rate_Hz, and the file's channels carry no time base "
                "(TDMS wf_increment / MDF master)"
            )
        # time stays None: align_channels chooses the common base from the own time bases
        own_times = [own for _, _, _, own in loaded]
    else:
        own_times = [own for _, _, _, own in loaded]

    time, channels, units = align_channels(
        time,
        loaded,
        own_times,
        own_time_exact=table.own_time_exact,
        info=info,
        notes=notes,
        where=where,
        resample_Hz=getattr(tspec, "resample_Hz", None),
    )
    return np.asarray(time, dtype=float), channels, units, info


# ---------------------------------------------------------------------------------------------
# Validation at the boundary


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample index of each run of True in ``mask``."""
    if not mask.any():
        return []
    d = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    return list(zip(starts.tolist(), ends.tolist(), strict=True))


def _validate(
    time: np.ndarray, channels: dict[str, np.ndarray], mode: str, where: str
) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    report: dict[str, Any] = {"gaps": [], "interpolated": []}
    if time.size < 2:
        raise RecordingError(f"{where} only {time.size} sample(s); need at least 2")
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
        )
    median = float(np.median(dt))
    gap_idx = np.flatnonzero(dt > GAP_FACTOR * median)
    gaps = [
        {
            "sample": int(k),
            "start_s": float(time[k]),
            "end_s": float(time[k + 1]),
            "duration_s": float(dt[k]),
            "missing_samples": round(float(dt[k]) / median) - 1,
        }
        for k in gap_idx
    ]
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
        v = np.asarray(values, dtype=float)
        bad = ~np.isfinite(v)
        if not bad.any():
            out[name] = v
            continue
        runs = _runs(bad)
        longest = max(runs, key=lambda r: r[1] - r[0])
        first = runs[0]

        def describe(run: tuple[int, int]) -> str:
            a, b = run
            return f"samples {a}..{b} (t = {time[a]:.9g} s .. {time[b]:.9g} s, {b - a + 1} samples)"

        if mode == "strict" or bad.all():
            raise RecordingError(
                f"{where} channel {name!r} has {int(bad.sum())} NaN/inf samples in {len(runs)} "
                f"run(s); first run: {describe(first)}"
                + ("" if mode == "strict" else "; every sample is bad")
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
                f"(more than {MAX_INTERPOLATED_NAN_RUN}): {describe(longest)}"
            )
        good = ~bad
        v = v.copy()
        v[bad] = np.interp(time[bad], time[good], v[good])
        for a, b in runs:
            report["interpolated"].append(
                {
                    "channel": name,
                    "first_sample": a,
                    "last_sample": b,
                    "start_s": float(time[a]),
                    "end_s": float(time[b]),
                    "method": "linear" if a > 0 and b < v.size - 1 else "held (edge)",
                }
            )
        out[name] = v
    return out, report


# ---------------------------------------------------------------------------------------------


def _as_channel_map(channel_map) -> ChannelMap:
    if channel_map is None:
        return default_channel_map()
    if isinstance(channel_map, ChannelMap):
        return channel_map
    if isinstance(channel_map, str | Path):
        return load_channel_map(channel_map)
    if isinstance(channel_map, Mapping):
        return ChannelMap.from_dict(channel_map)
    raise TypeError(
        f"channel_map must be a ChannelMap, a path, a dict or None, got {type(channel_map)}"
    )


def read_recording(
    path: str | Path,
    channel_map: ChannelMap | str | Path | Mapping[str, Any] | None = None,
    *,
    format: str | None = None,
    validate: Literal["strict", "lenient"] = "strict",
    channels: Iterable[str] | None = None,
) -> Recording:
    """Read a DAQ file into a validated :class:`Recording` in SI units.

    Parameters
    ----------
    path : str or path-like
        The file (opened read-only; never modified).
    channel_map : ChannelMap, path, dict or None
        Which column is which canonical channel, in which unit. None: the file was written by
        rollerrig (:func:`rollerrig.measure.channels.default_channel_map`: canonical names as
        columns, units in headers such as ``torque [N.m]`` or stored in the file).
    format : {"csv", "lvm", "parquet", "tdms", "mf4", "mdf", "mat"}, optional
        Overrides the format implied by the suffix (``.csv``/``.txt``/``.tsv``: text, read as the
        map's ``[file]`` section says or sniffed; ``.lvm``: LabVIEW Measurement).
    validate : {"strict", "lenient"}
        Strict: any NaN/inf sample or gap is an error. Lenient: NaN/inf runs of at most
        :data:`MAX_INTERPOLATED_NAN_RUN` samples are interpolated, gaps are kept; both are
        listed in the metadata.
    channels : iterable of str, optional
        Channels the caller needs; a missing one is an error naming it (and, when the map has an
        entry for it, the column with close matches). Map entries not in ``channels`` are read
        when their column is present and only noted in ``metadata["notes"]`` when it is not
        (as are entries with ``optional = true``). None: every map entry is needed.

    Returns
    -------
    Recording
        Time [s] and channels in SI units; ``metadata`` holds ``source``, ``format``,
        ``sha256``, ``channel_map``, ``columns`` (channel -> file column), ``source_units``,
        ``validate``, ``gaps``, ``interpolated``, ``notes``, ``resampled`` (when channels of
        different rasters were put on one time base), and ``stored_metadata`` (provenance that
        rollerrig's writers stored in the file).

    Raises
    ------
    FileNotFoundError
        The file (or the channel map file) does not exist.
    RecordingError
        Unsupported format, unreadable file, missing or ambiguous column (with close matches),
        unknown unit, bad time, NaN/inf, gaps (strict), missing required channels.
    ImportError
        The optional reader for the format is not installed (``rollerrig[io]``).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "run.csv").write_text("t_ms,n_roller\\n0,60\\n4,60\\n8,60\\n")
    >>> rec = read_recording(d / "run.csv", {"time": {"column": "t_ms", "unit": "ms"},
    ...     "channels": {"roller_speed": {"column": "n_roller", "unit": "rpm"}}})
    >>> rec.time.tolist(), rec["roller_speed"].round(4).tolist()
    ([0.0, 0.004, 0.008], [6.2832, 6.2832, 6.2832])
    """
    p = Path(path)
    if validate not in ("strict", "lenient"):
        raise RecordingError(f"validate must be 'strict' or 'lenient', got {validate!r}")
    fmt = detect_format(p, format)
    cmap = _as_channel_map(channel_map)
    if not p.is_file():
        raise FileNotFoundError(f"recording file not found: {p}")
    sha = file_sha256(p)
    where = f"{p}:"
    required = None if channels is None else [str(c) for c in channels]
    with open_table(p, fmt, cmap.file) as table:
        time, chans, units, info = _apply_map(table, cmap, p, required)
        notes = table.notes
        stored = table.stored_metadata
    missing = [c for c in required or () if c not in chans]
    if missing:
        raise RecordingError(
            f"{where} required channel(s) {missing} not in the recording (map {cmap.source} "
            f"gives {sorted(chans)}); add [channels.<name>] entries for them"
        )
    chans, report = _validate(time, chans, validate, where)
    metadata: dict[str, Any] = {
        "source": str(p.resolve()),
        "format": fmt,
        "sha256": sha,
        "size_bytes": p.stat().st_size,
        "channel_map": cmap.to_dict(),
        "validate": validate,
        **info,
        "gaps": report["gaps"],
        "interpolated": report["interpolated"],
        "notes": list(notes),
    }
    if report["interpolated"]:
        metadata["notes"].append(
            f"{len(report['interpolated'])} short NaN/inf run(s) interpolated (lenient)"
        )
    if report["gaps"]:
        metadata["notes"].append(f"{len(report['gaps'])} gap(s) kept (lenient)")
    if stored is not None:
        metadata["stored_metadata"] = stored
    return Recording(time, chans, units, metadata)
