"""Write a :class:`Recording` to CSV, Parquet, NI TDMS, ASAM MDF4 or MATLAB .mat.

Every writer is atomic (a temporary file in the target folder, then :func:`os.replace`) and
never replaces an existing file unless ``overwrite=True``. Units and provenance travel with the
data so that :func:`rollerrig.measure.readers.read_recording` reads the file back without a
channel map:

=========  ==========================================  ==========================================
format     units                                       provenance (``recording.metadata``, JSON)
=========  ==========================================  ==========================================
csv        headers ``time [s]``, ``torque [N.m]``      sidecar ``<name>.metadata.json``
parquet    field metadata ``unit`` + schema metadata   schema metadata ``rollerrig``
tdms       channel property ``unit_string``            root property ``rollerrig_metadata``
mf4        signal unit                                 header comment
mat        variable ``rollerrig_units`` (JSON text)    variable ``rollerrig_metadata`` (JSON)
=========  ==========================================  ==========================================

TDMS: one group ``rollerrig`` with a ``time`` channel and one channel per signal; each carries
``wf_increment``/``wf_start_offset`` when the time base is uniform. MAT: version 5 by default
(:func:`scipy.io.savemat`, column vectors); ``mat_version="7.3"`` writes an HDF5 file with the
MATLAB 7.3 header and ``MATLAB_class`` attributes (double column vectors and char rows only).
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rollerrig.measure.channels import format_unit_header
from rollerrig.measure.formats._table import META_KEY as _META_KEY
from rollerrig.measure.formats._table import UNITS_KEY as _UNITS_KEY
from rollerrig.measure.formats._table import require_module as _require
from rollerrig.measure.readers import detect_format
from rollerrig.measure.recording import Recording, RecordingError

__all__ = ["metadata_json", "write_recording"]

_MAT_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,62}$")


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, _dt.datetime | _dt.date):
        return obj.isoformat()
    if isinstance(obj, set | frozenset | tuple):
        return list(obj)
    if hasattr(obj, "items"):
        return dict(obj.items())
    return str(obj)


def metadata_json(recording: Recording) -> str:
    """``recording.metadata`` as JSON text (numpy values, paths and mappings converted).

    Examples
    --------
    >>> r = Recording(np.arange(3.0), {"torque": np.zeros(3)}, {"torque": "N.m"},
    ...               {"run": np.int64(3)})
    >>> metadata_json(r)
    '{"run": 3}'
    """
    return json.dumps(dict(recording.metadata), default=_json_default)


def _uniform_step(time: np.ndarray) -> float | None:
    dt = np.diff(time)
    step = float(np.median(dt))
    return step if np.allclose(dt, step, rtol=1e-9, atol=1e-12 * max(1.0, step)) else None


def _write_csv(rec: Recording, tmp: Path) -> None:
    import pandas as pd

    cols = {format_unit_header("time", "s"): rec.time}
    for name, values in rec.channels.items():
        cols[format_unit_header(name, rec.units[name])] = values
    pd.DataFrame(cols).to_csv(tmp, index=False)


def _write_parquet(rec: Recording, tmp: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    units = {"time": "s", **dict(rec.units)}
    fields = [pa.field("time", pa.float64(), metadata={"unit": "s"})]
    arrays = [pa.array(rec.time)]
    for name, values in rec.channels.items():
        fields.append(pa.field(name, pa.float64(), metadata={"unit": rec.units[name]}))
        arrays.append(pa.array(values))
    blob = json.dumps(
        {"units": units, "metadata": json.loads(metadata_json(rec))}, default=_json_default
    )
    schema = pa.schema(fields, metadata={"rollerrig": blob})
    pq.write_table(pa.Table.from_arrays(arrays, schema=schema), tmp)


def _write_tdms(rec: Recording, tmp: Path) -> None:
    nptdms = _require("nptdms", "TDMS files")
    step = _uniform_step(rec.time)
    start = float(rec.time[0])

    def props(unit: str) -> dict[str, Any]:
        p: dict[str, Any] = {"unit_string": unit}
        if step is not None:
            p.update(wf_increment=step, wf_start_offset=start, wf_samples=int(rec.time.size))
        return p

    objects = [
        nptdms.RootObject(properties={_META_KEY: metadata_json(rec), "name": tmp.name}),
        nptdms.GroupObject("rollerrig"),
        nptdms.ChannelObject("rollerrig", "time", rec.time, properties={"unit_string": "s"}),
    ]
    objects += [
        nptdms.ChannelObject("rollerrig", name, np.asarray(v), properties=props(rec.units[name]))
        for name, v in rec.channels.items()
    ]
    with nptdms.TdmsWriter(str(tmp)) as writer:
        writer.write_segment(objects)


def _write_mf4(rec: Recording, tmp: Path) -> Path:
    asammdf = _require("asammdf", "MDF4 files")
    mdf = asammdf.MDF(version="4.10")
    try:
        signals = [
            asammdf.Signal(np.asarray(v), rec.time, name=name, unit=rec.units[name])
            for name, v in rec.channels.items()
        ]
        if signals:
            mdf.append(signals, comment="rollerrig recording")
        mdf.header.comment = metadata_json(rec)
        saved = mdf.save(str(tmp), overwrite=True)
    finally:
        mdf.close()
    return Path(saved)


def _check_mat_names(rec: Recording) -> None:
    for name in rec.channels:
        if not _MAT_NAME.match(name) or name in ("time", _META_KEY, _UNITS_KEY):
            raise RecordingError(
                f"channel {name!r} cannot be a MATLAB variable name (letter first, then letters, "
                "digits and _, at most 63 characters; not a reserved name)"
            )


def _write_mat5(rec: Recording, tmp: Path) -> None:
    from scipy.io import savemat

    data: dict[str, Any] = {"time": rec.time.reshape(-1, 1)}
    for name, values in rec.channels.items():
        data[name] = np.asarray(values).reshape(-1, 1)
    data[_UNITS_KEY] = json.dumps({"time": "s", **dict(rec.units)})
    data[_META_KEY] = metadata_json(rec)
    with tmp.open("wb") as fh:
        savemat(fh, data, format="5", do_compression=True, oned_as="column")


def _write_mat73(rec: Recording, tmp: Path) -> None:
    """MATLAB 7.3: HDF5 with a 512-byte user block holding the MAT header."""
    h5py = _require("h5py", "MATLAB v7.3 files")

    def double(f, name: str, values: np.ndarray) -> None:
        # MATLAB is column-major: an n x 1 column vector is stored with HDF5 shape (1, n).
        ds = f.create_dataset(name, data=np.asarray(values, dtype=float).reshape(1, -1))
        ds.attrs["MATLAB_class"] = np.bytes_("double")

    def char(f, name: str, text: str) -> None:
        codes = np.frombuffer(text.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
        ds = f.create_dataset(name, data=codes)
        ds.attrs["MATLAB_class"] = np.bytes_("char")
        ds.attrs["MATLAB_int_decode"] = np.int32(2)

    with h5py.File(tmp, "w", userblock_size=512, libver="earliest") as f:
        double(f, "time", rec.time)
        for name, values in rec.channels.items():
            double(f, name, values)
        char(f, _UNITS_KEY, json.dumps({"time": "s", **dict(rec.units)}))
        char(f, _META_KEY, metadata_json(rec))
    stamp = _dt.datetime.now(_dt.UTC).strftime("%a %b %d %H:%M:%S %Y")
    text = f"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: {stamp} HDF5 schema 1.00 ."
    header = text.encode("ascii").ljust(116, b" ") + b" " * 8 + b"\x00\x02" + b"IM"
    with tmp.open("r+b") as fh:
        fh.write(header.ljust(512, b"\x00"))


def _commit(tmp: Path, dst: Path, overwrite: bool) -> None:
    if overwrite:
        os.replace(tmp, dst)
        return
    try:
        os.link(tmp, dst)  # atomic and refuses to replace an existing file
    except FileExistsError:
        raise FileExistsError(f"{dst} exists; pass overwrite=True to replace it") from None
    except OSError:  # file system without hard links
        if dst.exists():
            raise FileExistsError(f"{dst} exists; pass overwrite=True to replace it") from None
        os.replace(tmp, dst)
        return
    tmp.unlink()


def _atomic(dst: Path, overwrite: bool, write: Callable[[Path], Path | None]) -> None:
    fd, name = tempfile.mkstemp(dir=dst.parent, prefix=f".{dst.stem}.", suffix=f".tmp{dst.suffix}")
    os.close(fd)
    tmp = Path(name)
    written = tmp
    try:
        written = write(tmp) or tmp
        # mkstemp makes the file private (0o600); give it the mode a new file would get.
        if dst.exists():
            mode = dst.stat().st_mode & 0o777
        else:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(written, mode)
        _commit(written, dst, overwrite)
    finally:
        for leftover in {tmp, written}:
            with contextlib.suppress(FileNotFoundError):
                leftover.unlink()


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
        What to write; its units and metadata are stored with it.
    path : str or path-like
        Target file; the format follows from the suffix unless ``format`` is given.
    format : {"csv", "parquet", "tdms", "mf4", "mdf", "mat"}, optional
        Overrides the suffix.
    overwrite : bool
        Replace an existing file (and, for CSV, its metadata sidecar).
    mat_version : {"5", "7.3"}
        MAT-file version for ``format="mat"``.

    Returns
    -------
    Path
        The written file.

    Raises
    ------
    FileExistsError
        The file (or CSV sidecar) exists and ``overwrite`` is False.
    RecordingError
        Unsupported format, or a channel name that the format cannot store.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from rollerrig.measure.readers import read_recording
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
    if not dst.parent.is_dir():
        raise FileNotFoundError(f"folder {dst.parent} does not exist")
    if dst.exists() and not overwrite:
        raise FileExistsError(f"{dst} exists; pass overwrite=True to replace it")
    if fmt == "mf4" and dst.suffix.lower() not in (".mf4", ".mdf"):
        raise RecordingError(f"{dst}: MDF4 files must end in .mf4 (asammdf sets the suffix)")
    if fmt == "csv":
        sidecar = dst.with_suffix(".metadata.json")
        if sidecar.exists() and not overwrite:
            raise FileExistsError(f"{sidecar} exists; pass overwrite=True to replace it")
        _atomic(dst, overwrite, lambda tmp: _write_csv(recording, tmp))
        _atomic(
            sidecar,
            True,
            lambda tmp: (
                tmp.write_text(
                    json.dumps(json.loads(metadata_json(recording)), indent=2), encoding="utf-8"
                )
                and None
            ),
        )
    elif fmt == "parquet":
        _atomic(dst, overwrite, lambda tmp: _write_parquet(recording, tmp))
    elif fmt == "tdms":
        _atomic(dst, overwrite, lambda tmp: _write_tdms(recording, tmp))
    elif fmt == "mf4":
        _atomic(dst, overwrite, lambda tmp: _write_mf4(recording, tmp))
    else:
        _check_mat_names(recording)
        if mat_version == "5":
            _atomic(dst, overwrite, lambda tmp: _write_mat5(recording, tmp))
        elif mat_version == "7.3":
            _atomic(dst, overwrite, lambda tmp: _write_mat73(recording, tmp))
        else:
            raise RecordingError(f"mat_version must be '5' or '7.3', got {mat_version!r}")
    return dst
