"""Read DAQ recordings (CSV, Parquet, NI TDMS, ASAM MDF4, MATLAB .mat) into :class:`Recording`.

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
- channels the caller needs (``channels=``) must be present.

Input files are opened read-only and never modified. The optional readers (``nptdms``,
``asammdf``, ``pymatreader``) are imported only when their format is read.
"""

from __future__ import annotations

import contextlib
import difflib
import hashlib
import importlib
import json
import re
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rollerrig.measure.channels import (
    TIME_UNITS,
    ChannelMap,
    ChannelSpec,
    default_channel_map,
    load_channel_map,
    normalize_unit,
    split_unit_header,
)
from rollerrig.measure.recording import CANONICAL_CHANNELS, Recording, RecordingError

__all__ = [
    "FORMATS",
    "GAP_FACTOR",
    "MAX_INTERPOLATED_NAN_RUN",
    "detect_format",
    "file_sha256",
    "read_recording",
]

FORMATS: dict[str, tuple[str, ...]] = {
    "csv": (".csv",),
    "parquet": (".parquet", ".pq"),
    "tdms": (".tdms",),
    "mf4": (".mf4", ".mdf"),
    "mat": (".mat",),
}
"""Format name -> file suffixes."""

_FORMAT_ALIASES = {"mdf": "mf4", "mdf4": "mf4", "pq": "parquet"}

MAX_INTERPOLATED_NAN_RUN = 3
"""Longest run of NaN/inf samples that ``validate="lenient"`` interpolates [samples]."""

GAP_FACTOR = 1.5
"""A sample interval longer than this multiple of the median interval is a gap."""

_META_KEY = "rollerrig_metadata"
_UNITS_KEY = "rollerrig_units"


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


def _require(module: str, what: str):
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(
            f"reading {what} needs the optional package {module!r}: install rollerrig[io] "
            "(pip install 'rollerrig[io]')"
        ) from exc


# ---------------------------------------------------------------------------------------------
# A file as a table of columns


@dataclass
class _Column:
    values: np.ndarray
    unit: str | None = None
    time: np.ndarray | None = None  # the column's own time base [s] (TDMS waveform, MDF master)


@dataclass
class _Table:
    names: list[str]
    load: Callable[[str], _Column]
    base: dict[str, str] = field(default_factory=dict)  # name -> short name (no group / unit)
    aliases: dict[str, list[str]] = field(default_factory=dict)  # other spelling -> names
    notes: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    stored_metadata: Any = None
    own_time_exact: bool = False  # own time bases beat index alignment (MDF masters)


def _add_alias(table: _Table, alias: str, name: str) -> None:
    if alias != name:
        table.aliases.setdefault(alias, []).append(name)


def _header_table(frame, *, units: Mapping[str, str] | None = None) -> _Table:
    """Table over a pandas DataFrame whose headers may carry ``[unit]``."""
    names = [str(c) for c in frame.columns]
    header_units: dict[str, str | None] = {}
    table = _Table(names=names, load=lambda n: None)  # type: ignore[arg-type,return-value]
    for name in names:
        base, unit = split_unit_header(name)
        header_units[name] = unit
        table.base[name] = base
        _add_alias(table, base, name)
    stored = dict(units or {})

    def load(name: str) -> _Column:
        base = table.base[name]
        unit = header_units[name] or stored.get(name) or stored.get(base)
        return _Column(frame[name].to_numpy(), unit)

    table.load = load
    return table


def _read_csv(path: Path) -> _Table:
    import pandas as pd

    notes = []
    encoding = "utf-8-sig"
    try:
        head = path.read_bytes()[:65536].decode(encoding)
    except UnicodeDecodeError:
        encoding = "latin-1"
        head = path.read_bytes()[:65536].decode(encoding)
        notes.append("CSV is not UTF-8; read as Latin-1")
    lines = [ln for ln in head.splitlines() if ln.strip()]
    if not lines:
        raise RecordingError(f"{path}: the CSV file is empty")
    sep = max([",", ";", "\t"], key=lambda s: lines[0].count(s))
    decimal = "."
    if sep != "," and len(lines) > 1 and re.search(r"\d,\d", lines[1]):
        decimal = ","
        notes.append("CSV uses decimal commas")
    try:
        frame = pd.read_csv(path, sep=sep, decimal=decimal, encoding=encoding)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError) as exc:
        raise RecordingError(f"{path}: not a readable CSV file: {exc}") from exc
    table = _header_table(frame)
    table.notes += notes
    sidecar = path.with_suffix(".metadata.json")
    if sidecar.is_file():
        try:
            table.stored_metadata = json.loads(sidecar.read_text(encoding="utf-8"))
            table.notes.append(f"provenance read from {sidecar.name}")
        except json.JSONDecodeError:
            table.notes.append(f"sidecar {sidecar.name} is not valid JSON; ignored")
    return table


def _read_parquet(path: Path) -> _Table:
    import pyarrow.parquet as pq

    try:
        arrow = pq.read_table(path)
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable Parquet file: {exc}") from exc
    units: dict[str, str] = {}
    for f in arrow.schema:
        if f.metadata and b"unit" in f.metadata:
            units[f.name] = f.metadata[b"unit"].decode()
    stored = None
    meta = arrow.schema.metadata or {}
    if b"rollerrig" in meta:
        blob = json.loads(meta[b"rollerrig"])
        units = {**blob.get("units", {}), **units}
        stored = blob.get("metadata")
    table = _header_table(arrow.to_pandas(), units=units)
    table.stored_metadata = stored
    return table


@contextlib.contextmanager
def _open_tdms(path: Path) -> Iterator[_Table]:
    nptdms = _require("nptdms", "TDMS files")
    try:
        tdms = nptdms.TdmsFile.read(str(path))
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable TDMS file: {exc}") from exc
    chans = {}
    table = _Table(names=[], load=lambda n: None)  # type: ignore[arg-type,return-value]
    for group in tdms.groups():
        for ch in group.channels():
            name = f"{group.name}/{ch.name}"
            chans[name] = ch
            table.names.append(name)
            table.base[name] = ch.name
            _add_alias(table, ch.name, name)
            _add_alias(table, ch.path, name)

    def load(name: str) -> _Column:
        ch = chans[name]
        values = ch[:]
        props = ch.properties
        own = None
        if "wf_increment" in props and float(props["wf_increment"]) > 0:
            inc = float(props["wf_increment"])
            own = float(props.get("wf_start_offset", 0.0)) + np.arange(len(values)) * inc
        unit = props.get("unit_string") or None
        return _Column(np.asarray(values), unit, own)

    table.load = load
    raw = tdms.properties.get(_META_KEY)
    if raw:
        with contextlib.suppress(json.JSONDecodeError, TypeError):
            table.stored_metadata = json.loads(raw)
    yield table


def _hd_comment_text(comment: str) -> str:
    try:
        root = ET.fromstring(comment)
    except ET.ParseError:
        return comment
    tx = root.find("TX")
    return tx.text if tx is not None and tx.text else comment


@contextlib.contextmanager
def _open_mdf(path: Path) -> Iterator[_Table]:
    asammdf = _require("asammdf", "MDF4 files")
    try:
        mdf = asammdf.MDF(str(path))
    except Exception as exc:
        raise RecordingError(f"{path}: not a readable MDF file: {exc}") from exc
    try:
        db = mdf.channels_db
        table = _Table(names=list(db), load=lambda n: None)  # type: ignore[arg-type,return-value]
        for name in table.names:
            table.base[name] = name

        def load(name: str) -> _Column:
            occurrences = db[name]
            group, index = occurrences[0]
            if len(occurrences) > 1:
                table.notes.append(
                    f"MDF channel {name!r} occurs {len(occurrences)} times; "
                    f"the one in data group {group} was read"
                )
            sig = mdf.get(name, group=group, index=index)
            return _Column(
                np.asarray(sig.samples), sig.unit or None, np.asarray(sig.timestamps, dtype=float)
            )

        table.load = load
        table.own_time_exact = True
        comment = getattr(mdf.header, "comment", "") or ""
        if comment:
            with contextlib.suppress(json.JSONDecodeError, TypeError):
                table.stored_metadata = json.loads(_hd_comment_text(comment))
        yield table
    finally:
        mdf.close()


def _flatten_mat(data: Mapping[str, Any], prefix: str, out: dict, skipped: list) -> None:
    for key, value in data.items():
        if key.startswith("__") or key.startswith("#"):
            continue
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            _flatten_mat(value, f"{name}.", out, skipped)
        elif isinstance(value, str):
            out[name] = value
        else:
            arr = np.asarray(value)
            if arr.dtype.kind in "biuf" and arr.size >= 1:
                squeezed = arr.reshape(-1) if arr.ndim <= 1 or max(arr.shape) == arr.size else arr
                if squeezed.ndim == 1:
                    out[name] = squeezed
                    continue
            skipped.append(f"{name} ({arr.dtype}, shape {arr.shape})")


def _is_hdf5(path: Path) -> bool:
    signature = b"\x89HDF\r\n\x1a\n"
    with path.open("rb") as fh:
        for offset in (0, 512, 1024, 2048):
            fh.seek(offset)
            if fh.read(8) == signature:
                return True
    return False


def _read_plain_hdf5(path: Path) -> dict[str, Any]:
    """Datasets of an HDF5 file as nested dicts (MATLAB layout: char as uint16 text)."""
    h5py = _require("h5py", "HDF5 .mat files")

    def walk(group) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for key, item in group.items():
            if isinstance(item, h5py.Group):
                out[key] = walk(item)
                continue
            value = item[()]
            cls = item.attrs.get("MATLAB_class", b"")
            cls = cls.decode() if isinstance(cls, bytes) else str(cls)
            if cls == "char":
                out[key] = np.asarray(value, dtype=np.uint16).T.tobytes().decode("utf-16-le")
            else:
                out[key] = np.asarray(value)
        return out

    try:
        with h5py.File(path, "r") as f:
            return walk(f)
    except OSError as exc:
        raise RecordingError(f"{path}: not a readable HDF5 file: {exc}") from exc


def _read_mat(path: Path) -> _Table:
    from scipy.io import loadmat
    from scipy.io.matlab import matfile_version

    notes = []
    try:
        major, _ = matfile_version(str(path))
    except Exception as exc:
        if not _is_hdf5(path):
            raise RecordingError(f"{path}: not a MATLAB .mat file: {exc}") from exc
        major = -1  # HDF5 without the MATLAB header (written by h5py or other tools)
    if major == -1:
        data = _read_plain_hdf5(path)
        notes.append("HDF5 file without a MATLAB header read with h5py")
    elif major == 2:  # v7.3 = HDF5
        pymatreader = _require("pymatreader", "MATLAB v7.3 files")
        try:
            data = pymatreader.read_mat(str(path))
        except Exception as exc:
            raise RecordingError(f"{path}: not a readable MATLAB v7.3 file: {exc}") from exc
        notes.append("MATLAB v7.3 (HDF5) read with pymatreader")
    else:
        try:
            data = loadmat(str(path), squeeze_me=True, simplify_cells=True)
        except Exception as exc:
            raise RecordingError(f"{path}: not a readable MATLAB file: {exc}") from exc
    flat: dict[str, Any] = {}
    skipped: list[str] = []
    _flatten_mat(data, "", flat, skipped)
    stored = None
    units: dict[str, str] = {}
    if isinstance(flat.get(_META_KEY), str):
        with contextlib.suppress(json.JSONDecodeError):
            stored = json.loads(flat[_META_KEY])
    if isinstance(flat.get(_UNITS_KEY), str):
        with contextlib.suppress(json.JSONDecodeError):
            units = json.loads(flat[_UNITS_KEY])
    columns = {k: v for k, v in flat.items() if not isinstance(v, str)}
    table = _Table(
        names=list(columns),
        load=lambda n: _Column(columns[n], units.get(n)),
        base={n: n for n in columns},
        notes=notes,
        skipped=skipped,
        stored_metadata=stored,
    )
    if skipped:
        table.notes.append(f"MAT variables not read (not numeric vectors): {skipped}")
    return table


@contextlib.contextmanager
def _open_table(path: Path, fmt: str) -> Iterator[_Table]:
    if fmt == "csv":
        yield _read_csv(path)
    elif fmt == "parquet":
        yield _read_parquet(path)
    elif fmt == "mat":
        yield _read_mat(path)
    elif fmt == "tdms":
        with _open_tdms(path) as t:
            yield t
    else:
        with _open_mdf(path) as t:
            yield t


# ---------------------------------------------------------------------------------------------
# Channel map -> SI channels


def _resolve(table: _Table, column: str, entry: str, cmap: ChannelMap, path: Path) -> str:
    if column in table.names:
        return column
    candidates = table.aliases.get(column, [])
    if len(candidates) == 1:
        return candidates[0]
    if len(candidates) > 1:
        raise RecordingError(
            f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, "
            f"which is ambiguous in the file: {candidates}; give the full name"
        )
    pool = table.names + [a for a in table.aliases if a not in table.names]
    close = difflib.get_close_matches(column, pool, n=3, cutoff=0.6)
    shown = table.names if len(table.names) <= 60 else [*table.names[:60], "..."]
    raise RecordingError(
        f"{path}: channel map entry {entry} (map {cmap.source}) names column {column!r}, "
        f"which is not in the file"
        + (f"; close matches: {close}" if close else "")
        + f"; available columns: {shown}"
        + (f"; not readable: {table.skipped}" if table.skipped else "")
    )


def _as_float(values: np.ndarray, what: str) -> np.ndarray:
    arr = np.asarray(values)
    if arr.dtype.kind in "biuf":
        return arr.astype(float)
    if arr.dtype.kind == "O":
        import pandas as pd

        num = pd.to_numeric(pd.Series(arr), errors="coerce").to_numpy(dtype=float)
        bad = np.isnan(num) & ~pd.isna(pd.Series(arr)).to_numpy()
        bad &= ~np.array([str(v).strip().lower() in ("nan", "inf", "-inf") for v in arr])
        if not bad.any():
            return num
        k = int(np.flatnonzero(bad)[0])
        raise RecordingError(
            f"{what} has {int(bad.sum())} non-numeric entries, first at row {k}: {arr[k]!r}"
        )
    raise RecordingError(f"{what} is not numeric (dtype {arr.dtype})")


def _time_seconds(values: np.ndarray, unit: str, what: str, notes: list) -> np.ndarray:
    arr = np.asarray(values)
    if arr.dtype.kind == "O":
        import pandas as pd

        try:
            return _as_float(arr, what) * TIME_UNITS[unit]
        except RecordingError:
            try:
                arr = pd.to_datetime(pd.Series(arr)).to_numpy()
            except (ValueError, TypeError) as exc:
                raise RecordingError(f"{what} is neither numbers nor timestamps") from exc
    if arr.dtype.kind == "M":
        t0 = arr[0]
        notes.append(f"absolute timestamps converted to seconds since the first sample ({t0})")
        return (arr - t0) / np.timedelta64(1, "s")
    return _as_float(arr, what) * TIME_UNITS[unit]


def _auto_entries(table: _Table, cmap: ChannelMap, path: Path) -> list[ChannelSpec]:
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


def _apply_map(
    table: _Table, cmap: ChannelMap, path: Path
) -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, str], dict[str, Any]]:
    notes = table.notes
    info: dict[str, Any] = {"columns": {}, "source_units": {}}
    where = f"{path}:"

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
                raise RecordingError(
                    f"{where} channel map entry [time] (map {cmap.source}) says unit {unit!r} "
                    f"but column {col_name!r} says {col.unit!r}"
                )
            time = _time_seconds(col.values, unit, f"{where} time column {col_name!r}", notes)
            info["columns"]["time"] = col_name
            info["source_units"]["time"] = unit

    # --- channels
    specs = _auto_entries(table, cmap, path) if cmap.auto else list(cmap.entries)
    loaded: list[tuple[ChannelSpec, np.ndarray, str, np.ndarray | None]] = []
    for spec in specs:
        name = spec.column if cmap.auto else _resolve(table, spec.column, spec.entry, cmap, path)
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
        raw = _as_float(col.values, what)
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
    first_spec, first_values, _, first_own = loaded[0]
    if time is None and tspec is not None and tspec.sample_rate_Hz is not None:
        time = np.arange(first_values.size) / tspec.sample_rate_Hz
        info["source_units"]["time"] = f"sample_rate_Hz = {tspec.sample_rate_Hz}"
        if first_own is not None and first_own.size > 1:
            own_rate = 1.0 / float(np.median(np.diff(first_own)))
            if abs(own_rate - tspec.sample_rate_Hz) > 1e-6 * tspec.sample_rate_Hz:
                notes.append(
                    f"the map's sample_rate_Hz = {tspec.sample_rate_Hz} Hz overrides the file's "
                    f"{own_rate:.6g} Hz"
                )
        own_times: list = [None] * len(loaded)
    elif time is None:
        if first_own is None:
            raise RecordingError(
                f"{where} no time: the channel map (map {cmap.source}) gives no [time] column "
                "nor sample_rate_Hz, and the file's channels carry no time base "
                "(TDMS wf_increment / MDF master)"
            )
        time = first_own
        info["columns"]["time"] = f"time base of {info['columns'][first_spec.name]!r}"
        own_times = [own for _, _, _, own in loaded]
    else:
        own_times = [own for _, _, _, own in loaded]

    # --- put every channel on the reference time
    channels: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    needs: list[int] = []
    for i, (spec, values, _si, _own) in enumerate(loaded):
        own = own_times[i]
        same = own is not None and own.size == time.size and np.allclose(own, time)
        if own is not None and not same and (table.own_time_exact or values.size != time.size):
            needs.append(i)
        elif values.size != time.size:
            raise RecordingError(
                f"{where} column {info['columns'][spec.name]!r} (channel map entry {spec.entry}) "
                f"has {values.size} samples, time has {time.size}"
            )
    if needs:
        starts = [time[0]] + [own_times[i][0] for i in needs]
        ends = [time[-1]] + [own_times[i][-1] for i in needs]
        lo, hi = max(starts), min(ends)
        keep = (time >= lo) & (time <= hi)
        if not keep.any():
            raise RecordingError(f"{where} the channels' time ranges do not overlap")
        resampled = {}
        for i in needs:
            spec, values, own = loaded[i][0], loaded[i][1], own_times[i]
            if own.size != values.size or np.any(np.diff(own) <= 0):
                raise RecordingError(
                    f"{where} column {info['columns'][spec.name]!r}: its time base is not "
                    "strictly increasing or has the wrong length"
                )
            rate = 1.0 / float(np.median(np.diff(own))) if own.size > 1 else float("nan")
            resampled[spec.name] = {"from_rate_Hz": rate, "method": "linear"}
        ref_rate = 1.0 / float(np.median(np.diff(time))) if time.size > 1 else float("nan")
        info["resampled"] = {
            "onto": info["columns"].get("time", "time"),
            "rate_Hz": ref_rate,
            "channels": resampled,
        }
        notes.append(
            f"channels {sorted(resampled)} resampled (linear) onto the time base of "
            f"{info['resampled']['onto']} ({ref_rate:.6g} Hz)"
        )
        if not keep.all():
            notes.append(
                f"time trimmed to the common span {lo:.6g} s .. {hi:.6g} s "
                f"({int((~keep).sum())} samples dropped)"
            )
        full_time = time
        time = time[keep]
        for i, (spec, values, si, _own) in enumerate(loaded):
            if i in needs:
                channels[spec.name] = np.interp(time, own_times[i], values)
            else:
                channels[spec.name] = values[keep] if values.size == full_time.size else values
            units[spec.name] = si
    else:
        for spec, values, si, _ in loaded:
            channels[spec.name] = values
            units[spec.name] = si
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
            f"{len(gaps)} gap(s) in total; validate='lenient' keeps them (listed in metadata)"
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
                    "; validate='lenient' interpolates runs of at most "
                    f"{MAX_INTERPOLATED_NAN_RUN} samples"
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
    format : {"csv", "parquet", "tdms", "mf4", "mdf", "mat"}, optional
        Overrides the format implied by the suffix.
    validate : {"strict", "lenient"}
        Strict: any NaN/inf sample or gap is an error. Lenient: NaN/inf runs of at most
        :data:`MAX_INTERPOLATED_NAN_RUN` samples are interpolated, gaps are kept; both are
        listed in the metadata.
    channels : iterable of str, optional
        Channels the caller needs; a missing one is an error naming it.

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
    with _open_table(p, fmt) as table:
        time, chans, units, info = _apply_map(table, cmap, p)
        notes = table.notes
        stored = table.stored_metadata
    required = list(channels or ())
    missing = [c for c in required if c not in chans]
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
