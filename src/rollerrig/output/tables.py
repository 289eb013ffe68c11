"""The one results writer: named columns with units, keyed by format, written atomically.

One convention per format; every column has a unit (``"1"`` for dimensionless, ``"-"`` read as
``"1"``; label columns of text have none) and the file carries its metadata object (``attrs``,
a ``"variables"`` entry with each column's unit, long name and ``nan_meaning``, and the
``"provenance"`` record):

=======  ==========================================  ==========================================
format   units, long names                           metadata object (JSON)
=======  ==========================================  ==========================================
csv      headers ``time [s]``, ``creep [-]``         sidecar ``<stem>.metadata.json``
parquet  field metadata ``unit``, ``long_name``      schema metadata ``rollerrig``
tdms     channel properties ``unit_string``,         root property ``rollerrig_metadata``;
         ``description``                             root ``name`` = the file's stem
mf4      signal unit and comment                     header comment
mat      column vectors (n x 1) and a struct         ``rollerrig_metadata`` (JSON text) and
         ``units`` (field per variable -> unit)      ``provenance`` (JSON text of the record)
nc       CF-1.10: ``units``, ``long_name`` per       global attributes ``Conventions``,
         variable (``time``: elapsed seconds, no     ``title``, ``history``, ``provenance``
         calendar reference)                         (JSON), ``rollerrig_metadata`` (JSON)
=======  ==========================================  ==========================================

Units: a unit value (attributes, field metadata, the ``variables`` entry) is ``"1"`` for a
dimensionless column, its name in a CSV header ``[-]``
(:func:`rollerrig.units.labelled`): the rule of :mod:`rollerrig.units`.

Numbers in CSV: each value written with the shortest text that reads back as the value rounded
to 12 significant digits (:func:`csv_number`: ``0.1 * 26.39`` = 2.6390000000000002 is written
``2.639``), so the file carries no float noise; the same rounding as JSON
(:func:`rollerrig.output.jsonfile.json_number`). Data precision: a value read back is off by at
most half a unit in its 12th significant digit (5e-12 relative at most), far below what any
sensor of a rig resolves (a 24-bit ADC: 6e-8 of its range). The other formats store the binary
values as they are.

MAT: version 5 by default (:func:`scipy.io.savemat`); ``mat_version="7.3"`` writes an HDF5 file
with the MATLAB 7.3 header and ``MATLAB_class`` attributes (double column vectors, char rows,
the ``units`` struct). TDMS: one group ``rollerrig``; with a uniform time base every channel
carries ``wf_increment``/``wf_start_offset``.

:func:`write_dataset` writes an xarray Dataset through the same conventions (NetCDF keeps
every dimension; the other formats take variables along ``time``).

NaN policy: a column may hold NaN only when its attributes say why (``nan_meaning``); any other
non-finite sample is refused (:class:`~rollerrig._validation.ParameterError`). A column that
does hold NaN carries its ``nan_meaning`` and ``nan_samples`` (how many) on the variable itself
in every format (:data:`NAN_MEANING`), not only in the file's metadata object; CSV cells of
those samples are empty, the sidecar's ``variables`` entry says why.

Names: NetCDF and MAT files store identifiers only; a column whose name is not one (``oil
temp/bearing``, ``Group/Channel``, ``Öl-Temp``) is written under the name
:func:`rollerrig.output.varnames.storable_names` gives it (``oil_temp_bearing``) with the name
given as its ``original_name`` attribute, never refused after the work that made it.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal, NamedTuple

import numpy as np

from rollerrig._display import DIMENSIONLESS, is_dimensionless, labelled
from rollerrig._optional import require
from rollerrig._validation import ParameterError, did_you_mean, require_increasing
from rollerrig.output import netcdf as _netcdf
from rollerrig.output.atomic import (
    OutputError,
    _flag,
    atomic_write,
    atomic_write_all,
    file_path,
)
from rollerrig.output.csv_numbers import csv_number, csv_text
from rollerrig.output.jsonfile import (
    META_KEY,
    PROVENANCE_KEY,
    SIGNIFICANT_DIGITS,
    VARIABLES_KEY,
    json_text,
)
from rollerrig.output.netcdf import CONVENTIONS
from rollerrig.output.provenance import provenance as _provenance
from rollerrig.output.varnames import ORIGINAL_NAME, storable_names

__all__ = [
    "CONVENTIONS",
    "META_KEY",
    "NAN_MEANING",
    "NAN_SAMPLES",
    "PROVENANCE_KEY",
    "SIGNIFICANT_DIGITS",
    "TABLE_FORMATS",
    "UNITS_STRUCT",
    "VARIABLES_KEY",
    "TableColumn",
    "csv_number",
    "table_format",
    "write_dataset",
    "write_table",
]

TABLE_FORMATS: dict[str, tuple[str, ...]] = {
    "csv": (".csv",),
    "parquet": (".parquet",),
    "tdms": (".tdms",),
    "mf4": (".mf4", ".mdf"),
    "mat": (".mat",),
    "nc": (".nc",),
}
"""Format name -> file suffixes written by :func:`write_table`."""
_ALIASES = {"mdf": "mf4", "mdf4": "mf4", "netcdf": "nc", "pq": "parquet"}

NAN_MEANING = "nan_meaning"
"""Attribute of a column that may hold NaN: why (the NaN policy); on the variable in every
format (NetCDF attribute, Parquet field metadata, TDMS channel property, MDF4 signal comment,
the ``variables`` entry of the metadata object: CSV sidecar, MAT)."""
NAN_SAMPLES = "nan_samples"
"""Attribute beside :data:`NAN_MEANING`: how many samples of the column are NaN [-]."""
UNITS_STRUCT = "units"
"""MAT struct holding one field per variable: its unit."""
_MAT_RESERVED = ("time", UNITS_STRUCT, PROVENANCE_KEY, META_KEY, "rollerrig_units")


class TableColumn(NamedTuple):
    """One column: values, unit (None only for a label column of text), long name, attrs."""

    values: np.ndarray
    unit: str | None
    long_name: str = ""
    attrs: Mapping[str, Any] = {}


def table_format(path: str | os.PathLike, format: str | None = None) -> str:
    """Format name (a key of :data:`TABLE_FORMATS`) from ``format`` or the suffix of ``path``.

    Examples
    --------
    >>> table_format("run.MF4"), table_format("x.dat", "netcdf")
    ('mf4', 'nc')
    """
    if format is not None:
        if not isinstance(format, str):
            raise OutputError(
                f"{path}: format must be a str, one of {list(TABLE_FORMATS)}, got a "
                f"{type(format).__name__} ({format!r})"
            )
        name = format.lower().lstrip(".")
        name = _ALIASES.get(name, name)
        if name not in TABLE_FORMATS:
            hint = did_you_mean(name, [*TABLE_FORMATS, *_ALIASES])
            raise OutputError(
                f"{path}: unknown table format {format!r}{hint}; use {list(TABLE_FORMATS)}"
            )
        return name
    suffix = file_path(path).suffix.lower()
    for name, suffixes in TABLE_FORMATS.items():
        if suffix in suffixes:
            return name
    known = [s for ss in TABLE_FORMATS.values() for s in ss]
    raise OutputError(f"{path}: unknown results format {suffix!r}; use one of {known}")


def _require(module: str, what: str):
    return require(module, purpose=f"writing {what}")


# --------------------------------------------------------------------------- checks


def _columns(
    path: Path, columns: Mapping[str, Any], time: Any
) -> tuple[dict[str, TableColumn], int]:
    """Columns as :class:`TableColumn` (time first), checked: one length, units, NaN policy."""
    cols: dict[str, TableColumn] = {}
    if not isinstance(columns, Mapping):
        raise ParameterError(
            f"{path}: columns must be a mapping of name -> (values, unit[, long_name[, attrs]]), "
            f"got a {type(columns).__name__}"
        )
    if time is not None:
        cols["time"] = TableColumn(_time_values(path, time), "s", "time")
    for name, spec in columns.items():
        if not isinstance(name, str):
            raise ParameterError(
                f"{path}: column names must be str, got {name!r} ({type(name).__name__})"
            )
        if name in cols:
            raise ParameterError(f"{path}: column {name!r} given twice (time is written as 'time')")
        col = _column_spec(path, name, spec)
        values = np.asarray(col.values)
        if values.ndim != 1:
            raise ParameterError(
                f"{path}: column {name!r} has shape {values.shape}; columns are 1-D"
            )
        values = _column_values(path, name, values, col.unit)
        text = values.dtype.kind in "US"
        attrs = dict(col.attrs)
        if not text:
            values = values.astype(float, copy=False)
            _check_numeric(path, name, values, {**attrs, "units": col.unit})
            if attrs.get(NAN_MEANING):
                attrs[NAN_SAMPLES] = int(np.count_nonzero(~np.isfinite(values)))
        else:
            values = values.astype(str)
        unit = DIMENSIONLESS if is_dimensionless(col.unit) else col.unit
        cols[name] = TableColumn(values, None if text else unit, col.long_name, attrs)
    sizes = {c.values.size for c in cols.values()}
    if len(sizes) > 1:
        shown = {n: c.values.size for n, c in cols.items()}
        raise ParameterError(f"{path}: columns of different lengths {shown}")
    return cols, (sizes.pop() if sizes else 0)


def _time_values(path: Path, time: Any) -> np.ndarray:
    """The sample times [s] as a finite, non-decreasing 1-D float array (a NaN instant had been
    written as an empty CSV cell, a 2-D array had reached pandas' own error)."""
    values = np.asarray(time)
    if values.dtype.kind in "mMcUS":
        raise ParameterError(
            f"{path}: time must be numbers [s] (elapsed seconds), got an array of dtype "
            f"{values.dtype}"
        )
    try:
        return require_increasing("time", values, "s", strict=False)
    except ParameterError as exc:
        raise ParameterError(f"{path}: {exc}") from None


def _column_spec(path: Path, name: str, spec: Any) -> TableColumn:
    """``spec`` as a :class:`TableColumn`: a tuple (values, unit[, long_name[, attrs]]) or a
    mapping with those keys; anything else refused naming the column."""
    form = "(values, unit[, long_name[, attrs]]) or a mapping with those keys"
    try:
        if isinstance(spec, tuple):
            col = TableColumn(*spec)
        elif isinstance(spec, Mapping):
            unknown = [k for k in spec if k not in TableColumn._fields]
            if unknown:
                hint = did_you_mean(str(unknown[0]), TableColumn._fields)
                raise ParameterError(
                    f"{path}: column {name!r} has unknown key {unknown[0]!r}{hint}; "
                    f"the keys are {list(TableColumn._fields)}"
                )
            col = TableColumn(**spec)
        else:
            raise TypeError
    except TypeError:
        raise ParameterError(
            f"{path}: column {name!r} must be given as {form}, got {_short(spec)}"
        ) from None
    if col.unit is not None and not isinstance(col.unit, str):
        raise ParameterError(
            f'{path}: column {name!r} has unit {col.unit!r}; a unit is a str ("1" when '
            "dimensionless), None only for a label column of text"
        )
    if not isinstance(col.attrs, Mapping):
        raise ParameterError(
            f"{path}: column {name!r} has attrs {_short(col.attrs)}; attrs are a mapping"
        )
    return col


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:56] + " ..."


def _column_values(path: Path, name: str, values: np.ndarray, unit: str | None) -> np.ndarray:
    """Values of a column that the formats store as they are: numbers (a numeric column, one
    with a unit), or text (a label column, unit None). Complex numbers, dates and numbers held
    as Python objects with a unit are never written as something else (the imaginary part had
    been dropped, dates written as days under "s", ``[1.0, None]`` as the text "None")."""
    kind = values.dtype.kind
    if kind == "c":
        raise ParameterError(
            f"{path}: column {name!r} holds complex numbers; write the real and imaginary parts "
            "(or magnitude and phase) as two columns"
        )
    if kind in "mM":
        raise ParameterError(
            f"{path}: column {name!r} holds dates or durations ({values.dtype}); write them as "
            "numbers in a unit (seconds since a stated instant)"
        )
    if unit is None or kind not in "USO":
        return values
    if kind in "US":
        raise ParameterError(
            f"{path}: column {name!r} holds text but has unit {unit!r}; a column of text is a "
            "label column (unit None), a numeric column holds numbers"
        )
    try:
        return values.astype(float)
    except (TypeError, ValueError, OverflowError):
        bad = next((v for v in values if not _is_number(v)), values[0])
        raise ParameterError(
            f"{path}: column {name!r} has unit {unit!r} but holds {bad!r}, not a number"
        ) from None


def _is_number(value: Any) -> bool:
    try:
        float(value)
    except (TypeError, ValueError, OverflowError):
        return False
    return True


def _check_numeric(path: Path, name: str, values: np.ndarray, attrs: Mapping) -> None:
    """Units on every numeric column; NaN/inf only with a ``nan_meaning`` (the NaN policy)."""
    if not attrs.get("units"):
        raise ParameterError(
            f"{path}: column {name!r} has no unit; every numeric column has one "
            '("1" when dimensionless)'
        )
    bad = ~np.isfinite(values)
    if bad.any() and not attrs.get("nan_meaning"):
        k = int(np.flatnonzero(bad.reshape(-1))[0])
        raise ParameterError(
            f"{path}: column {name!r} has {int(bad.sum())} NaN/inf samples (first at sample "
            f"{k}) and no 'nan_meaning' attribute saying why; state it or replace them"
        )


def _variables(cols: Mapping[str, TableColumn]) -> dict[str, dict[str, Any]]:
    out = {}
    for name, c in cols.items():
        entry: dict[str, Any] = {"units": c.unit} if c.unit else {}
        if c.long_name:
            entry["long_name"] = c.long_name
        entry.update({k: v for k, v in c.attrs.items() if k not in ("units", "long_name")})
        out[name] = entry
    return out


def _numeric(cols: Mapping[str, TableColumn], path: Path, fmt: str) -> None:
    text = [n for n, c in cols.items() if c.unit is None]
    if text:
        raise ParameterError(f"{path}: {fmt} files hold numbers only; text columns {text}")


def _uniform_step(time: np.ndarray) -> float | None:
    if time.size < 2:
        return None
    dt = np.diff(time)
    step = float(np.median(dt))
    return step if np.allclose(dt, step, rtol=1e-9, atol=1e-12 * max(1.0, step)) else None


# --------------------------------------------------------------------------- formats


def _csv(cols, meta, tmp: Path) -> None:
    """Numbers rounded to :data:`SIGNIFICANT_DIGITS` digits, except in a column that rounding
    would blur, written exactly (:func:`rollerrig.output.csv_numbers.csv_text`)."""
    import pandas as pd

    data = {}
    for n, c in cols.items():
        values = c.values
        if c.unit is not None and np.asarray(values).dtype.kind == "f":
            values = csv_text(values)
        data[labelled(n, c.unit)] = values
    pd.DataFrame(data).to_csv(tmp, index=False, float_format=csv_number)


def _parquet(cols, meta, tmp: Path) -> None:
    pa = _require("pyarrow", "Parquet files")
    import pyarrow.parquet as pq

    fields, arrays = [], []
    for name, c in cols.items():
        fmeta = {"long_name": c.long_name} if c.long_name else {}
        if c.unit:
            fmeta["unit"] = c.unit
        fmeta.update(_nan_note(c))
        kind = pa.string() if c.unit is None else pa.float64()
        fields.append(pa.field(name, kind, metadata=fmeta or None))
        arrays.append(pa.array(c.values.tolist() if c.unit is None else c.values, type=kind))
    units = {n: c.unit for n, c in cols.items() if c.unit}
    blob = json_text({"units": units, "metadata": meta})
    schema = pa.schema(fields, metadata={"rollerrig": blob})
    pq.write_table(pa.Table.from_arrays(arrays, schema=schema), tmp)


def _nan_note(c: TableColumn) -> dict[str, str]:
    """``nan_meaning`` and ``nan_samples`` of a column as text (empty without a meaning)."""
    if not c.attrs.get(NAN_MEANING):
        return {}
    return {NAN_MEANING: str(c.attrs[NAN_MEANING]), NAN_SAMPLES: str(c.attrs.get(NAN_SAMPLES, 0))}


def _mf4_comment(c: TableColumn) -> str:
    """An MDF4 signal comment: the long name, and why the signal may hold NaN."""
    note = _nan_note(c)
    if not note:
        return c.long_name
    why = f"NaN in {note[NAN_SAMPLES]} samples: {note[NAN_MEANING]}"
    return f"{c.long_name}; {why}" if c.long_name else why


def _tdms(cols, meta, tmp: Path, stem: str) -> None:
    nptdms = _require("nptdms", "TDMS files")
    time = cols["time"].values if "time" in cols else None
    step = None if time is None else _uniform_step(time)
    objects = [
        nptdms.RootObject(properties={META_KEY: json_text(meta), "name": stem}),
        nptdms.GroupObject("rollerrig"),
    ]
    for name, c in cols.items():
        props: dict[str, Any] = {"unit_string": c.unit}
        if c.long_name:
            props["description"] = c.long_name
        props.update(_nan_note(c))
        if step is not None and name != "time":
            props.update(
                wf_increment=step, wf_start_offset=float(time[0]), wf_samples=int(time.size)
            )
        objects.append(nptdms.ChannelObject("rollerrig", name, c.values, properties=props))
    with nptdms.TdmsWriter(str(tmp)) as writer:
        writer.write_segment(objects)


def _mf4(cols, meta, tmp: Path) -> Path:
    asammdf = _require("asammdf", "MDF4 files")
    time = cols["time"].values
    mdf = asammdf.MDF(version="4.10")
    try:
        signals = [
            asammdf.Signal(c.values, time, name=n, unit=c.unit, comment=_mf4_comment(c))
            for n, c in cols.items()
            if n != "time"
        ]
        if signals:
            mdf.append(signals, comment="rollerrig")
        mdf.header.comment = json_text(meta)
        saved = mdf.save(str(tmp), overwrite=True)
    finally:
        mdf.close()
    return Path(saved)


def _stored_names(cols: dict[str, TableColumn], fmt: str) -> dict[str, TableColumn]:
    """The columns under names ``fmt`` can store (:func:`~rollerrig.output.varnames.
    storable_names`); a renamed column keeps the name it was given as ``original_name``."""
    reserved = {"mat": _MAT_RESERVED, "nc": ("time", "index")}.get(fmt, ())
    given = [n for n in cols if n != "time"]
    stored = storable_names(given, fmt, reserved=reserved)
    out = {"time": cols["time"]} if "time" in cols else {}
    for name in given:
        c = cols[name]
        if stored[name] != name:
            c = c._replace(attrs={**c.attrs, ORIGINAL_NAME: name})
        out[stored[name]] = c
    return out


def _mat5(cols, meta, tmp: Path) -> None:
    from scipy.io import savemat

    data: dict[str, Any] = {}
    for name, c in cols.items():
        if c.unit is None:  # text: a cell column
            cells = np.empty((c.values.size, 1), dtype=object)
            cells[:, 0] = list(c.values)
            data[name] = cells
        else:
            data[name] = c.values.reshape(-1, 1)
    data[UNITS_STRUCT] = {n: c.unit for n, c in cols.items() if c.unit}
    data[PROVENANCE_KEY] = json_text(meta[PROVENANCE_KEY])
    data[META_KEY] = json_text({k: v for k, v in meta.items() if k != PROVENANCE_KEY})
    with tmp.open("wb") as fh:
        savemat(fh, data, format="5", do_compression=True, oned_as="column")


def _mat73(cols, meta, tmp: Path) -> None:
    """MATLAB 7.3: HDF5 with a 512-byte user block holding the MAT header."""
    h5py = _require("h5py", "MATLAB v7.3 files")

    def double(parent, name: str, values: np.ndarray) -> None:
        # MATLAB is column-major: an n x 1 column vector is stored with HDF5 shape (1, n).
        ds = parent.create_dataset(name, data=np.asarray(values, dtype=float).reshape(1, -1))
        ds.attrs["MATLAB_class"] = np.bytes_("double")

    def char(parent, name: str, text: str) -> None:
        codes = np.frombuffer(text.encode("utf-16-le"), dtype=np.uint16).reshape(-1, 1)
        ds = parent.create_dataset(name, data=codes)
        ds.attrs["MATLAB_class"] = np.bytes_("char")
        ds.attrs["MATLAB_int_decode"] = np.int32(2)

    with h5py.File(tmp, "w", userblock_size=512, libver="earliest") as f:
        for name, c in cols.items():
            double(f, name, c.values)
        units = f.create_group(UNITS_STRUCT)
        units.attrs["MATLAB_class"] = np.bytes_("struct")
        names = [n for n, c in cols.items() if c.unit]
        vlen = h5py.vlen_dtype(np.dtype("S1"))
        fields = np.empty(len(names), dtype=object)
        for i, n in enumerate(names):
            fields[i] = np.array(list(n), dtype="S1")
            char(units, n, cols[n].unit)
        units.attrs.create("MATLAB_fields", fields, dtype=vlen)
        char(f, PROVENANCE_KEY, json_text(meta[PROVENANCE_KEY]))
        char(f, META_KEY, json_text({k: v for k, v in meta.items() if k != PROVENANCE_KEY}))
    stamp = _dt.datetime.now(_dt.UTC).strftime("%a %b %d %H:%M:%S %Y")
    text = f"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: {stamp} HDF5 schema 1.00 ."
    header = text.encode("ascii").ljust(116, b" ") + b" " * 8 + b"\x00\x02" + b"IM"
    with tmp.open("r+b") as fh:
        fh.write(header.ljust(512, b"\x00"))


def _nc(cols, meta, tmp: Path, title: str) -> None:
    """Columns as a NetCDF file (one dimension, ``time`` when given), written without xarray."""

    def var_attrs(c: TableColumn) -> dict[str, Any]:
        a: dict[str, Any] = {"units": c.unit} if c.unit else {}
        if c.long_name:
            a["long_name"] = c.long_name
        return {**a, **{k: v for k, v in c.attrs.items() if k not in a}}

    dim = "time" if "time" in cols else "index"
    variables = {
        n: _netcdf.NcVariable((dim,), c.values, var_attrs(c))
        for n, c in cols.items()
        if n != "time"
    }
    if "time" in cols:  # xarray's order: data variables, then the coordinate
        variables["time"] = _netcdf.NcVariable(
            ("time",), cols["time"].values, dict(_netcdf.TIME_ATTRS)
        )
    _netcdf.write_netcdf(tmp, *_netcdf.cf_attributes(variables, meta, title))


def write_dataset(
    path: str | os.PathLike,
    ds: Any,
    *,
    format: str | None = None,
    provenance: Mapping[str, Any] | None = None,
    overwrite: bool = False,
    mat_version: Literal["5", "7.3"] = "5",
) -> Path:
    """Write an :class:`xarray.Dataset` whose variables carry ``units`` and ``long_name``.

    NetCDF keeps every dimension (CF-1.10 attributes added as in :func:`write_table`); the
    other formats take variables along ``time`` alone (as :func:`write_table` columns). The
    dataset's attributes are the file's metadata; its ``provenance`` attribute (JSON text or a
    dict) is the record unless ``provenance`` is given, a new record when it has none.

    Raises
    ------
    ParameterError
        A numeric variable without ``units``, NaN/inf without ``nan_meaning``, or (not NetCDF)
        a variable not along ``time`` alone.
    FileExistsError, OutputError
        As :func:`write_table`.

    Examples
    --------
    >>> import tempfile, pathlib, xarray as xr
    >>> ds = xr.Dataset({"f": (("time", "line"), np.ones((3, 2)), {"units": "Hz"})},
    ...                 coords={"time": [0.0, 0.1, 0.2]})
    >>> p = write_dataset(pathlib.Path(tempfile.mkdtemp()) / "x.nc", ds)
    >>> with xr.open_dataset(p, engine="h5netcdf") as back:
    ...     back.attrs["Conventions"], back["f"].attrs["long_name"], back["time"].attrs["units"]
    ('CF-1.10', 'f', 's')
    """
    from rollerrig.output.labelled import LabelledData

    path = file_path(path)
    fmt = table_format(path, format)
    if not isinstance(ds, LabelledData) and not all(
        hasattr(ds, a) for a in ("data_vars", "coords", "attrs", "variables")
    ):
        raise ParameterError(
            f"{path}: ds must be an xarray Dataset or a LabelledData, got a {type(ds).__name__}"
        )
    _require_mapping(path, "provenance", provenance)
    source = None if isinstance(ds, LabelledData) else ds
    data = ds if source is None else LabelledData.from_xarray(ds)
    record = provenance if provenance is not None else data.attrs.get(PROVENANCE_KEY)
    if isinstance(record, str):
        try:
            record = json.loads(record)
        except json.JSONDecodeError as exc:
            raise ParameterError(
                f"{path}: the dataset's provenance attribute is not JSON ({exc}); pass "
                "provenance= or remove the attribute"
            ) from None
    _require_mapping(path, "the dataset's provenance attribute", record)
    attrs = {k: v for k, v in data.attrs.items() if k != PROVENANCE_KEY}
    if fmt != "nc":
        columns = {}
        for name, var in data.data_vars.items():
            if var.dims != ("time",):
                raise ParameterError(
                    f"{path}: variable {name!r} has dimensions {var.dims}; {fmt} files hold "
                    "columns along time only (write NetCDF)"
                )
            a = dict(var.attrs)
            columns[str(name)] = (var.values, a.pop("units", None), a.pop("long_name", ""), a)
        return write_table(
            path,
            columns,
            format=fmt,
            time=data["time"].values if "time" in data.coords else None,
            provenance=record,
            attrs=attrs,
            overwrite=overwrite,
            mat_version=mat_version,
        )
    variables = {n: v._replace(attrs=dict(v.attrs)) for n, v in data.variables.items()}
    for var in variables.values():
        if is_dimensionless(var.attrs.get("units")):
            var.attrs["units"] = DIMENSIONLESS
    if "time" in data.coords and data["time"].dims == ("time",):
        _time_values(path, data["time"].values)
    for name, var in data.data_vars.items():
        if var.dtype.kind in "biuf":
            values = np.asarray(var.values, dtype=float)
            attrs_of = variables[name].attrs
            _check_numeric(path, str(name), values, attrs_of)
            if attrs_of.get(NAN_MEANING):
                attrs_of[NAN_SAMPLES] = int(np.count_nonzero(~np.isfinite(values)))
    taken = [str(n) for n in (*data.coords, *data.sizes)]
    stored = storable_names(list(data.data_vars), "nc", reserved=taken)
    renamed = {n: s for n, s in stored.items() if s != n}
    for name in renamed:
        variables[name].attrs[ORIGINAL_NAME] = name
    data = LabelledData.from_variables(
        {renamed.get(n, n): v for n, v in variables.items()}, data.coords, data.attrs
    )
    if source is not None:  # xarray's own encoders may be needed: its names as written
        source = source.copy(deep=False).rename(renamed)
    meta = {**attrs, PROVENANCE_KEY: dict(record) if record is not None else _provenance()}
    return atomic_write(
        path,
        lambda tmp: _netcdf.write_cf_netcdf(data, meta, tmp, path.stem, source),
        overwrite=overwrite,
    )


# --------------------------------------------------------------------------- the writer


def _require_mapping(path: Path, name: str, value: Any) -> None:
    if value is not None and not isinstance(value, Mapping):
        raise ParameterError(
            f"{path}: {name} must be a mapping (dict) or None, got a {type(value).__name__}"
        )


def write_table(
    path: str | os.PathLike,
    columns: Mapping[str, Any],
    *,
    format: str | None = None,
    time: Any = None,
    provenance: Mapping[str, Any] | None = None,
    attrs: Mapping[str, Any] | None = None,
    overwrite: bool = False,
    mat_version: Literal["5", "7.3"] = "5",
) -> Path:
    """Write named columns with units to ``path`` atomically, in the format of its suffix.

    Parameters
    ----------
    path : str or path-like
        Target file (``.csv``, ``.parquet``, ``.tdms``, ``.mf4``/``.mdf``, ``.mat``, ``.nc``).
    columns : mapping of name -> (values, unit[, long_name[, attrs]])
        1-D columns of one length; ``unit`` is required for numbers (``"1"`` when
        dimensionless), None marks a label column of text (csv, parquet, nc, mat v5 only).
        ``attrs`` may hold ``nan_meaning``: without it NaN/inf samples are refused.
    format : str, optional
        Overrides the suffix (a key of :data:`TABLE_FORMATS`).
    time : array_like, optional
        Sample times [s], written first as column ``time`` (needed by mf4).
    provenance : mapping, optional
        The provenance record; default :func:`rollerrig.output.provenance` (run context). A
        ``"provenance"`` entry of ``attrs`` is used when given.
    attrs : mapping, optional
        The file's metadata (JSON-able): a recording's ``metadata``, a dataset's attributes.
    overwrite : bool
        Replace an existing file (and the CSV sidecar); default False: refuse.
    mat_version : {"5", "7.3"}
        MAT-file version.

    Returns
    -------
    Path
        The written file.

    Notes
    -----
    A CSV file and its sidecar are written as a pair (:func:`~rollerrig.output.atomic.
    atomic_write_all`): both in full before either replaces a file, and the table put back when
    the sidecar cannot replace its own. When this function raises, the pair is as it was (both
    old, or neither there); when it returns, both are new. Only for the instant between the two
    moves could a reader see the new table beside the old sidecar.

    Raises
    ------
    FileExistsError
        The file (or CSV sidecar) exists and ``overwrite`` is False.
    ParameterError
        A column without a unit, NaN without ``nan_meaning``, columns of different lengths, a
        column type the format cannot store. (Names are not refused: where the format cannot
        store a name, NetCDF and MAT, the column is written under
        :func:`~rollerrig.output.varnames.storable_names` with the name given as its
        ``original_name`` attribute, in the ``variables`` entry of the metadata as well.)
    OutputError
        Unknown format, or the file cannot be written (the message names the path).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> out = write_table(d / "run.csv", {"torque": ([1.0, 2.0], "N.m", "shaft torque")},
    ...                   time=[0.0, 0.004])
    >>> out.read_text().splitlines()[0], sorted(p.name for p in d.iterdir())
    ('time [s],torque [N.m]', ['run.csv', 'run.metadata.json'])
    """
    path = file_path(path)
    fmt = table_format(path, format)
    _flag("overwrite", overwrite, path)  # before the work: "no" had meant replace
    if mat_version not in ("5", "7.3"):
        raise ParameterError(f"{path}: mat_version must be '5' or '7.3', got {mat_version!r}")
    _require_mapping(path, "attrs", attrs)
    _require_mapping(path, "provenance", provenance)
    cols, _ = _columns(path, columns, time)
    cols = _stored_names(cols, fmt)
    meta: dict[str, Any] = dict(attrs or {})
    if PROVENANCE_KEY not in meta:
        meta[PROVENANCE_KEY] = dict(provenance) if provenance is not None else _provenance()
    meta[VARIABLES_KEY] = _variables(cols)
    if not overwrite and os.path.lexists(path):
        raise FileExistsError(f"{path} exists; pass overwrite=True to replace it")

    if fmt == "csv":
        sidecar = path.with_suffix(".metadata.json")
        if not overwrite and os.path.lexists(sidecar):
            raise FileExistsError(f"{sidecar} exists; pass overwrite=True to replace it")
        # The table and its sidecar as a pair: both written in full before either is moved,
        # and the table put back when the sidecar's move fails (atomic_write_all), so that a
        # failure never leaves a new table beside an old sidecar (or none).
        text = json_text(meta, indent=2) + "\n"
        atomic_write_all(
            [
                (path, lambda tmp: _csv(cols, meta, tmp)),
                (sidecar, lambda tmp: tmp.write_text(text, encoding="utf-8")),
            ],
            overwrite=overwrite,
        )
        return path
    if fmt == "parquet":
        return atomic_write(path, lambda tmp: _parquet(cols, meta, tmp), overwrite=overwrite)
    if fmt == "tdms":
        _numeric(cols, path, "TDMS")
        return atomic_write(
            path, lambda tmp: _tdms(cols, meta, tmp, path.stem), overwrite=overwrite
        )
    if fmt == "mf4":
        _numeric(cols, path, "MDF4")
        if "time" not in cols:
            raise ParameterError(f"{path}: MDF4 signals need a time base; pass time=")
        if path.suffix.lower() not in (".mf4", ".mdf"):
            raise OutputError(f"{path}: MDF4 files must end in .mf4 (asammdf sets the suffix)")
        return atomic_write(path, lambda tmp: _mf4(cols, meta, tmp), overwrite=overwrite)
    if fmt == "mat":
        if mat_version == "7.3":
            _numeric(cols, path, "MATLAB v7.3")
            return atomic_write(path, lambda tmp: _mat73(cols, meta, tmp), overwrite=overwrite)
        return atomic_write(path, lambda tmp: _mat5(cols, meta, tmp), overwrite=overwrite)
    return atomic_write(path, lambda tmp: _nc(cols, meta, tmp, path.stem), overwrite=overwrite)
