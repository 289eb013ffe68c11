"""NetCDF-4 files with CF-1.10 attributes, written through h5py as netCDF-C lays them out.

:func:`write_netcdf` writes variables (numbers, booleans, text) straight from numpy arrays, with
no xarray, dask or ``distributed`` imported; :func:`write_cf_netcdf` adds the CF attributes and
the provenance to labelled data and hands what h5py cannot write as xarray would (times,
non-dimension coordinates, encodings of a file read back) to xarray's own writer. The
conventions (units, long names, the metadata object) are those of
:mod:`rollerrig.output.tables`, the package's one results writer, which calls this module for
the ``nc`` format.
"""

from __future__ import annotations

import errno
import io
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from rollerrig._optional import require
from rollerrig._validation import ParameterError
from rollerrig.output.jsonfile import META_KEY, PROVENANCE_KEY, VARIABLES_KEY, json_text

__all__ = [
    "CONVENTIONS",
    "TIME_ATTRS",
    "NcVariable",
    "cf_attributes",
    "write_cf_netcdf",
    "write_netcdf",
]

CONVENTIONS = "CF-1.10"
"""The CF conventions the NetCDF files follow (global attribute ``Conventions``)."""


def attr_value(value: Any) -> Any:
    """A NetCDF attribute value: strings (a NUL, which HDF5 strings cannot hold, written as
    ``\\x00``) and finite numbers as they are, the rest as JSON."""
    if isinstance(value, str | bool | np.bool_):
        return value.replace("\x00", "\\x00") if isinstance(value, str) else int(value)
    if isinstance(value, int | float | np.integer | np.floating) and np.isfinite(value):
        return value
    return json_text(value)


# Elapsed time, not a calendar time: CF (section 4.4) identifies a time coordinate by units of
# the form "s since <date>", so standard_name "time" and axis "T" would be wrong with "s".
TIME_ATTRS = {"units": "s", "long_name": "time since the start of the record"}


class NcVariable(NamedTuple):
    """One NetCDF variable: its dimensions, values and attributes."""

    dims: tuple[str, ...]
    values: np.ndarray
    attrs: dict[str, Any]


def cf_attributes(
    variables: Mapping[str, NcVariable], meta: Mapping[str, Any], title: str
) -> tuple[dict[str, NcVariable], dict[str, Any]]:
    """The variables with their CF-1.10 attributes (``units``, ``long_name``; values a NetCDF
    attribute can hold) and the file's: ``Conventions``, ``title``, ``history``, ``source``,
    the provenance and the metadata object."""
    out = {}
    for name, var in variables.items():
        attrs = {k: attr_value(v) for k, v in var.attrs.items()}
        if name == "time":
            attrs = {**TIME_ATTRS, **attrs}
        attrs.setdefault("long_name", str(name))
        out[name] = var._replace(attrs=attrs)
    prov = meta[PROVENANCE_KEY]
    attrs = {k: v for k, v in meta.items() if k not in (PROVENANCE_KEY, VARIABLES_KEY)}
    command = " ".join(prov.get("command") or []) if isinstance(prov, Mapping) else ""
    version = prov.get("version", "") if isinstance(prov, Mapping) else ""
    created = prov.get("created_utc", "") if isinstance(prov, Mapping) else ""
    history = f"{created} rollerrig {version}: {command}".strip()
    file_attrs = {
        "Conventions": CONVENTIONS,
        "title": str(attrs.get("title") or title),
        "history": str(attrs.get("history") or history),
        "source": str(attrs.get("source") or f"rollerrig {version}".strip()),
        **{
            k: attr_value(v)
            for k, v in attrs.items()
            if k not in ("Conventions", "title", "history", "source")
            and isinstance(v, str | int | float | bool | np.number)
        },
        PROVENANCE_KEY: json_text(prov),
        META_KEY: json_text(attrs),
    }
    return out, file_attrs


def write_cf_netcdf(data, meta: Mapping[str, Any], tmp: Path, title: str, source=None) -> None:
    """Write labelled data (:class:`~rollerrig.output.labelled.LabelledData`) with CF-1.10
    attributes: ``Conventions``, ``title``, ``history``, ``source``, ``units``/``long_name``
    per variable, and the provenance.

    Numbers, booleans and text along dimensions (each dimension coordinate a variable of its
    own) are written by :func:`write_netcdf`, through h5py from the numpy arrays: no
    xarray, no dask or ``distributed`` imported by xarray's scheduler probe, the file as xarray
    would write it. Anything else (times, non-dimension coordinates, ...) goes through
    xarray's own encoders (:meth:`xarray.Dataset.to_netcdf`), from ``source`` (the xarray
    Dataset ``data`` came from, renamed as ``data`` is) or from ``data`` itself."""
    variables = {
        name: NcVariable(var.dims, var.values, dict(var.attrs))
        for name, var in data.variables.items()
    }
    variables, attrs = cf_attributes(variables, meta, title)
    if writable_directly(data, variables):
        write_netcdf(tmp, variables, attrs)
        return
    ds = data.to_xarray() if source is None else source
    for name, var in ds.variables.items():
        var.attrs = variables[str(name)].attrs
    ds.attrs = attrs
    encoding = {n: {"_FillValue": None} for n, v in ds.variables.items() if v.dtype.kind in "biuf"}
    ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding)


def writable_directly(ds, variables: Mapping[str, NcVariable]) -> bool:
    """Whether :func:`write_netcdf` writes ``ds`` as xarray would: every variable numbers,
    booleans or text, every coordinate a dimension's own, no variable named as a dimension it
    does not index (xarray writes that one under another scale), no encoding to honour but
    none."""
    if set(ds.coords) - set(ds.dims) or "coordinates" in ds.attrs:
        return False
    for name, var in variables.items():
        if name in ds.dims and tuple(var.dims) != (name,):
            return False
        kind = var.values.dtype.kind
        if (kind not in "biufU" and not is_text(var.values)) or "coordinates" in var.attrs:
            return False
        # Numbers are written with encoding {"_FillValue": None} alone; text as xarray writes
        # it unless its encoding asks for characters or compression (a file read back).
        encoding = ds[name].encoding if kind not in "biuf" else {}
        dtype = encoding.get("dtype")
        if dtype not in (None, str) and np.dtype(dtype).kind != "U":
            return False
        if any(encoding.get(k) for k in ("zlib", "compression", "chunksizes", "shuffle")):
            return False
    return True


def is_text(values: np.ndarray) -> bool:
    """An object array of Python strings (what xarray writes as variable-length text)."""
    return values.dtype.kind == "O" and all(isinstance(v, str) for v in values.flat)


_PHONY_DIMENSION = "This is a netCDF dimension but not a netCDF variable.%10d"
"""NAME of the dimension scale of a dimension with no variable of its own (netCDF-C's words)."""


def write_netcdf(tmp: Path, variables: Mapping[str, NcVariable], attrs: Mapping) -> None:
    """Write a NetCDF-4 file through h5py, laid out as netCDF-C and h5netcdf lay it out.

    Dimensions in the order the variables first name them, each an HDF5 dimension scale (the
    variable of the same name along it alone, or a scale of its own holding no variable);
    every variable along dimensions carries ``DIMENSION_LIST`` and ``_Netcdf4Coordinates``
    (its dimension ids) and ``_Netcdf4Dimid``; numbers as they are, with no ``_FillValue`` (the
    NaN policy says what a NaN means); booleans as int8 with ``dtype = "bool"`` (read back as
    booleans); text as variable-length UTF-8 strings; non-text scalar attributes as arrays of
    one, as netCDF-C writes them. The file reads back in xarray (h5netcdf) and netCDF4 as
    h5netcdf's own writer's did; written directly it costs about 1 ms a variable instead of 7.
    """
    h5py = require("h5py", purpose="writing NetCDF files")
    from rollerrig import __version__

    sizes: dict[str, int] = {}
    for name, var in variables.items():
        if var.values.ndim != len(var.dims):
            raise ParameterError(f"{tmp}: variable {name!r}: {var.dims} for {var.values.shape}")
        for dim, size in zip(var.dims, var.values.shape, strict=True):
            if sizes.setdefault(dim, size) != size:
                raise ParameterError(f"{tmp}: dimension {dim!r} has sizes {sizes[dim]}, {size}")
    dim_ids = {dim: i for i, dim in enumerate(sizes)}
    coordinate = {d for d in sizes if d in variables and variables[d].dims == (d,)}

    # HDF5 writes through a Python file that keeps the system's first write error (a full
    # disk) instead of handing it to HDF5: with its own driver, HDF5 fails to close the file
    # on a full disk (its metadata cannot be flushed), h5py raises "Can't decrement id ref
    # count", and the process crashed at exit with a segmentation fault. Here HDF5 closes
    # cleanly, and the error is raised after it, as the OSError it is.
    with open(tmp, "w+b", buffering=0) as raw:
        sink = _FirstWriteError(raw)
        try:
            _write_h5(h5py, sink, variables, attrs, sizes, dim_ids, coordinate, __version__)
        except Exception as exc:
            if sink.error is not None:
                raise sink.error from exc
            raise
        if sink.error is not None:
            raise sink.error


class _FirstWriteError(io.RawIOBase):
    """A binary file for h5py's file-object driver that records the first :class:`OSError` of
    a write, truncate or flush and lets HDF5 go on as if it had succeeded (the file is
    discarded: :func:`~rollerrig.output.atomic.atomic_write` removes it when the error is
    raised), so that HDF5 can still close its file. Reads and seeks pass through."""

    def __init__(self, raw) -> None:
        super().__init__()
        self.raw = raw
        self.error: OSError | None = None

    def readable(self) -> bool:
        return True

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def readinto(self, buffer) -> int:
        return self.raw.readinto(buffer)

    def seek(self, offset: int, whence: int = 0) -> int:
        return self.raw.seek(offset, whence)

    def tell(self) -> int:
        return self.raw.tell()

    def write(self, data) -> int:
        size = memoryview(data).nbytes
        if self.error is None:
            try:
                written = self.raw.write(data)
            except OSError as exc:
                self.error = exc
            else:
                if written is not None and written < size:  # the disk filled up mid-write
                    self.error = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
                    self.raw.seek(size - written, 1)
        else:
            self.raw.seek(size, 1)
        return size

    def truncate(self, size: int | None = None) -> int:
        try:
            return self.raw.truncate(size)
        except OSError as exc:
            self.error = self.error or exc
            return self.raw.tell() if size is None else size

    def flush(self) -> None:
        try:
            self.raw.flush()
        except OSError as exc:
            self.error = self.error or exc


def _write_h5(h5py, sink, variables, attrs, sizes, dim_ids, coordinate, version) -> None:
    """The HDF5 content of :func:`write_netcdf` into the file object ``sink``."""

    def put(attributes, key: str, value: Any) -> None:
        if np.isscalar(value) and not isinstance(value, str | bytes):
            value = np.atleast_1d(value)
        attributes[key] = value

    # Creation order tracked (links and attributes), as netCDF-C needs it to append to a file.
    with h5py.File(sink, "w", track_order=True) as f:
        for key, value in attrs.items():
            put(f.attrs, key, value)
        scales = {}
        for dim, size in sizes.items():  # a dimension without a variable: a scale of its own
            if dim not in coordinate:
                scale = f.create_dataset(dim, (size,), dtype=">f4", track_order=True)
                scale.attrs["_Netcdf4Dimid"] = np.int32(dim_ids[dim])
                scale.make_scale(_PHONY_DIMENSION % size)
                scales[dim] = scale
        created = {}
        for name, var in variables.items():
            values, var_attrs = var.values, dict(var.attrs)
            dtype = values.dtype
            if dtype.kind == "b":
                values, dtype = values.astype("i1"), np.dtype("i1")
                var_attrs["dtype"] = "bool"
            elif dtype.kind in "UO":
                values, dtype = values.astype(object), h5py.string_dtype()
            data = f.create_dataset(name, data=values, dtype=dtype, track_order=True)
            if var.dims:
                ids = [dim_ids[d] for d in var.dims]
                data.attrs["_Netcdf4Coordinates"] = np.array(ids, dtype=np.int32)
                data.attrs["_Netcdf4Dimid"] = np.int32(ids[0])
            for key, value in var_attrs.items():
                put(data.attrs, key, value)
            created[name] = data
        for dim in coordinate:
            created[dim].make_scale(dim)
            scales[dim] = created[dim]
        for name, var in variables.items():
            if name in coordinate:
                continue
            for axis, dim in enumerate(var.dims):
                created[name].dims[axis].attach_scale(scales[dim])
        properties = f"version=2,rollerrig={version},hdf5={h5py.version.hdf5_version}"
        f.attrs["_NCProperties"] = np.bytes_(f"{properties},h5py={h5py.__version__}")
