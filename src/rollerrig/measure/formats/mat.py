"""MATLAB .mat files (v4/v5/v7 via scipy, v7.3 via pymatreader, plain HDF5 via h5py)."""

from __future__ import annotations

import contextlib
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from rollerrig.measure.formats._table import (
    META_KEY,
    UNITS_KEY,
    Column,
    Table,
    require_module,
)
from rollerrig.measure.recording import RecordingError


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
    h5py = require_module("h5py", "HDF5 .mat files")

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


def read_mat(path: Path) -> Table:
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
        pymatreader = require_module("pymatreader", "MATLAB v7.3 files")
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
    if isinstance(flat.get(META_KEY), str):
        with contextlib.suppress(json.JSONDecodeError):
            stored = json.loads(flat[META_KEY])
    if isinstance(flat.get(UNITS_KEY), str):
        with contextlib.suppress(json.JSONDecodeError):
            units = json.loads(flat[UNITS_KEY])
    columns = {k: v for k, v in flat.items() if not isinstance(v, str)}
    table = Table(
        names=list(columns),
        load=lambda n: Column(columns[n], units.get(n)),
        base={n: n for n in columns},
        notes=notes,
        skipped=skipped,
        stored_metadata=stored,
    )
    if skipped:
        table.notes.append(f"MAT variables not read (not numeric vectors): {skipped}")
    return table
