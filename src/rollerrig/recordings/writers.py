"""Write a :class:`Recording` to CSV, Parquet, NI TDMS, ASAM MDF4 or MATLAB .mat.

A thin adapter over :func:`rollerrig.output.write_table` (the package's one results writer; its
module documents where each format keeps units, metadata and provenance): time [s] first, one
column per channel with its unit, ``recording.metadata`` as the file's metadata object, so that
:func:`rollerrig.recordings.readers.read_recording` reads the file back without a channel map and
gives the metadata back as ``metadata["stored_metadata"]``. Writing is atomic and never replaces
an existing file unless ``overwrite=True``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Literal

from rollerrig._validation import ParameterError
from rollerrig.output import OutputError, write_table
from rollerrig.output.provenance import jsonable
from rollerrig.recordings.readers import detect_format
from rollerrig.recordings.recording import Recording, RecordingError

__all__ = ["metadata_json", "write_recording"]

NAN_MEANING_KEY = "nan_meaning"
"""``recording.metadata[NAN_MEANING_KEY]``: ``{channel: why it holds NaN}`` (NaN policy)."""


def metadata_json(recording: Recording) -> str:
    """``recording.metadata`` as JSON text (numpy values, paths and mappings converted).

    Examples
    --------
    >>> import numpy as np
    >>> r = Recording(np.arange(3.0), {"torque": np.zeros(3)}, {"torque": "N.m"},
    ...               {"run": np.int64(3)})
    >>> metadata_json(r)
    '{"run": 3}'
    """
    return json.dumps(dict(recording.metadata), default=_default)


def _default(obj):
    try:
        return jsonable(obj)
    except TypeError:
        return str(obj)


def write_recording(
    recording: Recording,
    path: str | Path,
    *,
    format: str | None = None,
    overwrite: bool = False,
    mat_version: Literal["5", "7.3"] = "5",
) -> Path:
    """Write ``recording`` (SI units) to ``path``, atomically.

    Parameters
    ----------
    recording : Recording
        What to write; its units and metadata are stored with it. A channel may hold NaN only
        when ``recording.metadata["nan_meaning"][channel]`` says why.
    path : str or path-like
        Target file; the format follows from the suffix unless ``format`` is given.
    format : {"csv", "parquet", "tdms", "mf4", "mdf", "mat"}, optional
        Overrides the suffix.
    overwrite, mat_version
        As :func:`rollerrig.output.write_table` (default: an existing file is refused).

    Returns
    -------
    Path
        ``path``, written.

    Raises
    ------
    RecordingError
        Unsupported format, or a channel name or value that the format cannot store.
    FileExistsError
        ``path`` (or the CSV sidecar) exists and ``overwrite`` is False.
    rollerrig.output.OutputError
        The file cannot be written (the message names the path).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> from rollerrig.recordings.readers import read_recording
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> rec = Recording(np.arange(4) / 250.0, {"torque": np.arange(4.0)}, {"torque": "N.m"})
    >>> out = write_recording(rec, d / "run.csv")
    >>> sorted(p.name for p in d.iterdir())
    ['run.csv', 'run.metadata.json']
    >>> read_recording(out)["torque"].tolist()
    [0.0, 1.0, 2.0, 3.0]
    """
    dst = Path(path)
    fmt = detect_format(dst, format)
    if fmt == "xlsx":
        raise RecordingError(
            f"{dst}: recordings are not written as Excel workbooks (read only); write CSV, "
            "which Excel opens, or Parquet"
        )
    if fmt not in ("csv", "parquet", "tdms", "mf4", "mat"):
        raise RecordingError(f"{dst}: recordings are not written as {fmt!r}")
    metadata = json.loads(metadata_json(recording))
    why = metadata.get(NAN_MEANING_KEY) or {}
    columns = {
        name: (values, recording.units[name], "", {"nan_meaning": why[name]} if name in why else {})
        for name, values in recording.channels.items()
    }
    try:
        return write_table(
            dst,
            columns,
            format=fmt,
            time=recording.time,
            attrs=metadata,
            overwrite=overwrite,
            mat_version=mat_version,
        )
    except OutputError:
        raise
    except ParameterError as exc:
        if isinstance(exc, RecordingError):
            raise
        raise RecordingError(str(exc)) from exc
