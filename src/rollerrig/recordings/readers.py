"""Read DAQ recordings (CSV/text, LabVIEW .lvm, Parquet, NI TDMS, ASAM MDF4, MATLAB .mat).

One entry point, :func:`read_recording`: the file's format is detected (:func:`detect_format`)
and read into a table of columns (:mod:`rollerrig.recordings.formats`), the columns are translated
by a channel map into canonical channels in SI units (:mod:`rollerrig.recordings.translate`), then
validated at the boundary (:mod:`rollerrig.recordings.validate`: time strictly increasing; NaN/inf
samples and gaps are errors, or with ``validate="lenient"`` short NaN/inf runs are interpolated
and gaps kept, both listed in the metadata). Channels the caller needs (``channels=``) must be
present; map entries the caller does not need, and entries marked ``optional = true``, are read
when present and only noted when absent.

HBM catman binary files (``.bin``) are not read: the one PyPI reader (``apread``) needs
matplotlib, OpenCV and tqdm, asks on stdin which channel is the time, and prints instead of
raising; export from catman as ASCII or ASAM MDF4 instead (the error says so). imc FAMOS/STUDIO
``.raw`` files and Dewesoft ``.dxd``/``.dxz``/``.d7d``/``.d7z`` files are not read either: imc's
own reader on PyPI (``imctermite``) and Dewesoft's (``dwdatareader``) are compiled or wrap the
vendor's shared library, and no pure-Python reader on PyPI is established; the error names the
vendor and the export to use. A file is also recognised by its first bytes
(:data:`VENDOR_SIGNATURES`: FAMOS ``|CF,``, Dewesoft ``DEWESOFT``), so that a misnamed file gets
the same message rather than a parse error.

Input files are opened read-only and never modified. The optional readers (``nptdms``,
``asammdf``, ``h5py``, ``pandas``, ``pyarrow``) are imported only when their format is read.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rollerrig._validation import folder_not_file
from rollerrig.output.provenance import file_sha256
from rollerrig.recordings.channels import ChannelMap, default_channel_map, load_channel_map
from rollerrig.recordings.formats import Table, open_table
from rollerrig.recordings.formats.xlsx import _ODS, _XLS
from rollerrig.recordings.recording import Recording, RecordingError, RecordingFileNotFound
from rollerrig.recordings.translate import apply_map
from rollerrig.recordings.validate import (
    GAP_FACTOR,
    MAX_INTERPOLATED_NAN_RUN,
    check_time_unit,
    describe_gap,
    find_gaps,
    validate_samples,
)

__all__ = [
    "FORMATS",
    "GAP_FACTOR",
    "MAX_INTERPOLATED_NAN_RUN",
    "VENDOR_SIGNATURES",
    "ChannelMapLike",
    "describe_gap",
    "detect_format",
    "file_sha256",
    "find_gaps",
    "read_recording",
]

FORMATS: dict[str, tuple[str, ...]] = {
    "csv": (".csv", ".txt", ".tsv"),
    "lvm": (".lvm",),
    "parquet": (".parquet", ".pq"),
    "tdms": (".tdms",),
    "mf4": (".mf4", ".mdf"),
    "mat": (".mat",),
    "xlsx": (".xlsx", ".xlsm"),
}
"""Format name -> file suffixes."""

_FORMAT_ALIASES = {
    "mdf": "mf4",
    "mdf4": "mf4",
    "pq": "parquet",
    "txt": "csv",
    "tsv": "csv",
    "xlsm": "xlsx",
    "excel": "xlsx",
}

_FAMOS = (
    "imc FAMOS/STUDIO raw files (.raw, format '|CF,') are not read (imc's reader on PyPI, "
    "imctermite, is a compiled extension); in imc FAMOS or imc STUDIO export the channels as "
    "ASAM MDF4 (.mf4), MATLAB (.mat) or CSV (with channel names and units) and read that file"
)
_DEWESOFT = (
    "Dewesoft data files (.dxd, .dxz, .d7d, .d7z) are not read (Dewesoft's reader needs its "
    "DWDataReaderLib shared library); in Dewesoft X use Export to write the data as ASAM MDF4 "
    "(.mf4), MATLAB (.mat) or CSV (text, with channel names and units) and read that file"
)

_FEATHER = (
    "Feather / Arrow IPC files (.feather, .arrow) are not read; write the table as Parquet "
    "instead (pandas: df.to_parquet('run.parquet'); pyarrow: pyarrow.parquet.write_table), "
    "which is read in parts and keeps each column's type"
)

VENDOR_SIGNATURES: dict[bytes, str] = {
    b"|CF,": _FAMOS,
    b"DEWESOFT": _DEWESOFT,
    b"ARROW1": _FEATHER,
}
"""First bytes of vendor files no reader here reads -> what to do (names the vendor)."""

_NOT_READ = {
    ".raw": _FAMOS,
    ".dxd": _DEWESOFT,
    ".dxz": _DEWESOFT,
    ".d7d": _DEWESOFT,
    ".d7z": _DEWESOFT,
    ".bin": (
        "HBM catman binary files (.bin) are not read (the only PyPI reader, apread, prompts on "
        "stdin and pulls in matplotlib/OpenCV); in catman export the measurement as ASCII "
        "(tab-separated, with channel names and units: read it with format='csv', or rename "
        "it to .csv) or as ASAM MDF4 (.mf4), and read that file"
    ),
    ".tdm": ("NI DIAdem TDM headers (.tdm + .tdx) are not read; export as TDMS or CSV from DIAdem"),
    ".feather": _FEATHER,
    ".arrow": _FEATHER,
    ".xls": _XLS,
    ".ods": _ODS,
}

CONTENT_SIGNATURES: dict[bytes, str] = {
    b"MDF     ": "mf4",  # MDF3 and MDF4 (INCA and CANape write them as .dat too)
    b"UnFinMF ": "mf4",  # an MDF4 file its logger did not finalise
    b"TDSm": "tdms",
    b"MATLAB 5.0 MAT-file": "mat",
    b"MATLAB 7.3 MAT-file": "mat",
    b"PAR1": "parquet",
}
"""First bytes of files the readers here read -> their format, for a file whose suffix does
not say (INCA's MDF as ``.dat``, a download without its suffix)."""


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


# ---------------------------------------------------------------------------------------------


ChannelMapLike = ChannelMap | str | Path | Mapping[str, Any] | None
"""A channel map as a reader takes it: the map, its TOML file, its dict, or None (default)."""


def _as_channel_map(channel_map: ChannelMapLike) -> ChannelMap:
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


def _file_head(p: Path) -> bytes:
    """The file's first 32 bytes (b"" where it is missing or unreadable: the reader says so)."""
    try:
        with p.open("rb") as fh:
            return fh.read(32)
    except OSError:
        return b""


def _refuse_vendor_file(p: Path, head: bytes) -> None:
    """RecordingError naming the vendor when the file starts (``head``) like one no reader
    here reads (:data:`VENDOR_SIGNATURES`), whatever its suffix."""
    for magic, why in VENDOR_SIGNATURES.items():
        if head.startswith(magic):
            suffix = p.suffix.lower()
            named = "" if suffix in _NOT_READ else f" (recognised by its content; named {suffix!r})"
            raise RecordingError(f"{p}: {why}{named}")


def _format_by_content(p: Path, head: bytes) -> str | None:
    """The format of a file whose suffix is none of :data:`FORMATS`' but whose first bytes
    (``head``) are one of :data:`CONTENT_SIGNATURES`; None otherwise (the suffix decides)."""
    suffix = p.suffix.lower()
    if any(suffix in suffixes for suffixes in FORMATS.values()):
        return None
    for magic, fmt in CONTENT_SIGNATURES.items():
        if head.startswith(magic):
            return fmt
    return None


def resolve_inputs(
    path, channel_map: ChannelMapLike, format: str | None, channels: Iterable[str] | None
) -> tuple[Path, str, ChannelMap, list[str] | None]:
    """The file, its format, the channel map and the channels needed (None: every entry).

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    RecordingError
        An unsupported format; a channel map that cannot be loaded.
    """
    p = Path(path)
    folder = folder_not_file(
        p,
        "a recording file",
        "one of the recording files in it ("
        + ", ".join(s for suffixes in FORMATS.values() for s in suffixes)
        + ")",
    )
    if folder is not None:  # had been "unsupported file suffix ''"
        raise RecordingError(folder)
    head = _file_head(p)
    _refuse_vendor_file(p, head)
    fmt = _format_by_content(p, head) if format is None else None
    fmt = fmt or detect_format(p, format)
    cmap = _as_channel_map(channel_map)
    if not p.is_file():
        raise RecordingFileNotFound(f"recording file not found: {p}")
    return p, fmt, cmap, None if channels is None else [str(c) for c in channels]


def require_channels(
    where: str, needed: list[str] | None, have: Mapping[str, Any], cmap: ChannelMap
) -> None:
    """RecordingError naming the needed channels the map did not give."""
    missing = [c for c in needed or () if c not in have]
    if missing:
        raise RecordingError(
            f"{where} required channel(s) {missing} not in the recording (map {cmap.source} "
            f"gives {sorted(have)}); add [channels.<name>] entries for them"
        )


def recording_metadata(
    p: Path, fmt: str, cmap: ChannelMap, table: Table, info: dict[str, Any], **validation: Any
) -> dict[str, Any]:
    """A recording's metadata: the file, the map, what the map resolved to (``info``), the
    reader's notes, the provenance stored in the file; ``validation``: ``validate``,
    ``gaps``, ``interpolated`` (and ``sha256`` when known, placed after ``format``)."""
    sha = validation.pop("sha256", None)
    metadata: dict[str, Any] = {
        "source": str(p.resolve()),
        "format": fmt,
        **({} if sha is None else {"sha256": sha}),
        "size_bytes": p.stat().st_size,
        "channel_map": cmap.to_dict(),
        "validate": validation["validate"],
        **info,
        "gaps": validation["gaps"],
        "interpolated": validation["interpolated"],
        "notes": list(table.notes),
    }
    if table.stored_metadata is not None:
        metadata["stored_metadata"] = table.stored_metadata
    return metadata


def read_recording(
    path: str | Path,
    channel_map: ChannelMapLike = None,
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
        rollerrig (:func:`rollerrig.recordings.channels.default_channel_map`: canonical names as
        columns, units in headers such as ``torque [N.m]`` or stored in the file).
    format : {"csv", "lvm", "parquet", "tdms", "mf4", "mdf", "mat", "xlsx"}, optional
        Overrides the format implied by the suffix (``.csv``/``.txt``/``.tsv``: text, read as the
        map's ``[file]`` section says or sniffed; ``.lvm``: LabVIEW Measurement; ``.xlsx``/
        ``.xlsm``: one sheet of an Excel workbook, ``[file] sheet``).
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
    if validate not in ("strict", "lenient"):
        raise RecordingError(f"validate must be 'strict' or 'lenient', got {validate!r}")
    p, fmt, cmap, required = resolve_inputs(path, channel_map, format, channels)
    sha = file_sha256(p)
    where = f"{p}:"
    with open_table(p, fmt, cmap.file) as table:
        time, chans, units, info = apply_map(table, cmap, p, required, validate)
    require_channels(where, required, chans, cmap)
    chans, report = validate_samples(time, chans, validate, where, table.notes)
    # runs of resampled channels, interpolated on their own time base before resampling
    report["interpolated"][:0] = info.pop("interpolated", [])
    if info.pop("time_unit_assumed", None) is not None and time.size > 1:
        check_time_unit(
            1.0 / float(np.median(np.diff(time))),
            float(time[-1] - time[0]),
            where,
            info["columns"]["time"],
        )
    metadata = recording_metadata(
        p, fmt, cmap, table, info, sha256=sha, validate=validate, **report
    )
    if report["interpolated"]:
        metadata["notes"].append(
            f"{len(report['interpolated'])} short NaN/inf run(s) interpolated (lenient)"
        )
    if report["gaps"]:
        metadata["notes"].append(f"{len(report['gaps'])} gap(s) kept (lenient)")
    # The reader's own arrays, nobody else's: read-only, so the Recording shares them instead
    # of copying every channel of a whole file.
    for arr in (time, *chans.values()):
        if isinstance(arr, np.ndarray) and arr.dtype == np.float64:
            arr.setflags(write=False)
    return Recording(time, chans, units, metadata)
